// The checks every whole-raster loader makes (loaders/dem_loader.cpp for GDAL rasters, png_height_map.cpp for
// PNG height maps): the raster's size against the memory limit, the heights' range, and the grid built from them.
// Internal to the loaders.
#pragma once

#include "heightfield/height_grid.h"
#include "tracer/core/errors.h"

#include <cstdint>
#include <string>
#include <vector>

namespace terracast::dem_checks {

// Heights farther than this from sea level (1000 km; the Earth's relief spans 20 km) are refused as a wrong
// unit, scale or undeclared nodata: tracing them would lose all float precision on real terrain.
constexpr double kMaxAbsHeightM = 1.0e6;
// The largest height a vertical exaggeration may make (metres): far beyond any terrain, yet squares and products
// of heights stay finite and precise enough in double.
constexpr double kMaxExaggeratedHeightM = 1.0e12;

// A raster too large to hold whole, with what the process held and the limit (loadDem holds it as tiles).
struct RasterTooLarge : InputError {
    RasterTooLarge(const std::string& message, double held, double limit)
        : InputError(message), heldBytes(held), limitBytes(limit) {}
    double heldBytes;
    double limitBytes;
};

// Rejects rasters without a cell, and rasters too large to hold, before anything is allocated (the second
// check only for a `maxBytes` of 0, the default limit, or more; a negative `maxBytes` skips it).
void checkRasterSize(const std::string& path, int64_t width, int64_t height, double maxBytes);

// Builds the grid, naming the file in any GridError, and refuses grids without a cell to trace.
// `metresPerUnit` is the source's vertical unit, offered to the grid as a candidate scale for int16 storage.
HeightGrid makeGrid(const std::string& path, int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                    std::vector<float> heightsM, std::vector<uint8_t> valid, double metresPerUnit);
// The same from int16 codes of integer samples (HeightGrid's code constructor), `metresPerUnit` being the codes'
// own scale; `valid` as above.
HeightGrid makeGrid(const std::string& path, int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                    std::vector<int16_t> codes, int32_t codeOffset, double metresPerUnit, std::vector<uint8_t> valid = {});

// Reports a non-finite or out-of-range height at raster (column, row).
[[noreturn]] void throwBadHeight(const std::string& path, int64_t column, int64_t row, double heightM);

}  // namespace terracast::dem_checks
