// The sides of a cell a ray segment enters and leaves it through, as the cell walk reports them.
//
// The walk itself (traversal_kernels.h, interleaved with the maximum pyramid) is the 2D digital differential
// analyzer of Amanatides & Woo 1987 ("A Fast Voxel Traversal Algorithm for Ray Tracing"), applied to height
// fields as in Musgrave 1988. The next boundary crossing is recomputed from the integer cell index,
// t = (boundary - o) / d, instead of accumulating t increments, so rounding does not drift over thousands of
// cells. tests/heightfield/dda_test.cpp checks it against exact clipping.
#pragma once

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

}  // namespace terracast
