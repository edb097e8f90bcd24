// A tile source for tests: the tiles of a grid held whole, cut on request into a cache of a given budget.
#pragma once

#include "heightfield/grid_summary.h"
#include "heightfield/height_grid.h"
#include "heightfield/height_tile.h"
#include "heightfield/tile_cache.h"

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace terracast::testing {

// The tiles of a whole grid, cut on request into a cache of `budget` bytes: a tile source that shares no code
// with the grid's own pyramid or storage choice (the summary comes from GridSummaryBuilder, the tiles from
// HeightTile).
class CutTiles : public TileSource {
public:
    // With `wholeMetres`, tiles are made from 16-bit heights as a 16-bit DEM in metres makes them.
    CutTiles(const HeightGrid& whole, size_t budget, bool wholeMetres = false)
        : wholeMetres_(wholeMetres), heights_(whole.copyHeights()), valid_(size_t(whole.width() * whole.height()), 1),
          layout_{whole.width(), whole.height()},
          cache_(budget, [this](int64_t key) { return cut(key); }, [](const HeightTile& t) { return t.bytes(); }) {
        for (int64_t j = 0; j < whole.height(); ++j)
            for (int64_t i = 0; i < whole.width(); ++i) valid_[size_t(j * whole.width() + i)] = whole.vertexValid(i, j);
        // Scale hint 0.1: the whole grids built below with tenths get the same hint.
        GridSummaryBuilder builder(whole.width(), whole.height(), 0.1);
        // In bands of 37 rows, which tile edges do not align with.
        for (int64_t j0 = 0; j0 < whole.height(); j0 += 37) {
            const int64_t rows = std::min<int64_t>(37, whole.height() - j0);
            builder.addRows(j0, rows, heights_.data() + j0 * whole.width(), valid_.data() + j0 * whole.width());
        }
        summary_ = builder.finish();
    }
    std::shared_ptr<const HeightTile> tile(int64_t ti, int64_t tj) const override {
        return cache_.get(layout_.key(ti, tj));
    }
    TileCacheStats cacheStats() const override { return cache_.stats(); }
    size_t cacheBudgetBytes() const override { return cache_.budgetBytes(); }
    const GridSummary& summary() const { return summary_; }

private:
    std::shared_ptr<const HeightTile> cut(int64_t key) const {
        const int64_t ti = key % layout_.tilesX(), tj = key / layout_.tilesX();
        const int64_t x0 = layout_.firstVertexX(ti), y0 = layout_.firstVertexY(tj);
        const int64_t w = layout_.verticesX(ti), h = layout_.verticesY(tj);
        std::vector<float> z(size_t(w * h));
        std::vector<uint8_t> ok(z.size());
        for (int64_t j = 0; j < h; ++j)
            for (int64_t i = 0; i < w; ++i) {
                z[size_t(j * w + i)] = heights_[size_t((y0 + j) * layout_.width + x0 + i)];
                ok[size_t(j * w + i)] = valid_[size_t((y0 + j) * layout_.width + x0 + i)];
            }
        if (wholeMetres_) {
            std::vector<int16_t> metres(z.size());
            for (size_t k = 0; k < z.size(); ++k) metres[k] = ok[k] ? int16_t(z[k]) : int16_t{0};
            return std::make_shared<const HeightTile>(summary_, x0, y0, w, h, metres.data(), ok.data());
        }
        return std::make_shared<const HeightTile>(summary_, x0, y0, w, h, z.data(), ok.data());
    }

    bool wholeMetres_ = false;
    std::vector<float> heights_;
    std::vector<uint8_t> valid_;
    TileLayout layout_;
    GridSummary summary_;
    mutable TileCache<HeightTile> cache_;
};

}  // namespace terracast::testing
