// Clipping a ray to the grid's footprint and walking the cells it crosses in order.
//
// The walk is the 2D digital differential analyzer of Amanatides & Woo 1987 ("A Fast Voxel Traversal
// Algorithm for Ray Tracing"), applied to height fields as in Musgrave 1988. The next boundary crossing is
// recomputed from the integer cell index, t = (boundary - o) / d, instead of accumulating t increments, so
// rounding does not drift over thousands of cells.
#pragma once

#include "heightfield/geometry.h"

#include <cmath>
#include <cstdint>

namespace terracast {

// The side of a cell through which a ray segment enters or leaves it.
enum class CellSide : uint8_t {
    Interior,  // the segment starts or ends inside the cell (ray origin or end of the interval)
    XLow,      // the edge x = i
    XHigh,     // the edge x = i + 1
    YLow,      // the edge y = j
    YHigh,     // the edge y = j + 1
};

// One step of the walk: cell (i, j) is crossed for ray parameters [tEnter, tExit].
struct CellVisit {
    int64_t i, j;
    double tEnter, tExit;
    CellSide entry, exit;
};

// Clips [t0, t1] to the slab lo <= o + t d <= hi. Returns false when the result is empty.
inline bool clipToSlab(double o, double d, double lo, double hi, double& t0, double& t1) {
    if (d == 0.0) return lo <= o && o <= hi;
    double ta = (lo - o) / d;
    double tb = (hi - o) / d;
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    return t0 <= t1;
}

// Walks the cells of a grid with cellsX x cellsY unit cells (grid coordinates: vertex (i, j) at (i, j))
// crossed by origin + t * dir for t in [t0, t1], in order of increasing t. `visit(const CellVisit&)` returns
// true to stop the walk. Consecutive cells share a boundary: an exact corner crossing visits one of the two
// side cells with a zero-length segment. Precondition: t0 and t1 finite unless dir.x == dir.y == 0.
// This is the plain walk, a building block for tools and tests; the tracer's own walk (traversal.cpp) follows
// the same rules interleaved with the maximum pyramid, with boundary parameters taken as products with the
// direction's reciprocals.
template <class Visitor>
void walkCells(int64_t cellsX, int64_t cellsY, glm::dvec2 origin, glm::dvec2 dir, double t0, double t1,
               Visitor&& visit) {
    if (cellsX <= 0 || cellsY <= 0) return;
    if (!clipToSlab(origin.x, dir.x, 0.0, static_cast<double>(cellsX), t0, t1)) return;
    if (!clipToSlab(origin.y, dir.y, 0.0, static_cast<double>(cellsY), t0, t1)) return;

    // First cell: the cell containing the entry point, preferring the side the ray moves into when the
    // entry point lies exactly on a boundary.
    auto firstIndex = [](double o, double d, double t, int64_t cells) {
        const double p = o + t * d;
        double f = std::floor(p);
        if (d < 0.0 && f == p) f -= 1.0;
        const auto k = static_cast<int64_t>(std::clamp(f, 0.0, static_cast<double>(cells - 1)));
        return k;
    };
    int64_t i = firstIndex(origin.x, dir.x, t0, cellsX);
    int64_t j = firstIndex(origin.y, dir.y, t0, cellsY);
    const int64_t stepX = dir.x > 0.0 ? 1 : -1;
    const int64_t stepY = dir.y > 0.0 ? 1 : -1;

    auto nextX = [&](int64_t ci) {
        if (dir.x == 0.0) return kInfinity;
        return (static_cast<double>(ci + (dir.x > 0.0 ? 1 : 0)) - origin.x) / dir.x;
    };
    auto nextY = [&](int64_t cj) {
        if (dir.y == 0.0) return kInfinity;
        return (static_cast<double>(cj + (dir.y > 0.0 ? 1 : 0)) - origin.y) / dir.y;
    };
    double tNextX = nextX(i);
    double tNextY = nextY(j);

    CellVisit v{i, j, t0, t0, CellSide::Interior, CellSide::Interior};
    for (;;) {
        const bool crossX = tNextX <= tNextY;
        const double tBoundary = crossX ? tNextX : tNextY;
        const bool ends = t1 <= tBoundary;
        v.i = i;
        v.j = j;
        v.tExit = std::max(v.tEnter, ends ? t1 : tBoundary);
        v.exit = ends && t1 < tBoundary ? CellSide::Interior
                 : crossX             ? (stepX > 0 ? CellSide::XHigh : CellSide::XLow)
                                      : (stepY > 0 ? CellSide::YHigh : CellSide::YLow);
        if (visit(static_cast<const CellVisit&>(v))) return;
        if (ends) return;
        if (crossX) {
            i += stepX;
            if (i < 0 || i >= cellsX) return;
            tNextX = nextX(i);
            v.entry = stepX > 0 ? CellSide::XLow : CellSide::XHigh;
        } else {
            j += stepY;
            if (j < 0 || j >= cellsY) return;
            tNextY = nextY(j);
            v.entry = stepY > 0 ? CellSide::YLow : CellSide::YHigh;
        }
        v.tEnter = v.tExit;
    }
}

}  // namespace terracast
