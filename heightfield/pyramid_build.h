// Level 1 of the min/max pyramid from the vertices, shared by a grid held whole (height_grid.cpp) and by the
// tiles of a grid held as tiles (height_tile.cpp), so that both bound every block alike
// (docs/architecture.md, "Pyramid").
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace terracast {

// Block rows [b0, b1) of level 1 over a grid of `width` vertices per row and cellsX x cellsY cells. Block
// (bi, bj) covers cells 2bi..2bi+1 x 2bj..2bj+1, that is vertices 2bi..2bi+2 x 2bj..2bj+2 (clipped to the
// grid), and bounds those of them that are valid (`validBits`, one bit per vertex at k = j * width + i; empty
// when all are): a hole cell next to a valid vertex is still bounded by it, which the traversal's corner
// handling relies on. `get(k)` is vertex k's value, of type T; `highCode(h)` and `lowCode(l)` give a block's
// codes from its extremes, which are noneHigh and noneLow for a block without a valid vertex. Each block row
// first takes the column extremes of its three vertex rows (a loop over contiguous values the compiler
// vectorises), then the extremes of three columns per block.
template <class T, class Get, class HighCode, class LowCode>
void pyramidLevelOneRows(int64_t width, int64_t cellsX, int64_t cellsY, const std::vector<uint64_t>& validBits,
                         int64_t b0, int64_t b1, Get get, T noneHigh, T noneLow, HighCode highCode, LowCode lowCode,
                         int16_t* high1, int16_t* low1) {
    const int64_t bx1 = (cellsX + 1) / 2;
    std::vector<T> hi(static_cast<size_t>(width)), lo(static_cast<size_t>(width));
    for (int64_t bj = b0; bj < b1; ++bj) {
        std::fill(hi.begin(), hi.end(), noneHigh);
        std::fill(lo.begin(), lo.end(), noneLow);
        for (int64_t j = 2 * bj; j <= std::min(2 * bj + 2, cellsY); ++j) {
            const int64_t row = j * width;
            if (validBits.empty()) {
                for (int64_t i = 0; i < width; ++i) {
                    const T z = get(row + i);
                    hi[size_t(i)] = std::max(hi[size_t(i)], z);
                    lo[size_t(i)] = std::min(lo[size_t(i)], z);
                }
            } else {
                for (int64_t i = 0; i < width; ++i) {
                    const int64_t k = row + i;
                    if ((validBits[size_t(k) >> 6] >> (k & 63)) & 1u) {
                        const T z = get(k);
                        hi[size_t(i)] = std::max(hi[size_t(i)], z);
                        lo[size_t(i)] = std::min(lo[size_t(i)], z);
                    }
                }
            }
        }
        for (int64_t bi = 0; bi < bx1; ++bi) {
            T h = noneHigh, l = noneLow;
            for (int64_t i = 2 * bi; i <= std::min(2 * bi + 2, cellsX); ++i) {
                h = std::max(h, hi[size_t(i)]);
                l = std::min(l, lo[size_t(i)]);
            }
            high1[size_t(bj * bx1 + bi)] = highCode(h);
            low1[size_t(bj * bx1 + bi)] = lowCode(l);
        }
    }
}

}  // namespace terracast
