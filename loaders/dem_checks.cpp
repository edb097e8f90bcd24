#include "loaders/dem_checks.h"

#include "tracer/core/resources.h"
#include "tracer/core/text.h"

#include <fmt/format.h>

#include <cmath>
#include <utility>

namespace terracast::dem_checks {
namespace {

// Per vertex while loading and tracing: the height, the nodata flag, the cell flag, the pyramids (under a
// third of a float per cell) and the reader's float copy of the raster row data.
constexpr double kBytesPerVertex = sizeof(float) + 2 * sizeof(uint8_t) + sizeof(float) / 3.0 + sizeof(float);
// Cell sizes outside this range come from a broken geotransform or unit: the extent of the grid would
// overflow, or its cells vanish, in the float arithmetic of tracing.
constexpr double kMinCellSizeM = 1.0e-6;
constexpr double kMaxCellSizeM = 1.0e6;
// The largest raster held even as tiles: ten times the largest national LiDAR DEMs. Opening one streams every
// sample once, which takes hours beyond this.
constexpr double kMaxRasterSamples = 0x1p39;

}  // namespace

void checkRasterSize(const std::string& path, int64_t width, int64_t height, double maxBytes) {
    if (width <= 0 || height <= 0)
        throw InputError(fmt::format("{}: raster is {} x {}, with no sample to trace", path, width, height));
    if (width < 2 || height < 2)
        throw InputError(fmt::format("{}: {} x {} raster has no cell to trace (need at least 2 x 2)", path, width,
                                     height));
    if (double(width) * double(height) > kMaxRasterSamples)
        throw InputError(fmt::format("{}: {} x {} raster holds {:.3g} samples, more than the {:.3g} (2^39) terracast "
                                     "traces, even as tiles",
                                     path, width, height, double(width) * double(height), kMaxRasterSamples));
    if (maxBytes < 0.0) return;  // a window reader, which never holds the raster
    // What the process holds already (libraries, the image codec when it reads a PNG) counts against the limit.
    const double held = currentResidentBytes();
    const double bytes = static_cast<double>(width) * static_cast<double>(height) * kBytesPerVertex;
    const double limit = memoryLimitBytes(maxBytes);
    if (held + bytes > limit)
        throw RasterTooLarge(fmt::format("{}: {} x {} raster needs about {} to load and trace ({} held already), "
                                         "more than the {} limit (--max-memory)",
                                         path, width, height, humanBytes(bytes), humanBytes(held), humanBytes(limit)),
                             held, limit);
}

namespace {

// makeGrid around one of HeightGrid's constructors, `build`.
template <class Build>
HeightGrid checkedGrid(const std::string& path, int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                       Build build) {
    const auto sane = [](double m) { return m >= kMinCellSizeM && m <= kMaxCellSizeM; };
    if (!sane(cellSizeXM) || !sane(cellSizeYM))
        throw InputError(fmt::format("{}: cell size {:g} x {:g} m, expected {:g} m to {:g} m (a wrong geotransform or "
                                     "unit?)",
                                     path, cellSizeXM, cellSizeYM, kMinCellSizeM, kMaxCellSizeM));
    HeightGrid grid;
    try {
        grid = build();
    } catch (const GridError& e) {
        throw InputError(path + ": " + e.what());
    }
    if (grid.nodataVertexCount() == width * height) throw InputError(path + ": every vertex is nodata");
    if (grid.validCellCount() == 0)
        throw InputError(fmt::format("{}: no cell has four valid corners ({} of {} vertices are nodata)", path,
                                     grid.nodataVertexCount(), width * height));
    return grid;
}

}  // namespace

HeightGrid makeGrid(const std::string& path, int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                    std::vector<float> heightsM, std::vector<uint8_t> valid, double metresPerUnit) {
    return checkedGrid(path, width, height, cellSizeXM, cellSizeYM, [&] {
        return HeightGrid(width, height, cellSizeXM, cellSizeYM, std::move(heightsM), std::move(valid),
                          StoragePolicy::Auto, metresPerUnit);
    });
}

HeightGrid makeGrid(const std::string& path, int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                    std::vector<int16_t> codes, int32_t codeOffset, double metresPerUnit, std::vector<uint8_t> valid) {
    return checkedGrid(path, width, height, cellSizeXM, cellSizeYM, [&] {
        return HeightGrid(width, height, cellSizeXM, cellSizeYM, std::move(codes), codeOffset, metresPerUnit,
                          metresPerUnit, std::move(valid));
    });
}

[[noreturn]] void throwBadHeight(const std::string& path, int64_t column, int64_t row, double heightM) {
    if (std::isnan(heightM))
        throw InputError(fmt::format("{}: height at column {}, row {} is NaN (not declared as nodata)", path, column,
                                     row));
    if (std::isinf(heightM))
        throw InputError(fmt::format("{}: height at column {}, row {} is {}infinite (not declared as nodata)", path,
                                     column, row, heightM < 0 ? "minus " : ""));
    throw InputError(fmt::format("{}: height at column {}, row {} is {:g} m, expected within {:g} m of sea level "
                                 "(wrong unit or scale, or an undeclared nodata value?)",
                                 path, column, row, heightM, kMaxAbsHeightM));
}

}  // namespace terracast::dem_checks
