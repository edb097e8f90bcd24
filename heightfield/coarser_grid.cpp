#include "heightfield/coarser_grid.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace terracast {

HeightGrid coarserGrid(const HeightGrid& grid) {
    if (grid.tiled()) throw GridError("a coarser grid is made from a grid held in memory, not from tiles");
    if (grid.width() < 3 || grid.height() < 3)
        throw GridError("a grid of fewer than 3 x 3 vertices has no coarser grid");
    const int64_t w = grid.cellsX() / 2 + grid.cellsX() % 2 + 1, h = grid.cellsY() / 2 + grid.cellsY() % 2 + 1;
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

}  // namespace terracast
