// GeoTIFF writing on a DEM's grid: a raster written on the Mt St Helens grid has the source file's size,
// geotransform, CRS and row order; Byte rasters clamp and round; rasters without a georeference get no CRS;
// bad paths and sizes fail without leaving a file. Files are read back with GDAL directly.
#include "support/temp_dir.h"
#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"
#include "loaders/raster_writer.h"

#include <catch2/catch.hpp>
#include <cpl_error.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <filesystem>
#include <iterator>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using namespace terracast;
namespace fs = std::filesystem;
using terracast::testing::TempDir;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR "/data-samples/") + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";


GDALDatasetUniquePtr openRaster(const std::string& path) {
    GDALAllRegister();
    GDALDatasetUniquePtr dataset(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(dataset);
    return dataset;
}

// Every band of a dataset as float64, band-interleaved by pixel in file order (row 0 at the top).
std::vector<double> readAll(GDALDataset& dataset) {
    const int width = dataset.GetRasterXSize();
    const int height = dataset.GetRasterYSize();
    const int bands = dataset.GetRasterCount();
    std::vector<double> values(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(bands));
    const GSpacing pixelSpace = static_cast<GSpacing>(sizeof(double)) * bands;
    REQUIRE(dataset.RasterIO(GF_Read, 0, 0, width, height, values.data(), width, height, GDT_Float64, bands, nullptr,
                             pixelSpace, pixelSpace * width, sizeof(double), nullptr) == CE_None);
    return values;
}

std::string wktOf(GDALDataset& dataset) {
    const char* wkt = dataset.GetProjectionRef();
    return wkt ? wkt : "";
}

// The message of the InputError that writeGeoTiff throws (fails the test when it throws nothing or another type).
std::string writeInputError(const std::string& path, const GridRaster& raster) {
    GeoReference geo;
    try {
        writeGeoTiff(path, raster, RasterType::Float32, {geo, 0.0, 0.0, 1.0, 1.0});
    } catch (const InputError& e) {
        return e.what();
    }
    FAIL("no InputError for " << path);
    return "";
}

GridRaster smallRaster() {
    GridRaster raster;
    raster.width = 3;
    raster.height = 2;
    raster.values = {1, 2, 3, 4, 5, 6};
    return raster;
}

bool oneLine(const std::string& message) { return message.find('\n') == std::string::npos; }

}  // namespace

TEST_CASE("A raster written on the Mt St Helens grid overlays the source file exactly", "[loaders][raster_writer]") {
    const LoadedDem dem = loadDem(kStHelens);
    const HeightGrid& grid = dem.grid;
    REQUIRE(dem.geo.georeferenced);
    CHECK(sourcePixelSizeX(dem.geo) == 30.0);
    CHECK(sourcePixelSizeY(dem.geo) == 30.0);

    GridRaster raster;
    raster.width = grid.width();
    raster.height = grid.height();
    raster.hasNoData = true;
    raster.noDataValue = -9999.0;
    raster.values.resize(static_cast<size_t>(grid.width() * grid.height()));
    for (int64_t j = 0; j < grid.height(); ++j)
        for (int64_t i = 0; i < grid.width(); ++i)
            raster.values[static_cast<size_t>(j * grid.width() + i)] =
                grid.vertexValid(i, j) ? grid.at(i, j) : -9999.0f;

    TempDir dir;
    const std::string path = dir.file("heights.tif");
    writeGeoTiff(path, raster, RasterType::Float32, {dem.geo, dem.geo.originX, dem.geo.originY,
                 sourcePixelSizeX(dem.geo), sourcePixelSizeY(dem.geo)});
    CHECK(dir.entryCount() == 1);  // no temporary file left behind

    GDALDatasetUniquePtr source = openRaster(kStHelens);
    GDALDatasetUniquePtr written = openRaster(path);
    REQUIRE(written->GetRasterXSize() == source->GetRasterXSize());
    REQUIRE(written->GetRasterYSize() == source->GetRasterYSize());
    REQUIRE(written->GetRasterCount() == 1);
    CHECK(written->GetRasterBand(1)->GetRasterDataType() == GDT_Float32);
    const char* compression = written->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE");
    CHECK(std::string(compression ? compression : "") == "DEFLATE");

    double sourceGt[6] = {};
    double writtenGt[6] = {};
    REQUIRE(GDALGetGeoTransform(source.get(), sourceGt) == CE_None);
    REQUIRE(GDALGetGeoTransform(written.get(), writtenGt) == CE_None);
    for (int k = 0; k < 6; ++k) {
        INFO("geotransform term " << k);
        CHECK(writtenGt[k] == Approx(sourceGt[k]).margin(1e-6));
    }

    OGRSpatialReference sourceSrs;
    OGRSpatialReference writtenSrs;
    REQUIRE(sourceSrs.importFromWkt(wktOf(*source).c_str()) == OGRERR_NONE);
    REQUIRE(writtenSrs.importFromWkt(wktOf(*written).c_str()) == OGRERR_NONE);
    CHECK(writtenSrs.IsSame(&sourceSrs));

    int hasNodata = 0;
    const double nodata = written->GetRasterBand(1)->GetNoDataValue(&hasNodata);
    CHECK(hasNodata);
    CHECK(nodata == -9999.0);

    int sourceHasNodata = 0;
    const double sourceNodata = source->GetRasterBand(1)->GetNoDataValue(&sourceHasNodata);
    REQUIRE(sourceHasNodata);
    const std::vector<double> sourceValues = readAll(*source);
    const std::vector<double> writtenValues = readAll(*written);
    REQUIRE(sourceValues.size() == writtenValues.size());
    size_t valid = 0;
    size_t mismatches = 0;
    size_t nodataMismatches = 0;
    for (size_t k = 0; k < sourceValues.size(); ++k) {
        if (sourceValues[k] == sourceNodata) {
            if (writtenValues[k] != -9999.0) ++nodataMismatches;
            continue;
        }
        ++valid;
        if (writtenValues[k] != sourceValues[k]) ++mismatches;
    }
    CHECK(valid > sourceValues.size() / 2);
    CHECK(valid < sourceValues.size());  // the sample has nodata pixels, so their positions are compared too
    CHECK(mismatches == 0);
    CHECK(nodataMismatches == 0);
}

