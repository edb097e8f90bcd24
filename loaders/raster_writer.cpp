// Writing rasters on a DEM's grid as DEFLATE-compressed GeoTIFF through GDAL. Rows are written north-up
// (file row 0 is the northmost raster row) with a pixel-is-area geotransform whose pixel centres fall on the
// grid's vertices, so the file overlays the source DEM exactly.
#include "loaders/image_io.h"
#include "loaders/loader_support.h"
#include "loaders/raster_writer.h"

#include "tracer/core/errors.h"

#include <cpl_error.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <fmt/format.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace terracast {
namespace {

using namespace loader_support;

namespace fs = std::filesystem;

// A Byte sample: rounded to the nearest integer and clamped to 0..255 (NaN becomes 0).
uint8_t toByte(float value) {
    if (!(value > 0.0f)) return 0;
    if (value >= 255.0f) return 255;
    return static_cast<uint8_t>(std::lround(value));
}

// Converts raster rows [row0, row0 + rows) of file order (north-up) into `strip`, band-interleaved by pixel.
template <typename Sample>
void fillStrip(const GridRaster& raster, int64_t fileRow0, int64_t rows, std::vector<Sample>& strip) {
    const auto rowValues = static_cast<size_t>(raster.width) * static_cast<size_t>(raster.bands);
    for (int64_t r = 0; r < rows; ++r) {
        const int64_t j = raster.height - 1 - (fileRow0 + r);  // raster row 0 is the southmost
        const float* source = raster.values.data() + static_cast<size_t>(j) * rowValues;
        Sample* target = strip.data() + static_cast<size_t>(r) * rowValues;
        for (size_t k = 0; k < rowValues; ++k) {
            if constexpr (std::is_same_v<Sample, uint8_t>)
                target[k] = toByte(source[k]);
            else
                target[k] = source[k];
        }
    }
}

// Writes every row of `raster` into `dataset`, a strip of rows at a time. Returns false on a GDAL failure.
template <typename Sample>
bool writeRows(GDALDataset& dataset, const GridRaster& raster, GDALDataType type) {
    const int64_t rowValues = raster.width * raster.bands;
    const int64_t rowsPerStrip = std::max<int64_t>(1, (int64_t{1} << 22) / (rowValues * int64_t{sizeof(Sample)}));
    std::vector<Sample> strip(static_cast<size_t>(std::min(rowsPerStrip, raster.height) * rowValues));
    const auto pixelSpace = static_cast<GSpacing>(sizeof(Sample)) * raster.bands;
    for (int64_t row0 = 0; row0 < raster.height; row0 += rowsPerStrip) {
        const int64_t rows = std::min(rowsPerStrip, raster.height - row0);
        fillStrip(raster, row0, rows, strip);
        if (dataset.RasterIO(GF_Write, 0, static_cast<int>(row0), static_cast<int>(raster.width),
                             static_cast<int>(rows), strip.data(), static_cast<int>(raster.width),
                             static_cast<int>(rows), type, raster.bands, nullptr, pixelSpace,
                             pixelSpace * raster.width, static_cast<GSpacing>(sizeof(Sample)), nullptr) != CE_None)
            return false;
    }
    return true;
}

}  // namespace

