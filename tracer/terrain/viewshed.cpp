// The viewshed of one observer (maps.h): a sight line per vertex, decided by the occlusion walk, or the height a
// target needs from the horizon walk out of the eye.
#include "tracer/terrain/maps.h"
#include "tracer/terrain/vertex_loop.h"

#include "heightfield/horizon.h"
#include "heightfield/traversal.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/sight_bounds.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

namespace terracast {

using namespace vertex_maps;

namespace {

// The bounds are widened by this many times the grazing tolerance, so that what they settle is what the walk
// decides.
constexpr double kBoundsTolerance = 4.0;

// True for the methods whose surface in a cell is the bilinear patch.
bool bilinearSurface(CellMethod m) {
    return m == CellMethod::Bilinear || m == CellMethod::BilinearDouble || m == CellMethod::Reference;
}

// A cheap proof that a sight line is hidden, tried before walking it. Where a point of the line beyond the
// stretch known clear (by the sight bounds, or only the eye without them), and before the target, lies under a
// valid cell's surface by more than the bounds' tolerance, the walk from that stretch's end (where the line is
// above the surface) meets the surface before that point: the line is hidden, as the walk would find. Neighbouring targets are mostly hidden
// by the same ridge, so each thread first tries the distance at which its last walked hidden line was blocked,
// half a cell deeper, then one cell past the clear stretch. A failed probe decides nothing: the line is walked.
// The probe only ever answers "hidden" where the walk does, so which distances it tries changes no verdict.
class HiddenProbe {
public:
    HiddenProbe(const HeightGrid& g, CellMethod method, double marginM)
        : g_(g), shape_(method == CellMethod::Nearest ? Surface::None
                        : method == CellMethod::Triangles ? Surface::Triangles
                                                          : Surface::Bilinear),
          marginM_(marginM), cellM_(std::min(g.cellSizeXM(), g.cellSizeYM())) {}

    // The line from `eye` along `d` (the target at d, `horizontal` metres away), clear over [0, clear) and ending
    // at `end` (fractions of d).
    bool hidden(const glm::dvec3& eye, const glm::dvec3& d, double horizontal, double clear, double end) const {
        if (shape_ == Surface::None) return false;
        return under(eye, d, lastBlockM() / horizontal, clear, end) ||
               under(eye, d, clear + cellM_ / horizontal, clear, end);
    }
    // Where a walked line was blocked, `t` along d.
    void blockedAt(double t, double horizontal) const { lastBlockM() = t * horizontal + 0.5 * cellM_; }

private:
    enum class Surface { None, Bilinear, Triangles };
    static double& lastBlockM() {
        thread_local double m = -1.0;
        return m;
    }
    bool under(const glm::dvec3& eye, const glm::dvec3& d, double f, double clear, double end) const {
        if (!(f > clear && f < end)) return false;
        const double x = (eye.x + f * d.x) * g_.cellsPerMetreX(), y = (eye.y + f * d.y) * g_.cellsPerMetreY();
        if (!(x >= 0.0 && y >= 0.0 && x < double(g_.cellsX()) && y < double(g_.cellsY()))) return false;
        const auto i = int64_t(x), j = int64_t(y);
        if (!g_.wholeCellValid(i, j)) return false;
        const double u = x - double(i), v = y - double(j);
        const double h00 = g_.at(i, j), h10 = g_.at(i + 1, j), h01 = g_.at(i, j + 1), h11 = g_.at(i + 1, j + 1);
        double h;
        if (shape_ == Surface::Bilinear) h = (1.0 - v) * ((1.0 - u) * h00 + u * h10) + v * ((1.0 - u) * h01 + u * h11);
        else if (u + v > 1.0) h = h11 - (h11 - h01) * (1.0 - u) - (h11 - h10) * (1.0 - v);  // the two triangles' split
        else h = h00 + (h10 - h00) * u + (h01 - h00) * v;
        return h - (eye.z + f * d.z) > marginM_;
    }