TEST_CASE("A three-band Byte raster round-trips north-up with clamping, rounding and nodata on every band",
          "[loaders][raster_writer]") {
    // 4 x 3 pixels; band 0 holds the raster row (0 = south), band 1 the column, band 2 values to clamp and round.
    GridRaster raster;
    raster.width = 4;
    raster.height = 3;
    raster.bands = 3;
    raster.hasNoData = true;
    raster.noDataValue = 7.0;
    const std::vector<float> band2 = {300.0f, -5.0f, 12.4f, 12.6f, 254.5f, 255.0f, 0.0f, 1e9f, -1e9f, 99.0f, 0.49f, 128.0f};
    for (int64_t j = 0; j < raster.height; ++j)
        for (int64_t i = 0; i < raster.width; ++i) {
            raster.values.push_back(static_cast<float>(10 * (j + 1)));
            raster.values.push_back(static_cast<float>(i + 100));
            raster.values.push_back(band2[static_cast<size_t>(j * raster.width + i)]);
        }

    GeoReference geo;
    geo.georeferenced = true;
    OGRSpatialReference wgs84;
    REQUIRE(wgs84.importFromEPSG(4326) == OGRERR_NONE);
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // as GDAL returns a dataset's CRS
    char* wkt = nullptr;
    REQUIRE(wgs84.exportToWkt(&wkt) == OGRERR_NONE);
    geo.crsWkt = wkt;
    CPLFree(wkt);

    TempDir dir;
    const std::string path = dir.file("colours.TIFF");  // the extension is matched without regard to case
    writeGeoTiff(path, raster, RasterType::Byte, {geo, 7.0, 45.0, 0.25, 0.5});
    CHECK(dir.entryCount() == 1);

    GDALDatasetUniquePtr written = openRaster(path);
    REQUIRE(written->GetRasterXSize() == 4);
    REQUIRE(written->GetRasterYSize() == 3);
    REQUIRE(written->GetRasterCount() == 3);
    for (int b = 1; b <= 3; ++b) {
        INFO("band " << b);
        GDALRasterBand* band = written->GetRasterBand(b);
        CHECK(band->GetRasterDataType() == GDT_Byte);
        int hasNodata = 0;
        CHECK(band->GetNoDataValue(&hasNodata) == 7.0);
        CHECK(hasNodata);
    }

    // Pixel centres: sample (0, 0) at (7, 45), so the top-left corner is (6.875, 45 + 2 * 0.5 + 0.25).
    double gt[6] = {};
    REQUIRE(written->GetGeoTransform(gt) == CE_None);
    CHECK(gt[0] == Approx(6.875).margin(1e-12));
    CHECK(gt[1] == Approx(0.25).margin(1e-12));
    CHECK(gt[2] == 0.0);
    CHECK(gt[3] == Approx(46.25).margin(1e-12));
    CHECK(gt[4] == 0.0);
    CHECK(gt[5] == Approx(-0.5).margin(1e-12));
    const OGRSpatialReference* srs = written->GetSpatialRef();
    REQUIRE(srs != nullptr);
    CHECK(srs->IsSame(&wgs84));

    // File row r holds raster row 2 - r.
    const std::vector<double> values = readAll(*written);
    const std::vector<double> expectedBand2 = {0, 99, 0, 128, 255, 255, 0, 255, 255, 0, 12, 13};
    for (int64_t row = 0; row < 3; ++row)
        for (int64_t column = 0; column < 4; ++column) {
            INFO("file row " << row << ", column " << column);
            const auto k = static_cast<size_t>((row * 4 + column) * 3);
            CHECK(values[k] == 10.0 * static_cast<double>(3 - row));
            CHECK(values[k + 1] == static_cast<double>(column + 100));
            CHECK(values[k + 2] == expectedBand2[static_cast<size_t>(row * 4 + column)]);
        }
}

