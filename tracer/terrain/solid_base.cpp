#include "tracer/terrain/solid_base.h"

#include <algorithm>
#include <cmath>

namespace terracast {

double solidBaseFloorM(const HeightGrid& grid) {
    const double relief = double(grid.maxHeightM()) - double(grid.minHeightM());
    return double(grid.minHeightM()) - std::max(0.1 * relief, 0.01 * std::max(grid.extentXM(), grid.extentYM()));
}

namespace {

// The surface's height along an edge at `s` vertices from its start, or none over a nodata vertex. `at(k)`
// reads vertex k of the edge, `valid(k)` says whether it holds a height.
template <class At, class Valid>
std::optional<double> edgeHeight(double s, int64_t vertices, At&& at, Valid&& valid) {
    if (!(s >= 0.0) || s > double(vertices - 1)) return std::nullopt;
    const int64_t k = std::min<int64_t>(int64_t(s), vertices - 2);
    const double f = s - double(k);
    if (!valid(k) || !valid(k + 1)) return std::nullopt;
    return double(at(k)) * (1.0 - f) + double(at(k + 1)) * f;
}

}  // namespace

std::optional<WallHit> intersectSolidBase(const HeightGrid& grid, double floorM, const Ray& ray, double tMax) {
    std::optional<WallHit> best;
    const double xMax = grid.extentXM(), yMax = grid.extentYM();
    // The four walls: x = 0 (west), x = xMax (east), y = 0 (south), y = yMax (north).
    for (int wall = 0; wall < 4; ++wall) {
        const bool alongY = wall < 2;  // a west or east wall runs north-south
        const double plane = wall == 1 ? xMax : wall == 3 ? yMax : 0.0;
        const double outward = wall == 0 || wall == 2 ? -1.0 : 1.0;
        const double o = alongY ? ray.origin.x : ray.origin.y, d = alongY ? ray.dir.x : ray.dir.y;
        if (!(d * outward < 0.0)) continue;  // parallel, or meeting the wall from inside
        const double t = (plane - o) / d;
        if (!(t > 0.0 && t < tMax) || (best && t >= best->t)) continue;
        const glm::dvec3 p = ray.origin + t * ray.dir;
        // The wall's top interpolates the edge's heights: a point above the grid's highest (past the rounding of
        // that interpolation) is above the wall too.
        const double highest = double(grid.maxHeightM());
        if (p.z < floorM || p.z > highest + 1e-9 * (1.0 + std::abs(highest))) continue;
        std::optional<double> top;
        if (alongY) {
            const int64_t i = wall == 0 ? 0 : grid.width() - 1;
            top = edgeHeight(p.y / grid.cellSizeYM(), grid.height(), [&](int64_t j) { return grid.at(i, j); },
                             [&](int64_t j) { return grid.vertexValid(i, j); });
        } else {
            const int64_t j = wall == 2 ? 0 : grid.height() - 1;
            top = edgeHeight(p.x / grid.cellSizeXM(), grid.width(), [&](int64_t i) { return grid.at(i, j); },
                             [&](int64_t i) { return grid.vertexValid(i, j); });
        }
        if (!top || p.z > *top) continue;
        WallHit h;
        h.t = t;
        h.point = p;
        h.normal = alongY ? glm::dvec3(outward, 0.0, 0.0) : glm::dvec3(0.0, outward, 0.0);
        best = h;
    }
    return best;
}

}  // namespace terracast
