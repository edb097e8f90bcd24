// Coarser grids for a level of detail (docs/architecture.md, "Level of detail"): the same terrain with every
// other vertex, cells twice as wide.
#pragma once

#include "heightfield/height_grid.h"

namespace terracast {

// The grid of vertices (2i, 2j) of `grid` (a grid held in memory), with cells twice its cells' size: vertex
// (i, j) of the result is vertex (min(2i, W - 1), min(2j, H - 1)) of the source, height and validity, so that
// an odd count of cells gets a last coarse cell that reaches half a coarse cell past the source's edge (its far
// vertices are the edge's). The storage is chosen as for any grid (int16 codes when lossless). Throws
// GridError for a tiled grid or one of fewer than 3 x 3 vertices.
HeightGrid coarserGrid(const HeightGrid& grid);

}  // namespace terracast
