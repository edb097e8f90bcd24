// Coarser grids for a level of detail (docs/architecture.md, "Level of detail"): the same terrain with every
// other vertex, cells twice as wide.
#pragma once

#include "heightfield/height_grid.h"

#include <cstdint>
#include <vector>

namespace terracast {

// The grid of vertices (2i, 2j) of `grid` (a grid held in memory), with cells twice its cells' size: vertex
// (i, j) of the result is vertex (min(2i, W - 1), min(2j, H - 1)) of the source, height and validity, so that
// an odd count of cells gets a last coarse cell that reaches half a coarse cell past the source's edge (its far
// vertices are the edge's). The storage is chosen as for any grid (int16 codes when lossless). Throws
// GridError for a tiled grid or one of fewer than 3 x 3 vertices.
HeightGrid coarserGrid(const HeightGrid& grid);

// The grid `levels` (>= 1) steps coarser: the heights and validity of coarserGrid applied `levels` times, made
// in one pass from a grid held in memory or as tiles. A tiled grid's tiles are each read once, on `threads`
// threads (0 = all cores), and only the coarse grid is held; its source is offered the result to keep, and one
// it kept from an earlier run is taken instead of reading the tiles (TileSource::keptCoarseHeights). Throws GridError when a level on the way would have
// fewer than 3 x 3 vertices to start from, and whatever a tile's read throws.
HeightGrid coarserGrid(const HeightGrid& grid, int levels, int threads = 0);

// How many vertices an axis of `vertices` (3 or more) has one level coarser: half its cells, rounded up, plus one.
inline int64_t coarserVertexCount(int64_t vertices) { return (vertices - 1) / 2 + (vertices - 1) % 2 + 1; }

// The vertices of one axis of `vertices` vertices that the grid `levels` steps coarser keeps: entry i is the
// source index of its vertex i (coarserGrid's clamping applied at every step).
std::vector<int64_t> coarseVertexIndices(int64_t vertices, int levels);

// Bytes a grid of `width` x `height` vertices holds at most (float heights, flags and pyramids): for choosing,
// before making one, a coarse level that fits.
double coarseGridBytes(int64_t width, int64_t height);

}  // namespace terracast
