// Parallelism behind one helper, so render loops read sequentially.
#pragma once

#include "tracer/core/cancel.h"

#include <tbb/blocked_range2d.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <memory>

namespace terracast {

// Calls body(x0, y0, x1, y1) for every tile of a width x height raster, in parallel on `threads` threads
// (0 = all cores). Tiles are half-open pixel ranges [x0, x1) x [y0, y1). When cancellation is requested the
// remaining tiles are skipped and Cancelled is thrown once the workers have returned.
template <class Body>
void parallelForTiles(int width, int height, int tile, int threads, Body&& body) {
    std::unique_ptr<tbb::global_control> limit;
    if (threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      static_cast<size_t>(threads));
    tile = std::max(tile, 1);
    tbb::parallel_for(tbb::blocked_range2d<int>(0, height, tile, 0, width, tile),
                      [&](const tbb::blocked_range2d<int>& r) {
                          if (cancelFlag().load(std::memory_order_relaxed)) return;
                          body(r.cols().begin(), r.rows().begin(), r.cols().end(), r.rows().end());
                      });
    throwIfCancelled();
}

}  // namespace terracast
