// Rasters written tile by tile: a raster of several tiles in each direction, its tiles written in any order
// and from several threads, reads back through GDAL as the values given, as a COG (512 x 512 blocks,
// overviews); a writer that stops early leaves its finished tiles and no file at the path, and a resumed
// writer of the same raster keeps them and makes the same bytes as one that never stopped; a resumed writer
// of another raster, or a partial folder that is not one, is refused. Files are read back with GDAL directly.
#include "support/run_command.h"
#include "support/temp_dir.h"
#include "loaders/raster_writer.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

using namespace terracast;
namespace fs = std::filesystem;
using terracast::testing::TempDir;
using terracast::testing::slurp;

namespace {

// A 1100 x 700 raster of two bands (3 x 2 tiles), with a hole of NaN across the tiles' shared corner.
GridRaster testRaster() {
    GridRaster r;
    r.width = 1100;
    r.height = 700;
    r.bands = 2;
    r.hasNoData = true;
    r.noDataValue = -9999.0;
    r.bandDescriptions = {"first", "second"};
    r.bandUnits = {"m"};
    r.metadata = {{"TERRACAST_PRODUCT", "test"}};
    r.values.resize(size_t(r.width * r.height * r.bands));
    for (int64_t j = 0; j < r.height; ++j)
        for (int64_t i = 0; i < r.width; ++i) {
            const bool hole = std::abs(i - 512) < 20 && std::abs(j - 188) < 20;  // file row 511 is raster row 188
            r.values[size_t((j * r.width + i) * 2)] = hole ? std::numeric_limits<float>::quiet_NaN() : float(i) + 0.25f;
            r.values[size_t((j * r.width + i) * 2 + 1)] = float(j) * 0.5f - 3.0f;
        }
    return r;
}

RasterPlacement testPlacement() {
    RasterPlacement p;
    OGRSpatialReference srs;
    srs.importFromEPSG(32610);
    char* wkt = nullptr;
    srs.exportToWkt(&wkt);
    p.geo.georeferenced = true;
    p.geo.crsWkt = wkt;
    CPLFree(wkt);
    p.originX = 500000.0;
    p.originY = 5000000.0;
    p.pixelSizeX = 10.0;
    p.pixelSizeY = 10.0;
    return p;
}

// The window of `raster` that tile (tx, ty) holds, as the writer wants it.
std::vector<float> tileValues(const GridRaster& raster, const TiledGeoTiffWriter::Window& w) {
    std::vector<float> tile;
    for (int64_t j = w.j0; j < w.j1; ++j)
        for (int64_t i = w.i0; i < w.i1; ++i)
            for (int b = 0; b < raster.bands; ++b) tile.push_back(raster.values[size_t((j * raster.width + i) * raster.bands + b)]);
    return tile;
}

void writeTile(TiledGeoTiffWriter& writer, const GridRaster& raster, int64_t tx, int64_t ty) {
    const std::vector<float> values = tileValues(raster, writer.window(tx, ty));
    writer.write(tx, ty, values.data());
}

}  // namespace