void writeGeoTiff(const std::string& path, const GridRaster& raster, RasterType type, const GeoReference& geo,
                  double originX, double originY, double pixelSizeX, double pixelSizeY) {
    if (raster.width < 1 || raster.height < 1 || raster.bands < 1 ||
        raster.values.size() != static_cast<size_t>(raster.width) * static_cast<size_t>(raster.height) *
                                    static_cast<size_t>(raster.bands))
        throw std::invalid_argument(fmt::format("writeGeoTiff: {} x {} raster with {} bands holds {} values",
                                                raster.width, raster.height, raster.bands, raster.values.size()));
    if (raster.width > INT32_MAX || raster.height > INT32_MAX || raster.bands > 65535)
        throw std::invalid_argument(fmt::format("writeGeoTiff: {} x {} raster with {} bands is too large for GDAL",
                                                raster.width, raster.height, raster.bands));
    if (!(pixelSizeX > 0.0) || !(pixelSizeY > 0.0) || !std::isfinite(pixelSizeX) || !std::isfinite(pixelSizeY) ||
        !std::isfinite(originX) || !std::isfinite(originY))
        throw std::invalid_argument(fmt::format("writeGeoTiff: origin ({}, {}) and pixel size {} x {} must be "
                                                "finite, the pixel size positive",
                                                originX, originY, pixelSizeX, pixelSizeY));

    const std::string ext = lowerExtension(path);
    if (ext != ".tif" && ext != ".tiff")
        throw InputError(fmt::format("{}: unsupported output format '{}' (expected .tif)", path, ext));

    const fs::path target(path);
    // A device or pipe (a link to /dev/null) is written in place, from a GeoTIFF made in memory: renaming over it
    // would replace it with a regular file.
    std::error_code ec;
    const auto status = fs::status(target, ec);
    const bool inPlace = !ec && fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status);
    const fs::path folder = inPlace ? fs::path() : writableFolder(path);

    registerGdalDrivers();
    QuietGdalErrors quiet;
    auto fail = [&](const std::string& what) {
        const std::string reason = firstLine(CPLGetLastErrorMsg());
        return std::runtime_error(fmt::format("{}: {}{}", path, what, reason.empty() ? "" : " (" + reason + ")"));
    };

    OGRSpatialReference srs;
    const bool hasCrs = geo.georeferenced && !geo.crsWkt.empty();
    if (hasCrs) {
        srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        if (srs.importFromWkt(geo.crsWkt.c_str()) != OGRERR_NONE) throw fail("cannot interpret the CRS");
    }

    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    if (driver == nullptr) throw fail("GDAL has no GTiff driver");

    // Declared before the dataset, so that the dataset is closed before the file is removed.
    static std::atomic<int> memoryFiles{0};
    const fs::path temporaryPath = inPlace ? fs::path(fmt::format("/vsimem/terracast-out-{}-{}.tif", getpid(), memoryFiles++))
                                           : temporaryPathFor(folder, ext);
    TemporaryFile temporary(inPlace ? fs::path() : temporaryPath);
    struct MemoryFile {
        fs::path path;
        ~MemoryFile() {
            if (!path.empty()) VSIUnlink(path.c_str());
        }
    } memoryFile{inPlace ? temporaryPath : fs::path()};
    const GDALDataType gdalType = type == RasterType::Byte ? GDT_Byte : GDT_Float32;
    CPLStringList options;
    options.SetNameValue("COMPRESS", "DEFLATE");
    options.SetNameValue("BIGTIFF", "IF_SAFER");
    if (raster.bands > 1) options.SetNameValue("INTERLEAVE", "PIXEL");
    if (raster.lastBandIsAlpha) {
        options.SetNameValue("ALPHA", "YES");
        if (raster.bands == 4 && type == RasterType::Byte) options.SetNameValue("PHOTOMETRIC", "RGB");
    }
    GDALDataset* dataset = driver->Create(temporaryPath.c_str(), static_cast<int>(raster.width),
                                          static_cast<int>(raster.height), raster.bands, gdalType, options.List());
    if (dataset == nullptr) throw fail("cannot create GeoTIFF");
    bool ok = true;
    std::string what;
    // Before the geotransform: with AREA_OR_POINT=Point GDAL stores the tie point half a pixel in, and reads the
    // same geotransform back.
    if (raster.pixelIsPoint) dataset->SetMetadataItem(GDALMD_AREA_OR_POINT, GDALMD_AOP_POINT);
    for (const auto& [key, value] : raster.metadata) dataset->SetMetadataItem(key.c_str(), value.c_str());
    for (int b = 1; b <= raster.bands; ++b) {
        GDALRasterBand* band = dataset->GetRasterBand(b);
        if (size_t(b) <= raster.bandDescriptions.size()) band->SetDescription(raster.bandDescriptions[size_t(b - 1)].c_str());
        const size_t unit = raster.bandUnits.size() == 1 ? 0 : size_t(b - 1);
        if (unit < raster.bandUnits.size()) band->SetUnitType(raster.bandUnits[unit].c_str());
    }
    // Pixel-is-area geotransform: the centre of raster sample (i, j) lands on (originX + i * pixelSizeX,
    // originY + j * pixelSizeY); file row 0 is raster row height - 1.
    double gt[6] = {originX - 0.5 * pixelSizeX,
                    pixelSizeX,
                    0.0,
                    originY + (static_cast<double>(raster.height) - 0.5) * pixelSizeY,
                    0.0,
                    -pixelSizeY};
    if (dataset->SetGeoTransform(gt) != CE_None) {
        ok = false;
        what = "cannot set the geotransform";
    }
    if (ok && hasCrs && dataset->SetSpatialRef(&srs) != CE_None) {
        ok = false;
        what = "cannot set the CRS";
    }
    for (int b = 1; ok && raster.hasNoData && b <= raster.bands; ++b) {
        if (dataset->GetRasterBand(b)->SetNoDataValue(raster.noDataValue) != CE_None) {
            ok = false;
            what = fmt::format("cannot set nodata value {} on band {}", raster.noDataValue, b);
        }
    }
    if (ok) {
        ok = type == RasterType::Byte ? writeRows<uint8_t>(*dataset, raster, gdalType)
                                      : writeRows<float>(*dataset, raster, gdalType);
        if (!ok) what = "cannot write pixels";
    }
    if (!ok) {
        const std::runtime_error error = fail(what);  // GDAL's message before closing can replace it
        GDALClose(dataset);
        throw error;
    }
    // GDAL 3.6's FlushCache and GDALClose return nothing: a failed flush shows only as an error raised here.
    CPLErrorReset();
    dataset->FlushCache(false);
    GDALClose(dataset);
    if (CPLGetLastErrorType() >= CE_Failure) throw fail("cannot write GeoTIFF");

    if (inPlace) {
        vsi_l_offset size = 0;
        const GByte* data = VSIGetMemFileBuffer(temporaryPath.c_str(), &size, FALSE);
        if (data == nullptr) throw fail("cannot write GeoTIFF");
        writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(data), size_t(size)));
        return;
    }
    if (const int failed = commitTemporary(temporary.path(), target))
        throw std::runtime_error(fmt::format("{}: cannot write ({})", path, std::strerror(failed)));
    temporary.release();
}

double sourcePixelSizeX(const GeoReference& geo) { return geo.georeferenced ? std::abs(geo.geoTransform[1]) : 1.0; }

double sourcePixelSizeY(const GeoReference& geo) { return geo.georeferenced ? std::abs(geo.geoTransform[5]) : 1.0; }

}  // namespace terracast