TEST_CASE("A raster without a georeference is written without a CRS, in plain pixels", "[loaders][raster_writer]") {
    GeoReference geo;  // georeferenced == false
    // A leftover WKT must not be written when the flag says there is no georeference.
    OGRSpatialReference utm;
    REQUIRE(utm.importFromEPSG(32610) == OGRERR_NONE);
    char* wkt = nullptr;
    REQUIRE(utm.exportToWkt(&wkt) == OGRERR_NONE);
    geo.crsWkt = wkt;
    CPLFree(wkt);
    geo.geoTransform[1] = 30.0;
    geo.geoTransform[5] = -30.0;
    CHECK(sourcePixelSizeX(geo) == 1.0);
    CHECK(sourcePixelSizeY(geo) == 1.0);

    TempDir dir;
    const std::string path = dir.file("plain.tif");
    writeGeoTiff(path, smallRaster(), RasterType::Float32, {geo, 0.0, 0.0, sourcePixelSizeX(geo),
                 sourcePixelSizeY(geo)});
    GDALDatasetUniquePtr written = openRaster(path);
    const OGRSpatialReference* srs = written->GetSpatialRef();
    CHECK((srs == nullptr || srs->IsEmpty()));
    CHECK(wktOf(*written).empty());
    int hasNodata = 0;
    written->GetRasterBand(1)->GetNoDataValue(&hasNodata);
    CHECK_FALSE(hasNodata);

    double gt[6] = {};
    REQUIRE(written->GetGeoTransform(gt) == CE_None);
    CHECK(gt[0] == -0.5);
    CHECK(gt[1] == 1.0);
    CHECK(gt[3] == 1.5);
    CHECK(gt[5] == -1.0);
    CHECK(readAll(*written) == std::vector<double>{4, 5, 6, 1, 2, 3});
}

TEST_CASE("Bad output paths throw one-line InputErrors naming the path and leave no file",
          "[loaders][raster_writer]") {
    TempDir dir;
    std::string path;
    std::string message;
    SECTION("missing folder") {
        path = dir.file("missing/out.tif");
        message = writeInputError(path, smallRaster());
        CHECK_THAT(message, Catch::Contains("folder '" + dir.file("missing") + "' does not exist"));
        CHECK_FALSE(fs::exists(dir.path() / "missing"));
    }
    SECTION("bad extension") {
        path = dir.file("out.png");
        message = writeInputError(path, smallRaster());
        CHECK_THAT(message, Catch::Contains("unsupported output format '.png' (expected .tif)"));
    }
    SECTION("no extension") {
        path = dir.file("out");
        message = writeInputError(path, smallRaster());
        CHECK_THAT(message, Catch::Contains("unsupported output format"));
    }
    SECTION("folder not writable") {
        const fs::path folder = dir.path() / "locked";
        fs::create_directory(folder);
        fs::permissions(folder, fs::perms::owner_read | fs::perms::owner_exec);
        path = (folder / "out.tif").string();
        if (::access(folder.c_str(), W_OK) == 0) {
            WARN("running with permission to write anywhere (root?): cannot test an unwritable folder");
            return;
        }
        message = writeInputError(path, smallRaster());
        CHECK_THAT(message, Catch::Contains("not writable"));
        fs::permissions(folder, fs::perms::owner_all);
        CHECK(fs::is_empty(folder));
    }
    CHECK_THAT(message, Catch::StartsWith(path + ": "));
    CHECK(oneLine(message));
    CHECK_FALSE(fs::exists(path));
    CHECK(dir.entryCount() == (fs::exists(dir.path() / "locked") ? 1u : 0u));
}

TEST_CASE("Rasters whose size does not match their values are refused", "[loaders][raster_writer]") {
    TempDir dir;
    const std::string path = dir.file("out.tif");
    GeoReference geo;
    GridRaster raster = smallRaster();
    SECTION("too few values") { raster.values.pop_back(); }
    SECTION("too many values") { raster.values.push_back(7.0f); }
    SECTION("too few values for the bands") { raster.bands = 2; }
    SECTION("no rows") {
        raster.height = 0;
        raster.values.clear();
    }
    SECTION("no bands") {
        raster.bands = 0;
        raster.values.clear();
    }
    CHECK_THROWS_AS(writeGeoTiff(path, raster, RasterType::Float32, {geo, 0.0, 0.0, 1.0, 1.0}), std::invalid_argument);
    CHECK(dir.entryCount() == 0);
}
