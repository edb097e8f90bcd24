// The loop behind every map raster on the grid's vertices, and the surface's geometry at a vertex: internal to
// the terrain subsystem's map products (maps.cpp, insolation.cpp).
#pragma once

#include "tracer/terrain/maps.h"

#include "tracer/core/parallel.h"

#include <glm/glm.hpp>

#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <utility>

namespace terracast::vertex_maps {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Calls f(i, j, out, chainStart) for every vertex of the grid, with `out` the vertex's `bands` values (NaN until
// set); `progress` hears the share of vertices done and `raysPerVertex` times their count. In parallel tiles of
// 64 x 64 vertices, or with `wholeRows` a row at a time from west to east, chainStart true at every 64th vertex:
// what f carries from one vertex to the next (horizon hints) starts afresh there, so the results do not depend
// on how rows are shared among threads.
template <class F>
MapRaster forVertices(const HeightGrid& grid, int bands, int threads, const MapProgress& progress,
                      int64_t raysPerVertex, bool wholeRows, F&& f) {
    MapRaster r;
    r.width = grid.width();
    r.height = grid.height();
    r.bands = bands;
    r.values.assign(size_t(r.width * r.height * bands), kNaN);
    std::atomic<int64_t> done{0};
    std::mutex progressMutex;
    const double total = double(r.width) * double(r.height);
    parallelForTiles(wholeRows ? 1 : int(r.width), int(r.height), wholeRows ? 4 : 64, threads,
                     [&](int x0, int y0, int x1, int y1) {
                         const int64_t i0 = wholeRows ? 0 : x0, i1 = wholeRows ? r.width : x1;
                         for (int64_t j = y0; j < y1; ++j)
                             for (int64_t i = i0; i < i1; ++i)
                                 f(i, j, &r.values[size_t((j * r.width + i) * bands)], i % 64 == 0);
                         const int64_t now = done += (i1 - i0) * (y1 - y0);
                         if (progress) {
                             std::lock_guard lock(progressMutex);
                             progress(double(now) / total, now * raysPerVertex);
                         }
                     });
    return r;
}

// Every vertex in parallel tiles, f(i, j, out).
template <class F>
MapRaster perVertexBands(const HeightGrid& grid, int bands, int threads, const MapProgress& progress,
                         int64_t raysPerVertex, F&& f) {
    return forVertices(grid, bands, threads, progress, raysPerVertex, false,
                       [&](int64_t i, int64_t j, float* out, bool) { f(i, j, out); });
}

// Every vertex a row at a time, f(i, j, out, chainStart).
template <class F>
MapRaster perVertexRows(const HeightGrid& grid, int bands, int threads, const MapProgress& progress,
                        int64_t raysPerVertex, F&& f) {
    return forVertices(grid, bands, threads, progress, raysPerVertex, true, std::forward<F>(f));
}

// One value per vertex: f(i, j).
template <class F>
MapRaster perVertex(const HeightGrid& grid, int threads, const MapProgress& progress, int64_t raysPerVertex, F&& f) {
    return perVertexBands(grid, 1, threads, progress, raysPerVertex,
                          [&](int64_t i, int64_t j, float* out) { *out = f(i, j); });
}

// True when vertex (i, j) is a corner of at least one valid cell: the surface passes through it.
bool vertexOnSurface(const HeightGrid& g, int64_t i, int64_t j);

// The surface normal at vertex (i, j): the unit normals of its valid cells at that corner, averaged (for both
// surfaces the bilinear gradient at a corner is a triangle's there, or mixes the two that meet at it).
glm::dvec3 vertexNormal(const HeightGrid& g, int64_t i, int64_t j);

}  // namespace terracast::vertex_maps
