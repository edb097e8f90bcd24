// The traversal kernels: the walk and its cell visits (the height accessors it reads through are in
// height_accessors.h; the bundle proof, built on them, is in bundle_kernels.h).
// Not a header of its own: kernel_isas.h includes this file twice, inside two namespaces, once compiled for
// baseline x86-64 and once with AVX2 enabled (see the comment there), for traversal.cpp and traversal_tiled.cpp.
// It therefore includes nothing and holds no pragma once; everything it uses comes from their includes.

enum class Shape { Bilinear, Triangles, Nearest };

// The arithmetic that surface heights are evaluated in before rounding to Real: at least double.
template <class Real>
using Wide = std::conditional_t<(sizeof(Real) > sizeof(double)), Real, double>;

// The corners of a cell (as read, exact in double) relative to its own h00. Cell math runs on heights relative
// to the cell's h00, so float rounding scales with the cell's relief, not with its altitude (8000 m peaks keep
// millimetres). The differences are taken in Wide arithmetic, where they are exact, then rounded once.
template <class Real>
CellCorners<Real> corners(double h00, double h10, double h01, double h11) {
    using W = Wide<Real>;
    const W base = W(h00);
    return {Real(W(h00) - base), Real(W(h10) - base), Real(W(h01) - base), Real(W(h11) - base)};
}

