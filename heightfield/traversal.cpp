#include "heightfield/traversal.h"

#include "heightfield/cell_intersectors.h"
#include "heightfield/dda.h"

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

namespace terracast {

namespace {

struct MethodName {
    CellMethod method;
    const char* name;
};
constexpr std::array<MethodName, 5> kMethodNames{{
    {CellMethod::Bilinear, "bilinear"},
    {CellMethod::BilinearDouble, "bilinear-double"},
    {CellMethod::Triangles, "triangles"},
    {CellMethod::Nearest, "nearest"},
    {CellMethod::Reference, "reference"},
}};

enum class Shape { Bilinear, Triangles, Nearest };

// The arithmetic that surface heights are evaluated in before rounding to Real: at least double.
template <class Real>
using Wide = std::conditional_t<(sizeof(Real) > sizeof(double)), Real, double>;

// The corners of cell (i, j) relative to `baseM`. Cell math runs on heights relative to the cell's own
// h00, so float rounding scales with the cell's relief, not with its altitude (8000 m peaks keep
// millimetres). The differences are taken in Wide arithmetic, where they are exact, then rounded once.
template <class Real>
CellCorners<Real> corners(const HeightGrid& g, int64_t i, int64_t j, Wide<Real> baseM) {
    using W = Wide<Real>;
    return {Real(W(g.at(i, j)) - baseM), Real(W(g.at(i + 1, j)) - baseM), Real(W(g.at(i, j + 1)) - baseM),
            Real(W(g.at(i + 1, j + 1)) - baseM)};
}

// Surface height minus ray height at a point on the boundary `side` of cell (i, j), or inside the cell,
// evaluated in Wide arithmetic and rounded once to Real. On an edge only that edge's two vertices are used,
// in a fixed order and independently of the cell's base height, so both cells sharing the edge compute the
// same bits (see cell_intersectors.h on watertightness).
template <class Real, Shape shape>
Real surfaceAboveRay(const HeightGrid& g, int64_t i, int64_t j, CellSide side, const glm::dvec3& pGrid) {
    using W = Wide<Real>;
    auto lerp = [](W a, W b, W w) { return (W(1) - w) * a + w * b; };
    auto frac = [](double x) { return std::clamp(W(x), W(0), W(1)); };
    auto h = [&](int64_t x, int64_t y) { return W(g.at(x, y)); };
    const W z = W(pGrid.z);
    switch (side) {
    case CellSide::XLow:
    case CellSide::XHigh: {
        const int64_t x = side == CellSide::XLow ? i : i + 1;
        return Real(lerp(h(x, j), h(x, j + 1), frac(pGrid.y - double(j))) - z);
    }
    case CellSide::YLow:
    case CellSide::YHigh: {
        const int64_t y = side == CellSide::YLow ? j : j + 1;
        return Real(lerp(h(i, y), h(i + 1, y), frac(pGrid.x - double(i))) - z);
    }
    case CellSide::Interior:
        break;
    }
    const W u = frac(pGrid.x - double(i));
    const W v = frac(pGrid.y - double(j));
    const W h00 = h(i, j), h10 = h(i + 1, j), h01 = h(i, j + 1), h11 = h(i + 1, j + 1);
    if constexpr (shape == Shape::Triangles) {
        if (inUpperTriangle(u, v)) return Real(h11 - (h11 - h01) * (W(1) - u) - (h11 - h10) * (W(1) - v) - z);
        return Real(h00 + (h10 - h00) * u + (h01 - h00) * v - z);
    }
    // Nested interpolation: exact at the corners and equal to the edge formula on the edges.
    return Real(lerp(lerp(h00, h10, u), lerp(h01, h11, u), v) - z);
}

// True when the bilinear G(s) = A s^2 + B s + C of a segment comes within `tolM` of zero without a clean
// crossing: for a segment without a hit, anywhere on it; for a segment with a hit, at G's extreme inside it
// (a tangent touch, or a dip shallower than the tolerance).
template <class Real>
bool grazes(const CellCorners<Real>& h, const CellSegment<Real>& seg, bool hit, double tolM) {
    const Real A = h.d() * seg.du * seg.dv;
    const Real B = h.b() * seg.du + h.c() * seg.dv + h.d() * (seg.u0 * seg.dv + seg.v0 * seg.du) - seg.dz;
    const Real C = seg.gEntry;
    auto G = [&](Real s) { return double(std::abs((A * s + B) * s + C)); };
    if (A != Real(0)) {
        const Real sv = -B / (Real(2) * A);
        if (sv > Real(0) && sv < seg.length && G(sv) < tolM) return true;
    }
    return !hit && std::min(G(Real(0)), G(seg.length)) < tolM;
}

template <class Real>
Real unitRoundoff() {
    return std::numeric_limits<Real>::epsilon();
}

template <class Real, Shape shape>
std::optional<HeightFieldHit> trace(const HeightGrid& g, const Ray& ray, Interval interval, bool anyHit,
                                    TraceCounters* counters, Traversal traversal) {
    if (interval.empty()) return std::nullopt;
    const glm::dvec3 og{ray.origin.x / g.cellSizeXM(), ray.origin.y / g.cellSizeYM(), ray.origin.z};
    const glm::dvec3 dg{ray.dir.x / g.cellSizeXM(), ray.dir.y / g.cellSizeYM(), ray.dir.z};
    if (dg.x == 0.0 && dg.y == 0.0 && dg.z == 0.0) return std::nullopt;
    if (!std::isfinite(og.x + og.y + og.z + dg.x + dg.y + dg.z)) return std::nullopt;

    // The z slab is padded so a flat grid (zmin == zmax) still yields a segment of non-zero length.
    const double zLo = g.minHeightM(), zHi = g.maxHeightM();
    const double zPad = 1e-6 * (1.0 + std::max(std::abs(zLo), std::abs(zHi)));
    double t0 = interval.lo, t1 = interval.hi;
    if (!clipToSlab(og.z, dg.z, zLo - zPad, zHi + zPad, t0, t1)) return std::nullopt;
    if (!std::isfinite(t0) || !std::isfinite(t1)) {
        // Only a horizontal ray with an unbounded interval gets here; bound it by the footprint.
        if (!clipToSlab(og.x, dg.x, 0.0, double(g.cellsX()), t0, t1)) return std::nullopt;
        if (!clipToSlab(og.y, dg.y, 0.0, double(g.cellsY()), t0, t1)) return std::nullopt;
        if (!std::isfinite(t0) || !std::isfinite(t1)) return std::nullopt;
    }

    const Real eps = unitRoundoff<Real>();
    const double heightScale = std::max(std::abs(zLo), std::abs(zHi));
    const double tolerance = grazingToleranceM(g);
    // A cell is skipped when the ray's z range over it clears the cell's height range by this margin,
    // which exceeds any rounding of the edge interpolation, so skipping never breaks watertightness.
    double margin = 8.0 * double(eps) * (heightScale + std::abs(og.z)) + 1e-30;
    if (counters) margin = std::max(margin, tolerance);

    std::optional<HeightFieldHit> result;
    // G at the exit of the last cell tested, while every cell walked since has had (almost) zero length. An exact
    // corner crossing visits a zero-length cell between two diagonal neighbours; when that cell is a hole,
    // this carries the chain of shared G values across the corner.
    std::optional<Real> cornerG;

    // The ray parameter where the ray leaves the largest pyramid block around cell (i, j) that it passes
    // above (by the margin) from tFrom on, or tFrom when it passes above none. Every cell of such a block
    // would be rejected by the per-cell test below, so skipping it changes no hit.
    const int levels = traversal == Traversal::Pyramid ? g.pyramidLevels() : 0;
    // Block exits divide exactly as walkCells does, so a walk restarted there sees the same boundary t.
    auto skipTo = [&](int64_t i, int64_t j, double tFrom) {
        const double zFrom = og.z + tFrom * dg.z;
        double best = tFrom;
        for (int k = 1; k <= levels; ++k) {
            const int64_t bi = i >> k, bj = j >> k;
            const double x0 = double(bi << k), x1 = double(std::min((bi + 1) << k, g.cellsX()));
            const double y0 = double(bj << k), y1 = double(std::min((bj + 1) << k, g.cellsY()));
            double tOut = t1;
            if (dg.x != 0.0) tOut = std::min(tOut, ((dg.x > 0.0 ? x1 : x0) - og.x) / dg.x);
            if (dg.y != 0.0) tOut = std::min(tOut, ((dg.y > 0.0 ? y1 : y0) - og.y) / dg.y);
            const double zLow = std::min(zFrom, og.z + tOut * dg.z);
            if (!(zLow > double(g.blockMaxM(k, bi, bj)) + margin)) break;
            best = tOut;
        }
        return best;
    };

    double tStart = t0, restartAt = 0.0;
    auto visitCell = [&](const CellVisit& c) {
        if (counters) ++counters->cellsVisited;
        // Try the pyramid only where the cell itself would be passed over: a cell the ray might touch cannot
        // lie in a block it passes above, so cells near the surface pay nothing for the pyramid.
        auto trySkip = [&]() {
            if (levels == 0 || !(c.tExit > c.tEnter)) return false;
            const double tSkip = skipTo(c.i, c.j, c.tEnter);
            if (!(tSkip > c.tExit)) return false;
            if (counters) ++counters->blocksSkipped;
            cornerG.reset();
            restartAt = tSkip;
            return true;
        };
        if (!g.cellValid(c.i, c.j)) {
            if (trySkip()) return true;
            // A corner pass: the segment clips the hole cell by less than 1e-7 of a cell (rounding of t).
            if ((c.tExit - c.tEnter) * (std::abs(dg.x) + std::abs(dg.y)) > 1e-7) cornerG.reset();
            return false;
        }
        const glm::dvec3 pEnter = og + c.tEnter * dg;
        const glm::dvec3 pExit = og + c.tExit * dg;
        const double h00 = g.at(c.i, c.j), h10 = g.at(c.i + 1, c.j), h01 = g.at(c.i, c.j + 1),
                     h11 = g.at(c.i + 1, c.j + 1);
        const double zMin = std::min(pEnter.z, pExit.z), zMax = std::max(pEnter.z, pExit.z);
        if (zMin > std::max(std::max(h00, h10), std::max(h01, h11)) + margin) {
            if (trySkip()) return true;
            cornerG.reset();
            return false;
        }
        // A segment wholly below the cell is skipped when looking for the first crossing; for occlusion the
        // terrain is solid, so such a segment is tested (and found blocked) below.
        if (!anyHit && zMax < std::min(std::min(h00, h10), std::min(h01, h11)) - margin) {
            cornerG.reset();
            return false;
        }
        const auto h = corners<Real>(g, c.i, c.j, Wide<Real>(h00));
        if (counters) ++counters->cellsTested;

        CellSegment<Real> seg;
        seg.u0 = std::clamp(Real(pEnter.x - double(c.i)), Real(0), Real(1));
        seg.v0 = std::clamp(Real(pEnter.y - double(c.j)), Real(0), Real(1));
        seg.z0 = Real(Wide<Real>(pEnter.z) - Wide<Real>(h00));
        seg.du = Real(dg.x);
        seg.dv = Real(dg.y);
        seg.dz = Real(dg.z);
        seg.length = Real(c.tExit - c.tEnter);
        seg.gEntry = surfaceAboveRay<Real, shape>(g, c.i, c.j, c.entry, pEnter);
        seg.gExit = surfaceAboveRay<Real, shape>(g, c.i, c.j, c.exit, pExit);

        std::optional<Real> s;
        if (anyHit && seg.gEntry > Real(0)) s = Real(0);  // under the solid terrain (entered from a hole or edge)
        else if (shape != Shape::Nearest && cornerG && (*cornerG < Real(0)) != (seg.gEntry < Real(0))) s = Real(0);
        else if constexpr (shape == Shape::Bilinear) s = intersectBilinearCell(h, seg);
        else if constexpr (shape == Shape::Triangles) s = intersectTrianglesCell(h, seg);
        else s = intersectNearestCell(h, seg);
        cornerG = seg.gExit;

        if constexpr (shape == Shape::Bilinear)
            if (counters && !counters->ambiguous) counters->ambiguous = grazes(h, seg, s.has_value(), tolerance);
        if (!s) return false;

        const double t = c.tEnter + double(*s);
        if (!interval.contains(t)) return false;

        HeightFieldHit hit;
        hit.t = t;
        hit.cellX = c.i;
        hit.cellY = c.j;
        const Real u = std::clamp(seg.u0 + *s * seg.du, Real(0), Real(1));
        const Real v = std::clamp(seg.v0 + *s * seg.dv, Real(0), Real(1));
        hit.u = double(u);
        hit.v = double(v);
        hit.pointM = ray.at(t);
        double dhdu = 0.0, dhdv = 0.0;
        if constexpr (shape == Shape::Bilinear) {
            dhdu = double(h.b() + h.d() * v);
            dhdv = double(h.c() + h.d() * u);
        } else if constexpr (shape == Shape::Triangles) {
            if (inUpperTriangle(u, v)) {
                dhdu = double(h.h11 - h.h01);
                dhdv = double(h.h11 - h.h10);
            } else {
                dhdu = double(h.h10 - h.h00);
                dhdv = double(h.h01 - h.h00);
            }
        }
        glm::dvec3 n{-dhdu / g.cellSizeXM(), -dhdv / g.cellSizeYM(), 1.0};
        if constexpr (shape == Shape::Nearest) {
            // A hit at the entry below the square's level is a wall hit.
            const Real level = Real(0.25) * ((h.h00 + h.h10) + (h.h01 + h.h11));
            if (*s == Real(0) && level - seg.z0 >= Real(0)) {
                switch (c.entry) {
                case CellSide::XLow: n = {-1, 0, 0}; break;
                case CellSide::XHigh: n = {1, 0, 0}; break;
                case CellSide::YLow: n = {0, -1, 0}; break;
                case CellSide::YHigh: n = {0, 1, 0}; break;
                case CellSide::Interior: break;
                }
            }
        }
        hit.normal = glm::normalize(n);
        const double magnitude = std::abs(hit.pointM.x) + std::abs(hit.pointM.y) + std::abs(hit.pointM.z);
        hit.errorM = 16.0 * double(eps) * (std::abs(hit.pointM.z) + heightScale + g.cellSizeXM() + g.cellSizeYM()) +
                     16.0 * std::numeric_limits<double>::epsilon() * magnitude;
        result = hit;
        return true;
    };
    // Walk, and after each pyramid skip walk again from where the skipped block ends.
    for (;;) {
        restartAt = kInfinity;
        walkCells(g.cellsX(), g.cellsY(), {og.x, og.y}, {dg.x, dg.y}, tStart, t1, visitCell);
        if (result || !(restartAt < t1) || !(restartAt > tStart)) break;
        tStart = restartAt;
    }
    return result;
}

std::optional<HeightFieldHit> dispatch(const HeightGrid& g, const Ray& ray, Interval interval, CellMethod method,
                                       bool anyHit, TraceCounters* counters, Traversal tr) {
    switch (method) {
    case CellMethod::Bilinear: return trace<float, Shape::Bilinear>(g, ray, interval, anyHit, counters, tr);
    case CellMethod::BilinearDouble: return trace<double, Shape::Bilinear>(g, ray, interval, anyHit, counters, tr);
    case CellMethod::Triangles: return trace<float, Shape::Triangles>(g, ray, interval, anyHit, counters, tr);
    case CellMethod::Nearest: return trace<float, Shape::Nearest>(g, ray, interval, anyHit, counters, tr);
    case CellMethod::Reference: return trace<long double, Shape::Bilinear>(g, ray, interval, anyHit, counters, tr);
    }
    return std::nullopt;
}

}  // namespace

std::optional<CellMethod> parseCellMethod(std::string_view name) {
    for (const auto& m : kMethodNames)
        if (name == m.name) return m.method;
    return std::nullopt;
}

const char* cellMethodName(CellMethod method) {
    for (const auto& m : kMethodNames)
        if (m.method == method) return m.name;
    return "?";
}

const std::vector<CellMethod>& allCellMethods() {
    static const std::vector<CellMethod> methods{CellMethod::Bilinear, CellMethod::BilinearDouble,
                                                 CellMethod::Triangles, CellMethod::Nearest, CellMethod::Reference};
    return methods;
}

std::optional<HeightFieldHit> intersect(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method,
                                        TraceCounters* counters, Traversal traversal) {
    return dispatch(grid, ray, interval, method, false, counters, traversal);
}

bool occluded(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method, TraceCounters* counters,
              Traversal traversal) {
    return dispatch(grid, ray, interval, method, true, counters, traversal).has_value();
}

glm::dvec3 spawnOrigin(const HeightFieldHit& hit, const glm::dvec3& dir) {
    const double side = glm::dot(hit.normal, dir) >= 0.0 ? 1.0 : -1.0;
    return hit.pointM + side * hit.errorM * hit.normal;
}

double grazingToleranceM(const HeightGrid& grid) {
    const double scale = std::max({std::abs(double(grid.minHeightM())), std::abs(double(grid.maxHeightM())),
                                   grid.cellSizeXM(), grid.cellSizeYM()});
    return 8.0 * double(std::numeric_limits<float>::epsilon()) * scale;
}

}  // namespace terracast
