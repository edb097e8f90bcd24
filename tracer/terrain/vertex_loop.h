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

// Calls f(i, j, out, chainStart) for every vertex of `window` (of the grid: window.within), with `out` the
// vertex's `bands` values (NaN until set); `progress` hears the share of the window's vertices done and
// `raysPerVertex` times their count. In parallel tiles of 64 x 64 vertices, or with `wholeRows` a row of the
// window at a time from west to east (rowStart true at its first vertex), chainStart true at every 64th vertex
// of the grid: what f carries from one vertex to the next (horizon hints) starts afresh there, so the results
// depend neither on how rows are shared among threads nor on windows that start at multiples of 64.
template <class F>
MapRaster forVertices(const HeightGrid& grid, const VertexWindow& window, int bands, int threads,
                      const MapProgress& progress, int64_t raysPerVertex, bool wholeRows, F&& f) {
    const VertexWindow w = window.within(grid);
    MapRaster r;
    r.width = w.i1 - w.i0;
    r.height = w.j1 - w.j0;
    r.i0 = w.i0;
    r.j0 = w.j0;
    r.bands = bands;
    r.values.assign(size_t(r.width * r.height * bands), kNaN);
    std::atomic<int64_t> done{0};
    std::mutex progressMutex;
    const double total = double(r.width) * double(r.height);
    parallelForTiles(wholeRows ? 1 : int(r.width), int(r.height), wholeRows ? 4 : 64, threads,
                     [&](int x0, int y0, int x1, int y1) {
                         const int64_t a0 = wholeRows ? 0 : x0, a1 = wholeRows ? r.width : x1;
                         for (int64_t b = y0; b < y1; ++b) {
                             for (int64_t a = a0; a < a1; ++a) {
                                 // A task may hold many rows, and a vertex many horizon walks: a
                                 // cancellation is seen at the next vertex.
                                 if (cancelFlag().load(std::memory_order_relaxed)) return;
                                 const int64_t i = w.i0 + a, j = w.j0 + b;
                                 f(i, j, &r.values[size_t((b * r.width + a) * bands)], i % 64 == 0, a == 0);
                             }
                         }
                         const int64_t now = done += (a1 - a0) * (y1 - y0);
                         if (progress) {
                             std::lock_guard lock(progressMutex);
                             progress(double(now) / total, now * raysPerVertex);
                         }
                     });
    return r;
}

// Every vertex of the window in parallel tiles, f(i, j, out).
template <class F>
MapRaster perVertexBands(const HeightGrid& grid, const VertexWindow& window, int bands, int threads,
                         const MapProgress& progress, int64_t raysPerVertex, F&& f) {
    return forVertices(grid, window, bands, threads, progress, raysPerVertex, false,
                       [&](int64_t i, int64_t j, float* out, bool, bool) { f(i, j, out); });
}

// Every vertex of the window a row at a time, f(i, j, out, chainStart, rowStart).
template <class F>
MapRaster perVertexRows(const HeightGrid& grid, const VertexWindow& window, int bands, int threads,
                        const MapProgress& progress, int64_t raysPerVertex, F&& f) {
    return forVertices(grid, window, bands, threads, progress, raysPerVertex, true, std::forward<F>(f));
}

// One value per vertex of the window: f(i, j).
template <class F>
MapRaster perVertex(const HeightGrid& grid, const VertexWindow& window, int threads, const MapProgress& progress,
                    int64_t raysPerVertex, F&& f) {
    return perVertexBands(grid, window, 1, threads, progress, raysPerVertex,
                          [&](int64_t i, int64_t j, float* out) { *out = f(i, j); });
}

// True when vertex (i, j) is a corner of at least one valid cell: the surface passes through it.
bool vertexOnSurface(const HeightGrid& g, int64_t i, int64_t j);

// The surface normal at vertex (i, j): the unit normals of its valid cells at that corner, averaged (for both
// surfaces the bilinear gradient at a corner is a triangle's there, or mixes the two that meet at it).
glm::dvec3 vertexNormal(const HeightGrid& g, int64_t i, int64_t j);

}  // namespace terracast::vertex_maps
