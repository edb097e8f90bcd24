// Level 1 of the min/max pyramid from the vertices, shared by a grid held whole (height_grid.cpp) and by the
// tiles of a grid held as tiles (height_tile.cpp), so that both bound every block alike
// (docs/architecture.md, "Pyramid").
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

namespace terracast {

// out[b] = the larger (highest) or smaller of in[2b] and in[2b + 1], for b < pairs. Written as a loop over
// pairs, the compiler leaves it scalar; with GCC's vector extensions, eight pairs at a time: the even and the odd
// values of sixteen gathered by two shuffles (which SSE2 does with shifts and a pack), then their extremes.
inline void pairExtremes(const int16_t* in, int64_t pairs, bool highest, int16_t* out) {
    int64_t b = 0;
#if defined(__GNUC__) && !defined(__clang__)
    using Lanes = int16_t __attribute__((vector_size(16)));
    constexpr Lanes kEven = {0, 2, 4, 6, 8, 10, 12, 14}, kOdd = {1, 3, 5, 7, 9, 11, 13, 15};
    for (; b + 8 <= pairs; b += 8) {
        Lanes lo, hi;
        std::memcpy(&lo, in + 2 * b, sizeof lo);
        std::memcpy(&hi, in + 2 * b + 8, sizeof hi);
        const Lanes even = __builtin_shuffle(lo, hi, kEven), odd = __builtin_shuffle(lo, hi, kOdd);
        const Lanes pick = highest ? (even > odd ? even : odd) : (even < odd ? even : odd);
        std::memcpy(out + b, &pick, sizeof pick);
    }
#endif
    for (; b < pairs; ++b)
        out[b] = highest ? std::max(in[2 * b], in[2 * b + 1]) : std::min(in[2 * b], in[2 * b + 1]);
}

// Block rows [b0, b1) of level 1 over a grid of `width` vertices per row and cellsX x cellsY cells. Block
// (bi, bj) covers cells 2bi..2bi+1 x 2bj..2bj+1, that is vertices 2bi..2bi+2 x 2bj..2bj+2 (clipped to the
// grid), and bounds those of them that are valid (`validBits`, one bit per vertex at k = j * width + i; empty
// when all are): a hole cell next to a valid vertex is still bounded by it, which the traversal's corner
// handling relies on. `get(k)` is vertex k's value, of type T; `highCode(h)` and `lowCode(l)` give a block's
// codes from its extremes, which are noneHigh and noneLow for a block without a valid vertex. For T = int16_t the
// values are codes already and their extremes are stored as they are (highCode and lowCode are not called). Each block row
// first takes the column extremes of its three vertex rows (a loop over contiguous values the compiler
// vectorises), then the extremes of three columns per block. Block row bj is stored at row bj - b0 of high1 and
// low1 (bx1 = (cellsX + 1) / 2 codes per row).
template <class T, class Get, class HighCode, class LowCode>
void pyramidLevelOneRows(int64_t width, int64_t cellsX, int64_t cellsY, const std::vector<uint64_t>& validBits,
                         int64_t b0, int64_t b1, Get get, T noneHigh, T noneLow, HighCode highCode, LowCode lowCode,
                         int16_t* high1, int16_t* low1) {
    const int64_t bx1 = (cellsX + 1) / 2;
    // Column extremes, with one more column of `none` past the last vertex so that a last block holding only
    // two vertex columns reads its third as `none`; then extremes of adjacent columns, so that a block's three
    // columns are two neighbouring pairs.
    std::vector<T> hi(static_cast<size_t>(width + 1)), lo(static_cast<size_t>(width + 1));
    std::vector<T> hi2(static_cast<size_t>(2 * bx1)), lo2(static_cast<size_t>(2 * bx1));
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
        // Block bi covers columns 2bi .. 2bi + 2: pairs (2bi, 2bi + 1) and (2bi + 1, 2bi + 2).
        {
            const T* __restrict h = hi.data();
            const T* __restrict l = lo.data();
            T* __restrict h2 = hi2.data();
            T* __restrict l2 = lo2.data();
            for (int64_t i = 0; i < 2 * bx1; ++i) {
                h2[i] = std::max(h[i], h[i + 1]);
                l2[i] = std::min(l[i], l[i + 1]);
            }
        }
        int16_t* high = high1 + (bj - b0) * bx1;
        int16_t* low = low1 + (bj - b0) * bx1;
        if constexpr (std::is_same_v<T, int16_t>) {
            // Codes are their own pyramid codes (the caller's highCode and lowCode leave them as they are).
            pairExtremes(hi2.data(), bx1, true, high);
            pairExtremes(lo2.data(), bx1, false, low);
            continue;
        }
        for (int64_t bi = 0; bi < bx1; ++bi) {
            high[bi] = highCode(std::max(hi2[size_t(2 * bi)], hi2[size_t(2 * bi + 1)]));
            low[bi] = lowCode(std::min(lo2[size_t(2 * bi)], lo2[size_t(2 * bi + 1)]));
        }
    }
}

}  // namespace terracast
