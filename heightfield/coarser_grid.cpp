#include "heightfield/coarser_grid.h"
#include "heightfield/large_buffer.h"

#include "heightfield/height_tile.h"

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace terracast {

HeightGrid coarserGrid(const HeightGrid& grid) {
    if (grid.tiled()) throw GridError("a coarser grid is made from a grid held in memory, not from tiles");
    if (grid.width() < 3 || grid.height() < 3)
        throw GridError("a grid of fewer than 3 x 3 vertices has no coarser grid");
    const int64_t w = coarserVertexCount(grid.width()), h = coarserVertexCount(grid.height());
    std::vector<uint8_t> valid;
    bool holes = false;
    for (int64_t j = 0; j < h && !holes; ++j)
        for (int64_t i = 0; i < w; ++i)
            if (!grid.vertexValid(std::min(2 * i, grid.width() - 1), std::min(2 * j, grid.height() - 1))) {
                holes = true;
                break;
            }
    if (holes) valid.assign(static_cast<size_t>(w * h), 0);
    // Int16 codes stay codes: no float copy (the grid then re-bases them as it would the heights).
    if (const int16_t* codes = grid.int16Codes()) {
        std::vector<int16_t> coarse(static_cast<size_t>(w * h));
        for (int64_t j = 0; j < h; ++j) {
            const int64_t sj = std::min(2 * j, grid.height() - 1);
            const int16_t* row = codes + sj * grid.width();
            int16_t* out = coarse.data() + j * w;
            for (int64_t i = 0; i < w; ++i) out[i] = row[std::min(2 * i, grid.width() - 1)];
            if (holes)
                for (int64_t i = 0; i < w; ++i)
                    valid[size_t(j * w + i)] = grid.vertexValid(std::min(2 * i, grid.width() - 1), sj) ? 1 : 0;
        }
        return HeightGrid(w, h, 2.0 * grid.cellSizeXM(), 2.0 * grid.cellSizeYM(), std::move(coarse), grid.codeOffset(),
                          grid.codeScale(), grid.codeScale(), std::move(valid));
    }
    std::vector<float> heights(static_cast<size_t>(w * h));
    for (int64_t j = 0; j < h; ++j) {
        const int64_t sj = std::min(2 * j, grid.height() - 1);
        for (int64_t i = 0; i < w; ++i) {
            const int64_t si = std::min(2 * i, grid.width() - 1);
            const auto k = static_cast<size_t>(j * w + i);
            const bool ok = grid.vertexValid(si, sj);
            heights[k] = ok ? grid.at(si, sj) : 0.0f;
            if (holes) valid[k] = ok ? 1 : 0;
        }
    }
    return HeightGrid(w, h, 2.0 * grid.cellSizeXM(), 2.0 * grid.cellSizeYM(), std::move(heights), std::move(valid),
                      StoragePolicy::Auto, grid.storage() == HeightStorage::Int16 ? grid.codeScale() : 0.0);
}

std::vector<int64_t> coarseVertexIndices(int64_t vertices, int levels) {
    std::vector<int64_t> index(static_cast<size_t>(std::max<int64_t>(vertices, 0)));
    for (size_t k = 0; k < index.size(); ++k) index[k] = int64_t(k);
    for (int l = 0; l < levels; ++l) {
        const int64_t n = int64_t(index.size());
        if (n < 3) throw GridError("a grid of fewer than 3 x 3 vertices has no coarser grid");
        const int64_t coarse = coarserVertexCount(n);
        std::vector<int64_t> next(static_cast<size_t>(coarse));
        for (int64_t i = 0; i < coarse; ++i) next[size_t(i)] = index[size_t(std::min(2 * i, n - 1))];
        index = std::move(next);
    }
    return index;
}

double coarseGridBytes(int64_t width, int64_t height) {
    // Float heights (4 bytes), vertex and cell flags (2 bits) and the two pyramids (a third of a code each).
    return double(width) * double(height) * (4.0 + 0.25 + 1.4);
}

HeightGrid coarserGrid(const HeightGrid& grid, int levels, int threads) {
    if (levels < 1) throw GridError("a coarser grid is at least one level coarser");
    const std::vector<int64_t> xs = coarseVertexIndices(grid.width(), levels),
                               ys = coarseVertexIndices(grid.height(), levels);
    const int64_t w = int64_t(xs.size()), h = int64_t(ys.size());
    const double scale = double(int64_t(1) << levels);
    const auto make = [&](std::vector<float> heights, std::vector<uint8_t> valid) {
        if (std::all_of(valid.begin(), valid.end(), [](uint8_t v) { return v != 0; })) valid.clear();
        return HeightGrid(w, h, scale * grid.cellSizeXM(), scale * grid.cellSizeYM(), std::move(heights),
                          std::move(valid), StoragePolicy::Auto,
                          grid.storage() == HeightStorage::Int16 ? grid.codeScale() : 0.0);
    };
    // A tiled grid's source may have kept this level from an earlier run.
    if (grid.tiled())
        if (auto kept = grid.tileSource()->keptCoarseHeights(levels, w, h);
            kept && kept->width == w && kept->height == h && kept->heightsM.size() == size_t(w * h) &&
            kept->valid.size() == size_t(w * h))
            return make(std::move(kept->heightsM), std::move(kept->valid));
    std::vector<float> heights(static_cast<size_t>(w * h), 0.0f);
    std::vector<uint8_t> valid(heights.size(), 1);
    // Fills the coarse vertices [i0, i1) x [j0, j1) from `at` and `ok`, readers of the source's vertices.
    auto fill = [&](int64_t i0, int64_t i1, int64_t j0, int64_t j1, const auto& at, const auto& ok) {
        for (int64_t j = j0; j < j1; ++j)
            for (int64_t i = i0; i < i1; ++i) {
                const auto k = static_cast<size_t>(j * w + i);
                if (ok(xs[size_t(i)], ys[size_t(j)])) heights[k] = at(xs[size_t(i)], ys[size_t(j)]);
                else valid[k] = 0;
            }
    };
    if (!grid.tiled()) {
        fill(0, w, 0, h, [&](int64_t a, int64_t b) { return grid.at(a, b); },
             [&](int64_t a, int64_t b) { return grid.vertexValid(a, b); });
    } else {
        // Tile by tile: the coarse vertices whose source vertex lies in tile (ti, tj) (a vertex on a tile border
        // is read from the tile after it, or from the last tile) form a rectangle, each tile read once.
        const TileLayout layout{grid.width(), grid.height()};
        auto spans = [](const std::vector<int64_t>& index, int64_t tiles, int64_t cells) {
            std::vector<int64_t> first(static_cast<size_t>(tiles + 1), int64_t(index.size()));
            for (int64_t k = int64_t(index.size()) - 1; k >= 0; --k)
                first[size_t(std::min(index[size_t(k)], cells - 1) / kTileCells)] = k;
            for (int64_t t = tiles - 1; t >= 0; --t) first[size_t(t)] = std::min(first[size_t(t)], first[size_t(t + 1)]);
            return first;  // tile t's coarse vertices: [first[t], first[t + 1])
        };
        const std::vector<int64_t> spanX = spans(xs, layout.tilesX(), grid.cellsX()),
                                   spanY = spans(ys, layout.tilesY(), grid.cellsY());
        const int64_t tiles = layout.tilesX() * layout.tilesY();
        std::atomic<int64_t> next{0};
        std::exception_ptr failure;
        std::mutex failureMutex;
        auto work = [&] {
            try {
                for (int64_t t = next++; t < tiles; t = next++) {
                    const int64_t ti = t % layout.tilesX(), tj = t / layout.tilesX();
                    const int64_t i0 = spanX[size_t(ti)], i1 = spanX[size_t(ti + 1)];
                    const int64_t j0 = spanY[size_t(tj)], j1 = spanY[size_t(tj + 1)];
                    if (i0 >= i1 || j0 >= j1) continue;  // a tile none of whose vertices is kept
                    // Straight from the source: each tile is used once, so a thread's memo of recent tiles
                    // (HeightGrid::tileOfCell) would only hold tiles beyond the cache's budget.
                    const std::shared_ptr<const HeightTile> tile = grid.tileSource()->tile(ti, tj);
                    fill(i0, i1, j0, j1, [&](int64_t a, int64_t b) { return tile->at(a, b); },
                         [&](int64_t a, int64_t b) { return tile->vertexValid(a, b); });
                }
            } catch (...) {
                std::lock_guard lock(failureMutex);
                if (!failure) failure = std::current_exception();
                next = tiles;
            }
        };
        const int64_t count = std::clamp<int64_t>(
            threads > 0 ? threads : int64_t(arrayPassThreads()), 1, tiles);
        std::vector<std::thread> pool;
        try {
            for (int64_t k = 1; k < count; ++k) pool.emplace_back(work);
        } catch (...) {
            // No more threads to be had: those started and this one do the work.
        }
        work();
        for (auto& thread : pool) thread.join();
        if (failure) std::rethrow_exception(failure);
        CoarseHeights made{w, h, std::move(heights), std::move(valid)};
        grid.tileSource()->keepCoarseHeights(levels, made);
        return make(std::move(made.heightsM), std::move(made.valid));
    }
    return make(std::move(heights), std::move(valid));
}

}  // namespace terracast