TEST_CASE("Tiled writer: tiles in any order from several threads make the raster's COG", "[loaders][tiles]") {
    TempDir dir("tiled-writer");
    const GridRaster raster = testRaster();
    const std::string path = dir.file("out.tif");
    {
        TiledGeoTiffWriter writer(path, raster, RasterType::Float32, testPlacement(), "job", false);
        REQUIRE(writer.tilesX() == 3);
        REQUIRE(writer.tilesY() == 2);
        // File tile row 0 is the north: raster rows [700 - 512, 700).
        CHECK(writer.window(0, 0).j0 == 188);
        CHECK(writer.window(0, 0).j1 == 700);
        CHECK(writer.window(2, 1).i1 == 1100);
        CHECK(writer.window(2, 1).j0 == 0);
        CHECK(writer.window(2, 1).j1 == 188);
        std::thread other([&] {
            writeTile(writer, raster, 2, 1);
            writeTile(writer, raster, 0, 0);
        });
        writeTile(writer, raster, 1, 1);
        writeTile(writer, raster, 1, 0);
        writeTile(writer, raster, 0, 1);
        other.join();
        REQUIRE_THROWS_AS(writer.commit(), std::logic_error);  // tile (2, 0) is missing
        CHECK_FALSE(fs::exists(path));
        writeTile(writer, raster, 2, 0);
        writer.commit();
    }
    CHECK(fs::exists(path));
    CHECK_FALSE(fs::exists(path + ".partial"));
    CHECK(dir.entryCount() == 1);
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(ds);
    REQUIRE(ds->GetRasterXSize() == 1100);
    REQUIRE(ds->GetRasterYSize() == 700);
    REQUIRE(ds->GetRasterCount() == 2);
    CHECK(std::string(ds->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE")) == "COG");
    CHECK(std::string(ds->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE")) == "DEFLATE");
    CHECK(std::string(ds->GetMetadataItem("TERRACAST_PRODUCT")) == "test");
    int bx = 0, by = 0;
    ds->GetRasterBand(1)->GetBlockSize(&bx, &by);
    CHECK(bx == 512);
    CHECK(by == 512);
    CHECK(ds->GetRasterBand(1)->GetOverviewCount() >= 1);
    CHECK(std::string(ds->GetRasterBand(2)->GetDescription()) == "second");
    CHECK(std::string(ds->GetRasterBand(2)->GetUnitType()) == "m");
    double gt[6];
    REQUIRE(ds->GetGeoTransform(gt) == CE_None);
    CHECK(gt[0] == 500000.0 - 5.0);
    CHECK(gt[3] == 5000000.0 + 699.5 * 10.0);
    int hasNoData = 0;
    CHECK(ds->GetRasterBand(1)->GetNoDataValue(&hasNoData) == -9999.0);
    CHECK(hasNoData);
    std::vector<float> row(1100);
    int64_t mismatches = 0, holes = 0;
    for (int b = 1; b <= 2; ++b)
        for (int y = 0; y < 700; ++y) {
            REQUIRE(ds->GetRasterBand(b)->RasterIO(GF_Read, 0, y, 1100, 1, row.data(), 1100, 1, GDT_Float32, 0, 0,
                                                  nullptr) == CE_None);
            const int64_t j = 699 - y;
            for (int64_t i = 0; i < 1100; ++i) {
                const float want = raster.values[size_t((j * 1100 + i) * 2 + (b - 1))];
                if (std::isnan(want)) {
                    holes += row[size_t(i)] == -9999.0f;
                    mismatches += row[size_t(i)] != -9999.0f;
                } else {
                    mismatches += row[size_t(i)] != want;
                }
            }
        }
    CHECK(mismatches == 0);
    CHECK(holes == 39 * 39);
}

TEST_CASE("Tiled writer: a stopped writer keeps its tiles and a resumed one makes the same bytes",
          "[loaders][tiles]") {
    TempDir dir("tiled-resume");
    const GridRaster raster = testRaster();
    const RasterPlacement placement = testPlacement();
    // The reference: written without a stop, in its own folder.
    const std::string reference = dir.file("reference.tif");
    writeGeoTiff(reference, raster, RasterType::Float32, placement);
    const std::string path = dir.file("out.tif");
    // An uninterrupted tiled writer of the same raster gives the same bytes as writeGeoTiff, whatever its job.
    {
        TiledGeoTiffWriter writer(path, raster, RasterType::Float32, placement, "first", false);
        for (int64_t ty = 0; ty < 2; ++ty)
            for (int64_t tx = 0; tx < 3; ++tx) writeTile(writer, raster, tx, ty);
        writer.commit();
    }
    CHECK(slurp(path) == slurp(reference));
    fs::remove(path);
    // Stopped after two tiles (an exception between tiles).
    {
        TiledGeoTiffWriter writer(path, raster, RasterType::Float32, placement, "job A", false);
        writeTile(writer, raster, 0, 0);
        writeTile(writer, raster, 2, 1);
    }
    CHECK_FALSE(fs::exists(path));
    REQUIRE(fs::is_directory(path + ".partial"));
    // A damaged tile is computed again, not kept.
    { std::ofstream(path + ".partial/tile-2-1.tif", std::ios::trunc) << "not a tiff"; }
    // Another job's resume is refused, naming the difference.
    try {
        TiledGeoTiffWriter other(path, raster, RasterType::Float32, placement, "job B", true);
        FAIL("resumed another job's tiles");
    } catch (const InputError& e) {
        const std::string message = e.what();
        CHECK(message.find("--resume") != std::string::npos);
        CHECK(message.find("job B") != std::string::npos);
    }
    {
        TiledGeoTiffWriter writer(path, raster, RasterType::Float32, placement, "job A", true);
        CHECK(writer.resumedTiles() == 1);
        CHECK(writer.discardedTiles() == 1);
        CHECK(writer.finished(0, 0));
        CHECK_FALSE(writer.finished(2, 1));
        for (int64_t ty = 0; ty < 2; ++ty)
            for (int64_t tx = 0; tx < 3; ++tx)
                if (!writer.finished(tx, ty)) writeTile(writer, raster, tx, ty);
        writer.commit();
    }
    CHECK(slurp(path) == slurp(reference));
    CHECK_FALSE(fs::exists(path + ".partial"));
    // Without --resume, an earlier run's tiles are removed and counted.
    {
        TiledGeoTiffWriter stopped(dir.file("again.tif"), raster, RasterType::Float32, placement, "job A", false);
        writeTile(stopped, raster, 1, 1);
    }
    TiledGeoTiffWriter fresh(dir.file("again.tif"), raster, RasterType::Float32, placement, "job A", false);
    CHECK(fresh.discardedTiles() == 1);
    CHECK(fresh.resumedTiles() == 0);
    CHECK_FALSE(fresh.finished(1, 1));
}

TEST_CASE("Tiled writer: a folder in the way that is not a partial output is left alone", "[loaders][tiles]") {
    TempDir dir("tiled-foreign");
    const std::string path = dir.file("out.tif");
    fs::create_directory(path + ".partial");
    { std::ofstream(path + ".partial/keep.txt") << "mine"; }
    try {
        TiledGeoTiffWriter writer(path, testRaster(), RasterType::Float32, testPlacement(), "job", false);
        FAIL("took over a foreign folder");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()).find("not a terracast partial output") != std::string::npos);
    }
    CHECK(fs::exists(path + ".partial/keep.txt"));
    // A writer that finished no tile leaves no folder behind.
    TiledGeoTiffWriter(dir.file("other.tif"), testRaster(), RasterType::Float32, testPlacement(), "job", false);
    CHECK_FALSE(fs::exists(dir.file("other.tif.partial")));
}