// Surface height minus ray height at a point on the boundary `side` of cell (i, j), or inside the cell,
// evaluated in Wide arithmetic and rounded once to Real. On an edge only that edge's two vertices are used,
// in a fixed order and independently of the cell's base height, so both cells sharing the edge compute the
// same bits (see cell_intersectors.h on watertightness).
template <class Real, Shape shape, class Heights>
TERRACAST_CELL_INLINE Real surfaceAboveRay(const Heights& at, int64_t i, int64_t j, CellSide side,
                                           const glm::dvec3& pGrid) {
    using W = Wide<Real>;
    auto lerp = [](W a, W b, W w) { return (W(1) - w) * a + w * b; };
    auto frac = [](double x) { return std::clamp(W(x), W(0), W(1)); };
    auto h = [&](int64_t x, int64_t y) { return W(at(x, y)); };
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

// The margin by which a ray must clear a cell's highest corner for the walk to pass the cell without testing
// it, for cell arithmetic with unit roundoff `eps`: it exceeds any rounding of the edge interpolation, so
// skipping never breaks watertightness. Counting traces widen it to the grazing tolerance.
double cellSkipMargin(double eps, double heightScale, double originZ) {
    return 8.0 * eps * (heightScale + std::abs(originZ)) + 1e-30;
}

// The padding of the z slab a ray is clipped to, so that a flat grid (lowest height = highest) still gives a
// segment of non-zero length.
double zSlabPadM(const HeightGrid& g) {
    return 1e-6 * (1.0 + std::max(std::abs(g.minHeightM()), std::abs(g.maxHeightM())));
}

// What visiting one cell found: passed over it, ran wholly below it (looking for the first crossing), tested it
// without a hit, or hit it.
enum class Visit { Passed, Below, Tested, Hit };

// The walk of one ray through the grid. `start` clips the ray and places the walk in its first cell (false when
// there is nothing to walk); each `step` then tests one block or visits one cell (false once the walk has
// ended); `result` tells whether the ray met the surface. See `trace`, which runs it, for the parameters.
template <class Real, Shape shape, class Heights, int zSign, bool counting>
struct Walk {
    const HeightGrid& g;
    const Heights& at;
    const Ray& ray;
    Interval interval;
    bool anyHit;
    TraceCounters* counters;  // null without `counting`; each use tests `counting` first, so that it folds away
    HeightFieldHit* out;
    bool result = false;

    // The ray in grid units (x and y in cells, z in metres), its reciprocals and the clipped parameter range.
    glm::dvec3 og{}, dg{};
    bool movesX = false, movesY = false, movesZ = false;
    double invX = 0.0, invY = 0.0, invZ = 0.0;
    double t0 = 0.0, t1 = 0.0;
    Real eps = Real(0);
    double heightScale = 0.0, tolerance = 0.0, margin = 0.0;
    int64_t cellsX = 0, cellsY = 0;

    // G at the exit of the last cell tested, while every cell walked since has had (almost) zero length. An exact
    // corner crossing visits a zero-length cell between two diagonal neighbours; when that cell is a hole,
    // this carries the chain of shared G values across the corner.
    std::optional<Real> cornerG;
    // G on the boundary just crossed, when the cell before it was tested: the next cell's gEntry, bit for bit
    // (both are evaluated from that edge's two vertices at the same t), so it is not evaluated twice.
    Real carriedG = Real(0);
    bool hasCarriedG = false;

    // The pyramid and the ray's heights in its codes (see start).
    int levels = 0;
    HeightGrid::PyramidView pyramid{};
    double codeZ0 = 0.0, codeZ0High = 0.0, codeDz = 0.0;
    // The sign of the vertical direction: fixed by the instantiation, or read from the ray (zSign == 2).
    bool descending = false, rising = false;
    bool posX = false, posY = false;
    double tAtX0 = 0.0, tAtY0 = 0.0;
    int64_t exitOffX = 0, exitOffY = 0, stepX = 0, stepY = 0;

    // Where the walk stands: the cell, the side it entered through, the parameter it entered at, the pyramid
    // level (0 at the cells), and whether the last cell visited lay wholly above the ray (when looking for the
    // first crossing).
    int64_t i = 0, j = 0;
    // For a ray that runs along a grid line x = const (y = const), within 1e-9 of a cell: the column (row) on the
    // line's other side, whose cells share the line's edges with the walk's; -1 otherwise. Where the walk's cell
    // is a hole, that edge still belongs to the valid cell beside it.
    int64_t altI = -1, altJ = -1;
    CellSide entry = CellSide::Interior;
    double t = 0.0;
    int level = 0;
    bool under = false;

    Walk(const HeightGrid& grid, const Heights& heights, const Ray& r, Interval range, bool anyHitQuery,
         TraceCounters* tallies, HeightFieldHit* hitOut)
        : g(grid), at(heights), ray(r), interval(range), anyHit(anyHitQuery), counters(counting ? tallies : nullptr),
          out(hitOut) {}

    // The parameter of the boundary x = const is (x - og.x) / dg.x, taken as x / dg.x - og.x / dg.x with the
    // reciprocal; for a ray parallel to the boundaries the reciprocal is 0 and the constant +infinity, so every
    // boundary lies at +infinity.
    double tAtX(int64_t x) const { return double(x) * invX + tAtX0; }
    double tAtY(int64_t y) const { return double(y) * invY + tAtY0; }
    // The ray parameter where the walk leaves column c (row c) in its direction of travel.
    double exitX(int64_t c) const { return tAtX(c + exitOffX); }
    double exitY(int64_t c) const { return tAtY(c + exitOffY); }

    // Clips [ta, tb] to the slab lo <= o + t d <= hi, with the direction's reciprocal.
    static bool clip(double o, bool moves, double invD, double lo, double hi, double& ta, double& tb) {
        if (!moves) return lo <= o && o <= hi;
        const double tl = (lo - o) * invD, th = (hi - o) * invD;
        ta = std::max(ta, std::min(tl, th));
        tb = std::min(tb, std::max(tl, th));
        return ta <= tb;
    }

    bool start(Traversal traversal, double freeUntil) {
        if (interval.empty()) return false;
        og = {ray.origin.x * g.cellsPerMetreX(), ray.origin.y * g.cellsPerMetreY(), ray.origin.z};
        dg = {ray.dir.x * g.cellsPerMetreX(), ray.dir.y * g.cellsPerMetreY(), ray.dir.z};
        // A zero direction (or a NaN in it) fails the first test; an infinite or NaN coordinate, or magnitudes
        // near the largest double whose sum overflows, the second.
        const double dirSize = std::abs(dg.x) + std::abs(dg.y) + std::abs(dg.z);
        if (!(dirSize > 0.0) || !std::isfinite(og.x + og.y + og.z + dirSize)) return false;
        // The direction's reciprocals, 0 along an axis the ray does not move along. A component so small that its
        // reciprocal, or the product of the reciprocal with a coordinate the walk may meet (up to twice the
        // grid's extent, for the edges of the last pyramid blocks), would overflow counts as not moving too:
        // crossing one cell would take such a ray a parameter above DBL_MAX / (|o| + 2 cells + 2), and a
        // boundary parameter formed from it could be inf - inf.
        const glm::dvec3 inv = 1.0 / dg;
        auto moves = [](double invD, double o, double cells) {
            return std::isfinite((std::abs(o) + 2.0 * cells + 2.0) * invD);
        };
        movesX = moves(inv.x, og.x, double(g.cellsX()));
        movesY = moves(inv.y, og.y, double(g.cellsY()));
        movesZ = std::isfinite(inv.z);
        invX = movesX ? inv.x : 0.0;
        invY = movesY ? inv.y : 0.0;
        invZ = movesZ ? inv.z : 0.0;

        // The z slab, padded (see zSlabPadM).
        const double zLo = g.minHeightM(), zHi = g.maxHeightM();
        const double zPad = zSlabPadM(g);
        t0 = interval.lo;
        t1 = interval.hi;
        if (!clip(og.z, movesZ, invZ, zLo - zPad, zHi + zPad, t0, t1)) return false;
        if (!std::isfinite(t0) || !std::isfinite(t1)) {
            // Only a horizontal ray with an unbounded interval gets here; bound it by the footprint.
            if (!clip(og.x, movesX, invX, 0.0, double(g.cellsX()), t0, t1)) return false;
            if (!clip(og.y, movesY, invY, 0.0, double(g.cellsY()), t0, t1)) return false;
            if (!std::isfinite(t0) || !std::isfinite(t1)) return false;
        }

        eps = unitRoundoff<Real>();
        heightScale = std::max(std::abs(zLo), std::abs(zHi));
        tolerance = grazingToleranceM(g);
        // A cell is skipped when the ray's z range over it clears the cell's height range by this margin.
        margin = cellSkipMargin(double(eps), heightScale, og.z);
        if (counting && counters) margin = std::max(margin, tolerance);

        cellsX = g.cellsX();
        cellsY = g.cellsY();
        if (!clip(og.x, movesX, invX, 0.0, double(cellsX), t0, t1)) return false;
        if (!clip(og.y, movesY, invY, 0.0, double(cellsY), t0, t1)) return false;

        levels = traversal == Traversal::Pyramid ? g.pyramidLevels() : 0;
        pyramid = g.pyramidView();
        // The block test runs in code space: a block is passed when its code lies below the ray's lowest height
        // over it, mapped to codes after lowering it by the margin, by one code step, by 2^-22 of the largest
        // height magnitude and by 2^-50 of the ray's own height magnitudes. Conservative: those cover the float
        // rounding of the decoded heights, of this arithmetic and of the ray heights the cell test computes, so a
        // block passing in code space passes the height test. The ray's code-space height is linear in t.
        const double codeSlackM = margin + pyramid.scale + 0x1p-22 * (heightScale + pyramid.scale) +
                                  0x1p-50 * (std::abs(og.z) + std::abs(dg.z) * std::max(std::abs(t0), std::abs(t1)));
        codeZ0 = (og.z - codeSlackM) * pyramid.codesPerMetre - double(pyramid.offset);
        // The same for a block the ray runs under: passed when its lowest code lies above the ray's highest
        // height over it, raised by that slack.
        codeZ0High = (og.z + codeSlackM) * pyramid.codesPerMetre - double(pyramid.offset);
        codeDz = dg.z * pyramid.codesPerMetre;
        descending = zSign == 2 ? dg.z < 0.0 : zSign < 0;
        rising = zSign == 2 ? dg.z > 0.0 : zSign > 0;
        posX = dg.x > 0.0;
        posY = dg.y > 0.0;
        tAtX0 = movesX ? -og.x * invX : kInfinity;
        tAtY0 = movesY ? -og.y * invY : kInfinity;
        exitOffX = posX ? 1 : 0;
        exitOffY = posY ? 1 : 0;
        stepX = posX ? 1 : -1;
        stepY = posY ? 1 : -1;

        // The first cell holds the entry point, preferring the side the ray moves into on a boundary. (Truncation
        // is floor here: the point is clamped to the grid first; std::floor is a library call on baseline
        // x86-64.)
        auto firstIndex = [](double o, double d, double tt, int64_t cells) {
            const double p = std::clamp(o + tt * d, 0.0, static_cast<double>(cells));
            auto k = static_cast<int64_t>(p);
            if (d < 0.0 && static_cast<double>(k) == p) --k;
            return std::clamp(k, int64_t(0), cells - 1);
        };
        i = firstIndex(og.x, dg.x, t0, cellsX);
        j = firstIndex(og.y, dg.y, t0, cellsY);
        auto besideLine = [](bool movesAlong, double o, int64_t k, int64_t cells) -> int64_t {
            if (movesAlong) return -1;
            const double line = std::round(o);
            if (!(std::abs(o - line) <= 1e-9) || line < 1.0 || line > double(cells - 1)) return -1;
            return k == int64_t(line) ? k - 1 : k + 1;
        };
        altI = besideLine(movesX, og.x, i, cellsX);
        altJ = besideLine(movesY, og.y, j, cellsY);
        entry = CellSide::Interior;
        t = t0;
        // A ray from outside the grid's box (a camera's) starts a few levels up, where the first blocks it
        // crosses usually lie below it; one from inside (leaving a surface point) starts at the cells and climbs.
        const bool fromOutside = og.z > zHi + zPad || og.x < 0.0 || og.y < 0.0 || og.x > double(cellsX) ||
                                 og.y > double(cellsY);
        level = fromOutside ? std::min(3, levels) : 0;
        under = false;
        // A stretch known to be free is passed like a skipped block: the walk resumes at the last cell boundary
        // within it, in the state the flat walk has just after crossing that boundary, and a few levels up.
        if (freeUntil > t0 && levels > 0) {
            if (freeUntil >= t1) return false;
            // The last x (y) boundary whose parameter is at most freeUntil: the one at the point's coordinate,
            // corrected by the boundary formula itself; -infinity when there is none inside the grid.
            auto lastBoundary = [freeUntil](double o, double d, int64_t cells, int64_t step, auto tAt,
                                            int64_t& edge) {
                const double p = std::clamp(o + freeUntil * d, 0.0, static_cast<double>(cells));
                edge = static_cast<int64_t>(p) + (step < 0 && static_cast<double>(static_cast<int64_t>(p)) != p);
                while (edge >= 0 && edge <= cells && tAt(edge) > freeUntil) edge -= step;
                return edge >= 0 && edge <= cells ? tAt(edge) : -kInfinity;
            };
            int64_t xEdge = 0, yEdge = 0;
            const double txb = movesX ? lastBoundary(og.x, dg.x, cellsX, stepX, [this](int64_t x) { return tAtX(x); },
                                                     xEdge)
                                      : -kInfinity;
            const double tyb = movesY ? lastBoundary(og.y, dg.y, cellsY, stepY, [this](int64_t y) { return tAtY(y); },
                                                     yEdge)
                                      : -kInfinity;
            const bool acrossX = txb >= tyb;
            const double tb = acrossX ? txb : tyb;
            // Only a boundary ahead of the first cell: the face a ray enters through can get a parameter a few
            // ulps above t0 from the boundary formula, yet the flat walk never crosses it.
            const bool ahead =
                acrossX ? (xEdge - 1 + exitOffX - i) * stepX > 0 : (yEdge - 1 + exitOffY - j) * stepY > 0;
            if (tb > t0 && ahead) {
                if (!crossInto(acrossX, acrossX ? xEdge : yEdge, tb)) return false;
                t = tb;
                level = std::min(2, levels);
            }
        }
        return true;
    }

    // The column (row) the flat walk stands in once it has crossed exactly those boundaries of that axis
    // whose parameter is below tb, or also those at tb when `inclusive`. The flat walk crosses boundaries in
    // order of t, x before y on a tie, so "every boundary below tb, and the x boundaries at tb" and "every
    // boundary below tb" are both states it passes through. Starts from the point's floor, never behind the
    // current index `from` (the flat walk does not step back), and corrects by the boundary parameters; -1
    // when the flat walk would have left the grid first.
    template <class ExitAt>
    int64_t settle(int64_t from, double o, double d, int64_t cells, double tb, int64_t step, bool inclusive,
                   ExitAt exitAt) const {
        auto crossed = [&](int64_t c) { return inclusive ? exitAt(c) <= tb : exitAt(c) < tb; };
        // Most often the walk has not left its column (row) by tb: one comparison, whose boundary parameter
        // does not wait for tb.
        if (!crossed(from)) return from;
        auto k = static_cast<int64_t>(std::clamp(o + tb * d, 0.0, static_cast<double>(cells - 1)));
        if ((k - from) * step < 0) k = from;
        if (crossed(k)) {
            do {
                k += step;
                if (k < 0 || k >= cells) return -1;
            } while (crossed(k));
        } else if ((k != from) & !crossed(k - step)) {  // rare: evaluated without a data-dependent branch
            do k -= step;
            while (k != from && !crossed(k - step));
        }
        return k;
    }

    // Moves the walk across the boundary `edge` of the x axis (when `acrossX`) or of the y axis, at parameter tb:
    // into the column (row) beyond it, the other axis settled at tb. False when that leaves the grid.
    __attribute__((always_inline)) bool crossInto(bool acrossX, int64_t edge, double tb) {
        if (acrossX) {
            i = edge - 1 + exitOffX;
            if (i < 0 || i >= cellsX) return false;
            if (movesY) j = settle(j, og.y, dg.y, cellsY, tb, stepY, false, [this](int64_t c) { return exitY(c); });
            if (j < 0) return false;
            entry = posX ? CellSide::XLow : CellSide::XHigh;
        } else {
            j = edge - 1 + exitOffY;
            if (j < 0 || j >= cellsY) return false;
            if (movesX) i = settle(i, og.x, dg.x, cellsX, tb, stepX, true, [this](int64_t c) { return exitX(c); });
            if (i < 0) return false;
            entry = posY ? CellSide::YLow : CellSide::YHigh;
        }
        return true;
    }

    // Cell flags and pyramid codes: a whole grid's arrays, or the tiles of a tiled grid's accessor.
    bool cellValid(int64_t ci, int64_t cj) const {
        if constexpr (Heights::kTiled) return at.cellValid(ci, cj);
        else return g.wholeCellValid(ci, cj);
    }
    int16_t maxCode(int k, int64_t bi, int64_t bj) const {
        if constexpr (Heights::kTiled) return at.code(k, bi, bj);
        else return pyramid.code(k, bi, bj);
    }
    int16_t minCode(int k, int64_t bi, int64_t bj) const {
        if constexpr (Heights::kTiled) return at.minCode(k, bi, bj);
        else return pyramid.minCode(k, bi, bj);
    }

    // Visits cell (ci, cj), which the ray crosses from tEnter (through `entry`) to tExit (through exitSide()).
    template <class ExitSide>
    __attribute__((always_inline)) Visit visitCell(int64_t ci, int64_t cj, double tEnter, double tExit, CellSide entry,
                                                   ExitSide exitSide) {
        if (counting && counters) ++counters->cellsVisited;
        // Along a grid line, the edge the ray runs on belongs to the valid cell beside a hole too (for the surfaces
        // through the vertices; nearest's flat squares have no shared edge).
        if (shape != Shape::Nearest && !cellValid(ci, cj)) {
            if (altI >= 0 && cellValid(altI, cj)) ci = altI;
            else if (altJ >= 0 && cellValid(ci, altJ)) cj = altJ;
        }
        if (!cellValid(ci, cj)) {
            hasCarriedG = false;
            // A corner pass: the segment clips the hole cell by less than 1e-7 of a cell (rounding of t).
            if ((tExit - tEnter) * (std::abs(dg.x) + std::abs(dg.y)) > 1e-7) cornerG.reset();
            return Visit::Passed;
        }
        const double zEnter = og.z + tEnter * dg.z, zExit = og.z + tExit * dg.z;
        // The corners as read (floats); their extremes are taken in float, which converting to double keeps.
        const float f00 = at(ci, cj), f10 = at(ci + 1, cj), f01 = at(ci, cj + 1), f11 = at(ci + 1, cj + 1);
        const double zMin = std::min(zEnter, zExit), zMax = std::max(zEnter, zExit);
        if (zMin > double(std::max(std::max(f00, f10), std::max(f01, f11))) + margin) {
            cornerG.reset();
            hasCarriedG = false;
            return Visit::Passed;
        }
        // A segment wholly below the cell is skipped when looking for the first crossing; for occlusion the
        // terrain is solid, so such a segment is tested (and found blocked) below. Not for the nearest squares:
        // their walls make a crossing of a ray that was above the previous square and enters this cell below all
        // its corners, which a continuous surface cannot.
        if (!anyHit && shape != Shape::Nearest &&
            zMax < double(std::min(std::min(f00, f10), std::min(f01, f11))) - margin) {
            cornerG.reset();
            hasCarriedG = false;
            return Visit::Below;
        }
        const auto h = corners<Real>(f00, f10, f01, f11);  // the heights read for the tests above
        if (counting && counters) ++counters->cellsTested;

        const glm::dvec3 pEnter{og.x + tEnter * dg.x, og.y + tEnter * dg.y, zEnter};
        const glm::dvec3 pExit{og.x + tExit * dg.x, og.y + tExit * dg.y, zExit};
        CellSegment<Real> seg;
        seg.u0 = std::clamp(Real(pEnter.x - double(ci)), Real(0), Real(1));
        seg.v0 = std::clamp(Real(pEnter.y - double(cj)), Real(0), Real(1));
        seg.z0 = Real(Wide<Real>(zEnter) - Wide<Real>(f00));
        seg.du = Real(dg.x);
        seg.dv = Real(dg.y);
        seg.dz = Real(dg.z);
        seg.length = Real(tExit - tEnter);
        seg.gEntry = hasCarriedG ? carriedG : surfaceAboveRay<Real, shape>(at, ci, cj, entry, pEnter);
        seg.gExit = surfaceAboveRay<Real, shape>(at, ci, cj, exitSide(), pExit);
        carriedG = seg.gExit;
        hasCarriedG = true;

        std::optional<Real> s;
        if (anyHit && seg.gEntry > Real(0)) s = Real(0);  // under the solid terrain (entered from a hole or edge)
        else if (shape != Shape::Nearest && cornerG && (*cornerG < Real(0)) != (seg.gEntry < Real(0))) s = Real(0);
        else if constexpr (shape == Shape::Bilinear) s = intersectBilinearCell(h, seg);
        else if constexpr (shape == Shape::Triangles) s = intersectTrianglesCell(h, seg);
        else s = intersectNearestCell(h, seg);
        cornerG = seg.gExit;

        if constexpr (shape == Shape::Bilinear)
            if (counting && counters && !counters->ambiguous)
                counters->ambiguous = grazes(h, seg, s.has_value(), tolerance);
        if (!s) return Visit::Tested;

        const double t = tEnter + double(*s);
        if (!interval.contains(t)) return Visit::Tested;
        result = true;
        if (!out) return Visit::Hit;

        HeightFieldHit& hit = *out;
        hit.t = t;
        hit.cellX = ci;
        hit.cellY = cj;
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
                switch (entry) {
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
        return Visit::Hit;
    }

    // One step of the walk: the 2D DDA of Amanatides & Woo 1987 over the cells, interleaved with the
    // maximum-pyramid descent of Tevs, Ihrke, Seidel 2008. At level k >= 1 the walk stands at the block of
    // 2^k x 2^k cells holding the current cell; when the ray passes above the block's highest vertex (by the
    // margin) over the whole stretch it spends in the block, the block is skipped and the walk climbs one
    // level, otherwise it descends. At level 0 one cell is visited exactly as the flat walk visits it. Every
    // boundary's ray parameter comes from one formula, and after a skip the walk resumes in the cell the flat
    // walk would stand in at that parameter (ties between an x and a y boundary go to x first, as in the flat
    // walk), so the cells reached see the same tEnter, tExit and sides, and skipping changes no hit: every cell
    // of a skipped block would have been passed over.
    __attribute__((always_inline)) bool step() {
        if (level > 0) {
            const int64_t bi = i >> level, bj = j >> level;
            // The block's exit edges in the direction of travel and their parameters. A last, partial block's
            // edge may lie beyond the grid; the ray's stretch in it still ends at t1, inside the grid.
            const int64_t xEdge = (bi + exitOffX) << level;
            const int64_t yEdge = (bj + exitOffY) << level;
            const double txb = tAtX(xEdge), tyb = tAtY(yEdge);
            const bool leavesX = txb <= tyb;
            const double tb = std::min(txb, tyb);  // txb when leavesX
            const double tOut = std::max(t, std::min(tb, t1));
            const double tLow = descending ? tOut : t;
            const bool ahead = tOut > t;
            const bool above = ahead && double(maxCode(level, bi, bj)) < codeZ0 + codeDz * tLow;
            // Under the surface, a block of the minimum pyramid (level 2 up) may lie wholly above the ray.
            if (!above && !(ahead && under && level >= 2 &&
                            double(minCode(level, bi, bj)) > codeZ0High + codeDz * (descending ? t : tOut))) {
                // Level 1 has no minimum: a ray under the surface goes straight to the cells.
                level = under && level == 2 ? 0 : level - 1;
                return true;
            }
            if (counting && counters) ++counters->blocksSkipped;
            cornerG.reset();
            hasCarriedG = false;
            if (t1 <= tb) return false;  // the interval ends inside the skipped block
            if (!crossInto(leavesX, leavesX ? xEdge : yEdge, tb)) return false;
            t = tb;
            // Climb a level, unless a descending ray stays inside the parent block: the parent's remaining
            // stretch ends at the same exit, as low as before, so when the walk came down from the parent (the
            // usual case) it would fail again; the sibling at this level is tested instead. Under the surface
            // the same holds for a ray that does not descend.
            const bool sameParent = (i >> (level + 1)) == (bi >> 1) && (j >> (level + 1)) == (bj >> 1);
            if (level < levels && (!sameParent || (above ? rising : descending))) ++level;
            return true;
        }

        const double tNextX = exitX(i), tNextY = exitY(j);
        const bool crossX = tNextX <= tNextY;
        const double tBoundary = std::min(tNextX, tNextY);  // tNextX when crossX
        const bool ends = t1 <= tBoundary;
        const double tExit = std::max(t, std::min(tBoundary, t1));  // t1 when the walk ends in this cell
        // The side the walk leaves the cell through, asked for only when the cell is tested.
        auto exitSide = [&] {
            return ends && t1 < tBoundary ? CellSide::Interior
                   : crossX               ? (posX ? CellSide::XHigh : CellSide::XLow)
                                          : (posY ? CellSide::YHigh : CellSide::YLow);
        };
        // The row a step along y reaches next is the one most likely to miss the cache (rows lie a grid width
        // apart); ask for it while this cell is tested.
        at.prefetch(i, std::clamp(j + (posY ? 2 : -1), int64_t(0), cellsY));
        const Visit visit = visitCell(i, j, t, tExit, entry, exitSide);
        if (visit == Visit::Hit || ends) return false;
        const int64_t iWas = i, jWas = j;
        if (crossX) {
            i += stepX;
            if (i < 0 || i >= cellsX) return false;
            entry = posX ? CellSide::XLow : CellSide::XHigh;
        } else {
            j += stepY;
            if (j < 0 || j >= cellsY) return false;
            entry = posY ? CellSide::YLow : CellSide::YHigh;
        }
        t = tExit;
        // Try the pyramid only after a cell the ray passed over: a cell the ray might touch cannot lie in a
        // block it passes above, so cells near the surface pay nothing for the pyramid. Nor when a ray that
        // does not rise stays in the same 2 x 2 block: its lowest height there is at the block's exit, so when
        // the walk came down from that block, or met a cell of it that it could not pass, the block would fail
        // again (the usual case; otherwise only a skip is missed, never a hit).
        if (visit == Visit::Passed && levels > 0 && (rising || ((i ^ iWas) | (j ^ jWas)) > 1)) level = 1;
        // A ray running under the surface tries the minimum pyramid, which starts at level 2.
        under = visit == Visit::Below && levels >= 2;
        if (under) level = 2;
        return true;
    }
};

// True when the ray meets the surface in `interval`; the nearest such hit is written to `out` when given
// (occlusion queries pass none and skip building it). `freeUntil` is a ray parameter up to which the ray is
// known to pass above every cell by more than the skip margin (see bundleFreeDistanceM), or -infinity.
// zSign is the sign of ray.dir.z (-1, 0 or 1; 0 also for -0.0), or 2 to read it from the ray; the block tests
// and level choices rely on it. Without `counting`, counters are ignored. (The walk is an object rather than
// this function's locals and lambdas: the code GCC generates for it runs a few per cent faster that way.)
template <class Real, Shape shape, class Heights, int zSign, bool counting>
bool trace(const HeightGrid& g, const Heights& at, const Ray& ray, Interval interval, bool anyHit,
           TraceCounters* counters, Traversal traversal, HeightFieldHit* out, double freeUntil) {
    Walk<Real, shape, Heights, zSign, counting> walk(g, at, ray, interval, anyHit, counters, out);
    if (walk.start(traversal, freeUntil))
        while (walk.step()) {
        }
    return walk.result;
}

// For bilinear and triangles in float, which renders use, the walk is compiled once per sign of the ray's
// vertical direction (its block tests and level choices depend on it at every step), and once with and once
// without counters, so that untallied traces test none. The other methods (double and reference arithmetic, the
// naive flat cells) are compiled once and read the sign and the counters at run time.
template <class Real, Shape shape, class Heights>
bool traceSign(const HeightGrid& g, const Heights& at, const Ray& ray, Interval interval, bool anyHit,
               TraceCounters* counters, Traversal tr, HeightFieldHit* out, double freeUntil) {
    if constexpr (!std::is_same_v<Real, float> || shape == Shape::Nearest) {
        return trace<Real, shape, Heights, 2, true>(g, at, ray, interval, anyHit, counters, tr, out, freeUntil);
    } else {
        auto walk = [&]<int zSign>() {
            if (counters)
                return trace<Real, shape, Heights, zSign, true>(g, at, ray, interval, anyHit, counters, tr, out,
                                                                freeUntil);
            return trace<Real, shape, Heights, zSign, false>(g, at, ray, interval, anyHit, nullptr, tr, out,
                                                             freeUntil);
        };
        if (ray.dir.z < 0.0) return walk.template operator()<-1>();
        if (ray.dir.z > 0.0) return walk.template operator()<1>();
        return walk.template operator()<0>();
    }
}

// Calls f.template operator()<Real, shape>(heights) with the arithmetic and cell shape of `method` and the height
// access of the grid's storage (its tiles, in the tiled kernels), so that callers tracing many rays choose them
// once.
template <class F>
bool withMethod(const HeightGrid& g, CellMethod method, F&& f) {
    auto storage = [&]<class Real, Shape shape>() {
#if TERRACAST_TILED_KERNELS
        return f.template operator()<Real, shape>(
            TiledHeights{&g, g.pyramidView(), g.tileLevels(), g.cellsX(), g.cellsY()});
#else
        if (const float* h = g.float32Heights())
            return f.template operator()<Real, shape>(Float32Heights{h, g.width()});
        if (g.codeScale() == 1.0)
            return f.template operator()<Real, shape>(Int16UnitHeights{g.int16Codes(), g.width(), g.codeOffset()});
        return f.template operator()<Real, shape>(
            Int16Heights{g.int16Codes(), g.width(), g.codeOffset(), g.codeScale()});
#endif
    };
    switch (method) {
    case CellMethod::Bilinear: return storage.template operator()<float, Shape::Bilinear>();
    case CellMethod::BilinearDouble: return storage.template operator()<double, Shape::Bilinear>();
    case CellMethod::Triangles: return storage.template operator()<float, Shape::Triangles>();
    case CellMethod::Nearest: return storage.template operator()<float, Shape::Nearest>();
    case CellMethod::Reference: return storage.template operator()<long double, Shape::Bilinear>();
    }
    return false;
}

bool dispatch(const HeightGrid& g, const Ray& ray, Interval interval, CellMethod method, bool anyHit,
              TraceCounters* counters, Traversal tr, HeightFieldHit* out) {
    return withMethod(g, method, [&]<class Real, Shape shape>(const auto& at) {
        return traceSign<Real, shape>(g, at, ray, interval, anyHit, counters, tr, out, -kInfinity);
    });
}