    const HeightGrid& g_;
    Surface shape_;
    double marginM_, cellM_;
};

}  // namespace

bool viewshedUsesSightBounds(const HeightGrid& grid, const ViewshedSettings& s) {
    return s.boundSightLines && s.values != ViewshedValues::Height && !grid.tiled();
}

std::function<MapRaster(const VertexWindow&, const MapProgress&)> viewshedMaker(const HeightGrid& grid, const ViewshedSettings& s) {
    // Earth curvature (less refraction) lowers everything by coeff * d^2 / (2 R) with distance d from the
    // observer: trace in a copy of the grid with that drop applied.
    const HeightGrid* g = &grid;
    std::shared_ptr<const HeightGrid> curved;
    if (s.curvatureCoeff != 0.0) {
        HeightTransform lower;
        lower.curvatureCoeff = s.curvatureCoeff;
        lower.earthRadiusM = s.earthRadiusM;
        lower.observerXM = s.observerXM;
        lower.observerYM = s.observerYM;
        curved = std::make_shared<const HeightGrid>(grid.transformed(lower));
        g = curved.get();
    }
    const auto ground = surfacePointAt(*g, s.observerXM, s.observerYM, s.method);
    if (!ground)
        throw GridError("the observer at local (" + std::to_string(s.observerXM) + ", " + std::to_string(s.observerYM) +
                        ") m is not over the DEM's surface");
    const glm::dvec3 eye = ground->pointM + glm::dvec3(0.0, 0.0, s.observerHeightM);
    const double cellM = std::min(g->cellSizeXM(), g->cellSizeYM());
    const double endGap = 0.01 * cellM;
    static constexpr double kNearTargetCells = 8.0;
    const bool visibleOnly = s.values == ViewshedValues::Visible;
    // Most sight lines are settled by bounds on the surface's slope around the eye (sight_bounds.h); the rest are
    // walked from where those bounds stop.
    std::shared_ptr<const SightBounds> bounds;
    if (viewshedUsesSightBounds(*g, s))
        bounds = std::make_shared<const SightBounds>(*g, eye, kBoundsTolerance * grazingToleranceM(*g),
                                                     bilinearSurface(s.method), s.threads);
    const auto probe = std::make_shared<const HiddenProbe>(*g, s.method, kBoundsTolerance * grazingToleranceM(*g));
    return [g, curved, bounds, probe, s, eye, cellM, endGap, visibleOnly](const VertexWindow& window, const MapProgress& progress) {
    return perVertex(*g, window, s.threads, progress, 1, [&](int64_t i, int64_t j) {
        if (!g->vertexValid(i, j)) return kNaN;
        const glm::dvec3 target{double(i) * g->cellSizeXM(), double(j) * g->cellSizeYM(),
                                double(g->at(i, j)) + s.targetHeightM};
        const glm::dvec3 d = target - eye;
        if (s.values == ViewshedValues::Height) {
            const double horizontal = std::hypot(d.x, d.y);
            if (s.maxDistanceM > 0.0 && horizontal > s.maxDistanceM) return kNaN;
            // The sight line to (target, h + t) clears every surface point p at distance r along the way when
            // z_eye + r (h + t - z_eye) / D >= h(p), that is t >= D (h(p) - z_eye) / r + z_eye - h.
            if (!(horizontal > 0.0)) return 0.0f;
            HorizonSearch within;
            within.maxDistanceM = horizontal;
            const double tangent = horizonTangentFrom(*g, eye.x, eye.y, eye.z, d.x, d.y, s.method, within);
            const double h = double(g->at(i, j));
            const double need = horizontal * tangent + eye.z - h;
            // The supremum includes the target itself, where the sum is zero up to its rounding: the ground that is
            // seen needs nothing.
            const double rounding = 1e-9 * (1.0 + std::abs(eye.z) + std::abs(h));
            return std::isfinite(need) && need > rounding ? float(need) : 0.0f;
        }
        // (A square root rather than hypot: no overflow is possible here, and it costs a tenth.)
        const double horizontal = std::sqrt(d.x * d.x + d.y * d.y);
        if (s.maxDistanceM > 0.0 && horizontal > s.maxDistanceM) return visibleOnly ? 0.0f : kNaN;
        const double len = glm::length(d);
        // The sight line stops just short of the target, so a target on the surface does not hide itself.
        const double end = 1.0 - endGap / len;
        bool seen;
        if (len <= endGap) {
            seen = true;
        } else if (bounds && horizontal > 0.0) {
            // Hidden when the surface surely rises above the line somewhere before the target; else the line is
            // walked from as far as the bounds show it clear.
            const double slope = d.z / horizontal, key = bounds->azimuthKey(d.x, d.y);
            if (bounds->surelySlopeBefore(key, end * horizontal) > slope) {
                seen = false;
            } else {
                const double clear = bounds->clearBefore(key, slope) / horizontal;
                if (clear >= end) {
                    seen = true;
                } else if (probe->hidden(eye, d, horizontal, clear, end)) {
                    seen = false;
                } else {
                    const auto block = firstBlock(*g, Ray{eye, d}, {clear, end}, s.method);
                    seen = !block;
                    if (block) probe->blockedAt(block->t, horizontal);
                }
            }
        } else if (s.method == CellMethod::Nearest) {
            // A walk that starts inside a cell asks whether it starts under the bilinear surface, which is not
            // the flat square's: the line is walked whole.
            seen = !occluded(*g, Ray{eye, d}, {0.0, end}, s.method);
        } else {
            // Without the bounds the line is clear only at the eye: probed from there. Then the last few cells
            // before the target are asked first: a target hidden by the ground around it (the common case far from
            // the eye) is found there without walking the whole line.
            const double nearTarget = std::max(0.0, end - kNearTargetCells * cellM / len);
            if (horizontal > 0.0 && probe->hidden(eye, d, horizontal, 0.0, end)) {
                seen = false;
            } else {
                auto block = firstBlock(*g, Ray{eye, d}, {nearTarget, end}, s.method);
                if (!block && nearTarget > 0.0) block = firstBlock(*g, Ray{eye, d}, {0.0, nearTarget}, s.method);
                seen = !block;
                if (block && horizontal > 0.0) probe->blockedAt(block->t, horizontal);
            }
        }
        if (visibleOnly) return seen ? 1.0f : 0.0f;
        // The angle from hypot, as before the bounds: the raster's bits do not depend on them.
        return seen ? float(degrees(std::atan2(d.z, std::hypot(d.x, d.y)))) : kNaN;
    });
    };
}

MapRaster viewshed(const HeightGrid& grid, const ViewshedSettings& s) { return viewshedMaker(grid, s)(s.window, s.progress); }

}  // namespace terracast
