// What a grid read a band of rows at a time must know before its first ray, gathered in one pass that holds one
// row of flags: the height range, the nodata and valid-cell counts, and the storage a whole HeightGrid of the same
// heights would choose (docs/architecture.md, "Tiled grids").
#pragma once

#include "heightfield/height_grid.h"

#include <cstdint>
#include <vector>

namespace terracast {

struct GridSummary {
    int64_t width = 0;                 // vertices along x
    int64_t height = 0;                // vertices along y
    float minHeightM = 0.0f;           // over valid vertices; both 0 when there is none
    float maxHeightM = 0.0f;
    int64_t nodataVertices = 0;
    int64_t validCells = 0;            // cells with four valid corners
    HeightStorage storage = HeightStorage::Float32;
    int32_t codeOffset = 0;            // Int16 storage: height = (code + codeOffset) * codeScale
    double codeScale = 1.0;
    PyramidCoding pyramid;             // the min/max pyramids' codes, as a whole grid would choose them
    // Per tile of TileLayout (height_tile.h), row-major: the pyramid codes bounding its valid vertices from above
    // and below (PyramidCoding::kNoMax and kNoMin for a tile without one). They are the pyramid level whose
    // blocks are the tiles.
    std::vector<int16_t> tileMaxCodes;
    std::vector<int16_t> tileMinCodes;
};

class GridSummaryBuilder {
public:
    // `scaleHint` as HeightGrid takes it: metres per stored unit of the source, 0 for none.
    GridSummaryBuilder(int64_t width, int64_t height, double scaleHint = 0.0);

    // Rows j0 .. j0 + rows - 1, every column, row-major, in order from row 0. `valid` holds a flag per vertex,
    // or is null when all are valid. Throws GridError for a non-finite valid height, std::invalid_argument
    // for rows out of order.
    void addRows(int64_t j0, int64_t rows, const float* heightsM, const uint8_t* valid);

    // The summary, once every row has been added (std::logic_error before).
    GridSummary finish() const;

private:
    int64_t width_ = 0;
    int64_t height_ = 0;
    int64_t nextRow_ = 0;
    std::vector<uint8_t> previousValid_;  // row nextRow_ - 1
    std::vector<double> scales_;          // int16 scales to try, in HeightGrid's order
    std::vector<char> roundTrips_;        // per scale: every valid height so far round-trips
    float lo_;
    float hi_;
    int64_t nodata_ = 0;
    int64_t validCells_ = 0;
    int64_t tilesX_ = 0;
    std::vector<float> tileHigh_;  // per tile: the highest and lowest valid height so far
    std::vector<float> tileLow_;
};

}  // namespace terracast
