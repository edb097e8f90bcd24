// One tile of a tiled grid (docs/architecture.md, "Tiled grids"): the vertices of up to kTileCells x kTileCells
// cells, with the edge row and column it shares with its neighbours, so that the four corners of each of its
// cells are its own; held as the whole grid's storage would hold them (int16 codes with the grid's offset and
// scale, or float32), with validity bits for vertices and cells.
#pragma once

#include "heightfield/grid_summary.h"
#include "heightfield/height_grid.h"
#include "heightfield/tile_memory.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace terracast {

// Cells along each side of a tile.
inline constexpr int64_t kTileCells = 256;
// Pyramid levels a tile holds (1 to 7); level 8's blocks are the tiles themselves, held by the grid.
inline constexpr int kTileLevels = 7;
static_assert(kTileCells == int64_t(1) << (kTileLevels + 1));

// Where the tiles of a W x H vertex grid lie: tile (ti, tj) holds cells ti * kTileCells .. and the vertices
// from ti * kTileCells to (ti + 1) * kTileCells inclusive, clipped to the grid.
struct TileLayout {
    int64_t width = 0;   // grid vertices along x
    int64_t height = 0;  // grid vertices along y

    int64_t tilesX() const { return (width - 1 + kTileCells - 1) / kTileCells; }
    int64_t tilesY() const { return (height - 1 + kTileCells - 1) / kTileCells; }
    int64_t tileCount() const { return tilesX() * tilesY(); }
    // The tile holding cell (i, j); a vertex on a shared edge belongs to the tiles on both sides, and this gives
    // the one whose cell (i, j) is, clipped so that the last vertex row and column have a tile.
    int64_t tileOfCellX(int64_t i) const { return std::min(i / kTileCells, tilesX() - 1); }
    int64_t tileOfCellY(int64_t j) const { return std::min(j / kTileCells, tilesY() - 1); }
    int64_t key(int64_t ti, int64_t tj) const { return tj * tilesX() + ti; }
    // The first vertex of tile (ti, tj) and its vertex counts.
    int64_t firstVertexX(int64_t ti) const { return ti * kTileCells; }
    int64_t firstVertexY(int64_t tj) const { return tj * kTileCells; }
    int64_t verticesX(int64_t ti) const { return std::min(kTileCells + 1, width - firstVertexX(ti)); }
    int64_t verticesY(int64_t tj) const { return std::min(kTileCells + 1, height - firstVertexY(tj)); }
};

class HeightTile {
public:
    // Encodes the tile's vertices (row-major from its first row; `valid` null when all are valid) in the storage
    // `summary` chose for the whole grid, and builds its pyramid levels (1 to kTileLevels, as far as the grid has
    // them) in the grid's pyramid codes. Throws GridError for a valid height that storage cannot hold exactly,
    // which means the heights are not those the summary was made from.
    HeightTile(const GridSummary& summary, int64_t firstX, int64_t firstY, int64_t verticesX, int64_t verticesY,
               const float* heightsM, const uint8_t* valid);
    // The same from heights in whole metres (a 16-bit integer band without scale or offset, nodata vertices at
    // 0), for a grid whose storage takesWholeMetres: each code is the height less the grid's code offset, the
    // code the constructor above gives the same height as a float, found without conversions.
    HeightTile(const GridSummary& summary, int64_t firstX, int64_t firstY, int64_t verticesX, int64_t verticesY,
               const int16_t* wholeMetres, const uint8_t* valid);
    // Whether a grid summarised so stores one metre per int16 code (the second constructor's condition).
    static bool takesWholeMetres(const GridSummary& summary);

    int64_t firstX() const { return firstX_; }
    int64_t firstY() const { return firstY_; }
    int64_t verticesX() const { return verticesX_; }
    int64_t verticesY() const { return verticesY_; }

    // At grid vertex (i, j), which must lie in the tile.
    // (The traversal kernels' hot loop: indices relative to the tile come from origins worked out once.)
    float at(int64_t i, int64_t j) const {
        const auto k = static_cast<size_t>(j * verticesX_ + i - vertexOrigin_);
        // At one metre per code the decoded height is the integer itself: decodeHeightCode's value exactly.
        if (unitCodes_) return static_cast<float>(int32_t(codes_[k]) + codeOffset_);
        return codes_.empty() ? heightsM_[k] : decodeHeightCode(codes_[k], codeOffset_, codeScale_);
    }
    bool vertexValid(int64_t i, int64_t j) const {
        return valid_.empty() || bit(valid_, j * verticesX_ + i - vertexOrigin_);
    }
    // Cell (i, j) of the grid, which must be one of the tile's.
    bool cellValid(int64_t i, int64_t j) const {
        return cellValid_.empty() || bit(cellValid_, j * (verticesX_ - 1) + i - cellOrigin_);
    }
    // The grid's pyramid codes (HeightGrid::PyramidView) for block (bi, bj) of level k, one of the tile's:
    // 1 <= k <= levels() (2 <= k for the minimum).
    int levels() const { return levels_; }
    int16_t maxCode(int k, int64_t bi, int64_t bj) const { return maxCodes_[blockIndex(k, bi, bj)]; }
    int16_t minCode(int k, int64_t bi, int64_t bj) const { return minCodes_[blockIndex(k, bi, bj)]; }
    // Bytes held, by capacity.
    size_t bytes() const;

private:
    size_t blockIndex(int k, int64_t bi, int64_t bj) const {
        return static_cast<size_t>(levelOrigin_[k - 1] + bj * levelBlocksX_[k - 1] + bi);
    }
    void setValidity(const uint8_t* valid);
    [[noreturn]] void throwNoCode(size_t k, double heightM) const;
    void buildPyramid(const GridSummary& summary);
    static bool bit(const std::vector<uint64_t>& bits, int64_t k) {
        return (bits[static_cast<size_t>(k) >> 6] >> (k & 63)) & 1u;
    }

    int64_t firstX_ = 0;
    int64_t firstY_ = 0;
    int64_t verticesX_ = 0;
    int64_t verticesY_ = 0;
    template <class T>
    using Array = std::vector<T, TileAllocator<T>>;

    Array<int16_t> codes_;   // Int16 storage
    Array<float> heightsM_;  // Float32 storage
    int32_t codeOffset_ = 0;
    double codeScale_ = 1.0;
    std::vector<uint64_t> valid_;      // one bit per vertex; empty when all valid
    std::vector<uint64_t> cellValid_;  // one bit per cell; empty when all valid
    int levels_ = 0;
    Array<int16_t> maxCodes_;  // levels 1..levels_, each row-major, one after the other
    Array<int16_t> minCodes_;  // laid out alike (level 1's entries unused)
    int64_t levelStart_[kTileLevels] = {};
    int64_t levelBlocksX_[kTileLevels] = {};
    // Where grid vertex (i, j) sits: j * verticesX_ + i - vertexOrigin_; cell (i, j): j * (verticesX_ - 1) + i -
    // cellOrigin_; block (bi, bj) of level k: levelOrigin_[k - 1] + bj * levelBlocksX_[k - 1] + bi.
    int64_t vertexOrigin_ = 0;
    int64_t cellOrigin_ = 0;
    int64_t levelOrigin_[kTileLevels] = {};
    bool unitCodes_ = false;  // int16 codes at one metre each
};

}  // namespace terracast
