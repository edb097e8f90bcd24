// Comparing two grids that must hold the same thing: their pyramids, block by block.
#pragma once

#include "heightfield/height_grid.h"

#include <cstdint>

namespace terracast::testing {

// The pyramid blocks whose maximum or minimum differ between `a` and `b` (which must have the same levels).
inline int64_t pyramidDifferences(const HeightGrid& a, const HeightGrid& b) {
    int64_t differ = 0;
    for (int k = 1; k <= a.pyramidLevels(); ++k)
        for (int64_t bj = 0; bj < a.pyramidBlocksY(k); ++bj)
            for (int64_t bi = 0; bi < a.pyramidBlocksX(k); ++bi)
                differ += a.blockMaxM(k, bi, bj) != b.blockMaxM(k, bi, bj) ||
                          a.blockMinM(k, bi, bj) != b.blockMinM(k, bi, bj);
    return differ;
}

}  // namespace terracast::testing
