// Windowed reads of a DEM, the source of tiled grids: every window holds exactly the heights and nodata flags the
// whole-raster load holds at those vertices, on real DEMs in three CRS kinds, on rasters stored south-up and
// east-to-west, on a VRT mosaic of several files, and from several threads at once.
#include "support/temp_dir.h"
#include "heightfield/grid_summary.h"
#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <gdal_utils.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <thread>
#include <vector>

using namespace terracast;
using terracast::testing::TempDir;

namespace {

std::string sample(const std::string& name) { return std::string(TERRACAST_SOURCE_DIR "/data-samples/") + name; }

// Compares window [i0, i0 + w) x [j0, j0 + h) of `reader` with the loaded grid; returns the first difference.
std::string compareWindow(const DemWindowReader& reader, const HeightGrid& grid, int64_t i0, int64_t j0, int64_t w,
                          int64_t h) {
    std::vector<float> z(size_t(w * h), -1.0f);
    std::vector<uint8_t> valid(size_t(w * h), 7);
    reader.read(i0, j0, w, h, z.data(), valid.data());
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) {
            const size_t k = size_t(j * w + i);
            const bool v = grid.vertexValid(i0 + i, j0 + j);
            if ((valid[k] == 1) != v || valid[k] > 1)
                return "validity differs at vertex " + std::to_string(i0 + i) + "," + std::to_string(j0 + j);
            if (v && std::bit_cast<uint32_t>(z[k]) != std::bit_cast<uint32_t>(grid.at(i0 + i, j0 + j)))
                return "height differs at vertex " + std::to_string(i0 + i) + "," + std::to_string(j0 + j) + ": " +
                       std::to_string(z[k]) + " against " + std::to_string(grid.at(i0 + i, j0 + j));
        }
    if (!reader.wholeMetres()) return "";
    // The same window as stored 16-bit metres: the same flags, the same heights, 0 at nodata.
    std::vector<int16_t> metres(size_t(w * h), -1);
    std::vector<uint8_t> flags(size_t(w * h), 7);
    reader.readWholeMetres(i0, j0, w, h, metres.data(), flags.data());
    for (size_t k = 0; k < metres.size(); ++k) {
        if (flags[k] != valid[k]) return "whole metres: validity differs at window sample " + std::to_string(k);
        if (float(metres[k]) != z[k])
            return "whole metres: height differs at window sample " + std::to_string(k) + ": " +
                   std::to_string(metres[k]) + " against " + std::to_string(z[k]);
    }
    return "";
}

// Random windows, the four corners' windows and whole rows and columns agree with the loaded grid.
void checkWindows(const std::string& path) {
    INFO(path);
    const LoadedDem dem = loadDem(path);
    const DemWindowReader reader(path);
    REQUIRE(reader.width() == dem.grid.width());
    REQUIRE(reader.height() == dem.grid.height());
    CHECK(reader.cellSizeXM() == dem.grid.cellSizeXM());
    CHECK(reader.cellSizeYM() == dem.grid.cellSizeYM());
    CHECK(reader.geo().originX == dem.geo.originX);
    CHECK(reader.geo().originY == dem.geo.originY);
    CHECK(reader.geo().crsWkt == dem.geo.crsWkt);
    CHECK(reader.warnings() == dem.warnings);
    CHECK((reader.hasNodata() || !dem.grid.hasNodata()));
    const int64_t W = reader.width(), H = reader.height();
    CHECK(compareWindow(reader, dem.grid, 0, 0, 1, 1) == "");
    CHECK(compareWindow(reader, dem.grid, W - 1, H - 1, 1, 1) == "");
    CHECK(compareWindow(reader, dem.grid, 0, H - 17, 17, 17) == "");
    CHECK(compareWindow(reader, dem.grid, W - 33, 0, 33, 5) == "");
    CHECK(compareWindow(reader, dem.grid, 0, H / 2, W, 1) == "");
    CHECK(compareWindow(reader, dem.grid, W / 3, 0, 1, H) == "");
    std::mt19937_64 rng(4);
    for (int n = 0; n < 20; ++n) {
        const int64_t w = 1 + int64_t(rng() % uint64_t(std::min<int64_t>(W, 300)));
        const int64_t h = 1 + int64_t(rng() % uint64_t(std::min<int64_t>(H, 300)));
        const int64_t i0 = int64_t(rng() % uint64_t(W - w + 1)), j0 = int64_t(rng() % uint64_t(H - h + 1));
        CHECK(compareWindow(reader, dem.grid, i0, j0, w, h) == "");
    }
}

// gdal_translate with `args` from `from` to `to`.
void translate(const std::string& from, const std::string& to, std::vector<std::string> args) {
    GDALAllRegister();
    GDALDatasetUniquePtr source(GDALDataset::Open(from.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(source);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
    GDALDatasetH out = GDALTranslate(to.c_str(), source.get(), options, nullptr);
    GDALTranslateOptionsFree(options);
    REQUIRE(out != nullptr);
    GDALClose(out);
}

}  // namespace

TEST_CASE("DEM windows: every window of a real DEM holds the whole load's heights and nodata", "[loaders][tiles]") {
    checkWindows(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"));
    checkWindows(sample("landfire-storm-lake-mt-utm12n-int16-small-nodata.tif"));
    checkWindows(sample("N44W072.srtm3-white-mountains-nh.hgt"));
    checkWindows(sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif"));
}

TEST_CASE("DEM windows: 16-bit bands in metres are read without conversion, others as floats", "[loaders][tiles]") {
    CHECK(DemWindowReader(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif")).wholeMetres());
    CHECK(DemWindowReader(sample("N44W072.srtm3-white-mountains-nh.hgt")).wholeMetres());
    TempDir dir("dem-window-metres");
    GDALAllRegister();
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    // A scale, an offset or a float band takes the float path; a nodata value no Int16 sample can hold marks
    // nothing.
    struct Case {
        const char* name;
        GDALDataType type;
        double scale, offset, nodata;
        bool whole;
    };
    for (const Case& c : {Case{"scaled.tif", GDT_Int16, 0.1, 0.0, -9999.0, false},
                          Case{"offset.tif", GDT_Int16, 1.0, 100.0, -9999.0, false},
                          Case{"float.tif", GDT_Float32, 1.0, 0.0, -9999.0, false},
                          Case{"uint16.tif", GDT_UInt16, 1.0, 0.0, 0.0, false},
                          Case{"far-nodata.tif", GDT_Int16, 1.0, 0.0, 40000.0, true},
                          Case{"fraction-nodata.tif", GDT_Int16, 1.0, 0.0, 7.5, true},
                          Case{"nodata.tif", GDT_Int16, 1.0, 0.0, 7.0, true}}) {
        INFO(c.name);
        const std::string path = dir.file(c.name);
        GDALDatasetUniquePtr ds(tiff->Create(path.c_str(), 41, 19, 1, c.type, nullptr));
        std::array<double, 6> gt{500000, 30, 0, 4000000, 0, -30};
        ds->SetGeoTransform(gt.data());
        std::vector<double> z(41 * 19);
        for (size_t k = 0; k < z.size(); ++k) z[k] = double(k * 13 % 300);
        GDALRasterBand* band = ds->GetRasterBand(1);
        band->SetScale(c.scale);
        band->SetOffset(c.offset);
        band->SetNoDataValue(c.nodata);
        REQUIRE(band->RasterIO(GF_Write, 0, 0, 41, 19, z.data(), 41, 19, GDT_Float64, 0, 0, nullptr) == CE_None);
        ds.reset();
        const DemWindowReader reader(path);
        CHECK(reader.wholeMetres() == c.whole);
        const LoadedDem dem = loadDem(path);
        CHECK(compareWindow(reader, dem.grid, 0, 0, 41, 19) == "");
        CHECK(compareWindow(reader, dem.grid, 3, 2, 30, 11) == "");
        if (!c.whole) {
            std::vector<int16_t> metres(4);
            std::vector<uint8_t> flags(4);
            CHECK_THROWS_AS(reader.readWholeMetres(0, 0, 2, 2, metres.data(), flags.data()), std::logic_error);
        }
    }
}

TEST_CASE("DEM windows: rasters stored south-up and east-to-west are read in grid order", "[loaders][tiles]") {
    TempDir dir("dem-window");
    GDALAllRegister();
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    for (const auto& [name, gt] : {std::pair{"south-up.tif", std::array<double, 6>{500000, 30, 0, 4000000, 0, 30}},
                                   std::pair{"east-west.tif", std::array<double, 6>{500000, -30, 0, 4000000, 0, -30}}}) {
        const std::string path = dir.file(name);
        GDALDatasetUniquePtr ds(tiff->Create(path.c_str(), 37, 23, 1, GDT_Int16, nullptr));
        ds->SetGeoTransform(const_cast<double*>(gt.data()));
        std::vector<int16_t> z(37 * 23);
        for (size_t k = 0; k < z.size(); ++k) z[k] = int16_t(k * 7 % 1000 - 20);
        z[5] = -9999;
        ds->GetRasterBand(1)->SetNoDataValue(-9999);
        REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 37, 23, z.data(), 37, 23, GDT_Int16, 0, 0, nullptr) ==
                CE_None);
        ds.reset();
        checkWindows(path);
    }
}

TEST_CASE("DEM windows: a VRT mosaic of four files reads as the DEM they were cut from", "[loaders][tiles]") {
    // The White Mountains tile cut into four GeoTIFFs that share their edge rows and columns, and put back
    // together by a VRT, as a mosaic of SRTM tiles is.
    TempDir dir("dem-window-vrt");
    const std::string tile = sample("N44W072.srtm3-white-mountains-nh.hgt");
    GDALAllRegister();
    GDALDatasetUniquePtr source(GDALDataset::Open(tile.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(source);
    const int W = source->GetRasterXSize(), H = source->GetRasterYSize();
    std::vector<std::string> pieces;
    for (const auto& [x0, y0, w, h] : {std::array<int, 4>{0, 0, 601, 601}, {600, 0, W - 600, 601},
                                       {0, 600, 601, H - 600}, {600, 600, W - 600, H - 600}}) {
        pieces.push_back(dir.file("piece-" + std::to_string(x0) + "-" + std::to_string(y0) + ".tif"));
        const std::vector<std::string> args = {"-srcwin", std::to_string(x0), std::to_string(y0), std::to_string(w),
                                               std::to_string(h), "-of", "GTiff"};
        std::vector<char*> argv;
        for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
        GDALDatasetH out = GDALTranslate(pieces.back().c_str(), source.get(), options, nullptr);
        GDALTranslateOptionsFree(options);
        REQUIRE(out != nullptr);
        GDALClose(out);
    }
    std::vector<const char*> names;
    for (const auto& p : pieces) names.push_back(p.c_str());
    const std::string vrt = dir.file("mosaic.vrt");
    GDALDatasetH mosaic = GDALBuildVRT(vrt.c_str(), int(names.size()), nullptr, names.data(), nullptr, nullptr);
    REQUIRE(mosaic != nullptr);
    GDALClose(mosaic);

    const LoadedDem whole = loadDem(tile);
    const DemWindowReader reader(vrt);
    REQUIRE(reader.width() == W);
    REQUIRE(reader.height() == H);
    CHECK(reader.geo().originX == whole.geo.originX);
    CHECK(reader.geo().originY == whole.geo.originY);
    // Windows across the seams, and the whole raster.
    CHECK(compareWindow(reader, whole.grid, 590, 590, 21, 21) == "");
    CHECK(compareWindow(reader, whole.grid, 0, 595, W, 11) == "");
    CHECK(compareWindow(reader, whole.grid, 0, 0, W, H) == "");
}

TEST_CASE("DEM windows: threads reading at once each get their own window right", "[loaders][tiles]") {
    // St Helens (16-bit, nodata) as GDAL stores it, in strips, and as a tiled copy; each window is read both as
    // floats and as whole metres.
    TempDir dir("dem-window-threads");
    const std::string striped = sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    const std::string tiled = dir.file("tiled.tif");
    translate(striped, tiled, {"-co", "TILED=YES", "-co", "BLOCKXSIZE=16", "-co", "BLOCKYSIZE=16", "-co",
                               "COMPRESS=DEFLATE"});
    for (const std::string& path : {striped, tiled}) {
        INFO(path);
        const LoadedDem dem = loadDem(path);
        const DemWindowReader reader(path);
        std::vector<std::string> failures(4);
        std::vector<std::thread> threads;
        std::atomic<int> ready{0};
        for (int t = 0; t < 4; ++t)
            threads.emplace_back([&, t] {
                ++ready;
                while (ready.load() < 4) std::this_thread::yield();  // all four read at once
                std::mt19937_64 rng{uint64_t(t)};
                // Windows up to 200 x 200: reads long enough to meet one another even on a busy machine.
                for (int n = 0; n < 100 && failures[size_t(t)].empty(); ++n) {
                    const int64_t w = 1 + int64_t(rng() % 200), h = 1 + int64_t(rng() % 200);
                    const int64_t i0 = int64_t(rng() % uint64_t(reader.width() - w + 1));
                    const int64_t j0 = int64_t(rng() % uint64_t(reader.height() - h + 1));
                    failures[size_t(t)] = compareWindow(reader, dem.grid, i0, j0, w, h);
                }
            });
        for (auto& th : threads) th.join();
        for (const auto& f : failures) CHECK(f == "");
        // The threads did not all wait for one dataset.
        CHECK(reader.wholeMetres());
        CHECK(reader.openings() >= 2);
        CHECK(reader.openings() <= int(std::max(std::thread::hardware_concurrency(), 2u)));
    }
}

TEST_CASE("DEM windows: a damaged file fails the read that meets the damage, naming its rows", "[loaders][tiles]") {
    TempDir dir("dem-window-bad");
    const std::string path = dir.file("cut.tif");
    {
        std::ifstream in(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), {});
        std::ofstream(path, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }
    const DemWindowReader reader(path);
    std::vector<float> z(327 * 468);
    std::vector<uint8_t> valid(z.size());
    CHECK_THROWS_WITH(reader.read(0, 0, 327, 468, z.data(), valid.data()),
                      Catch::StartsWith(path + ": cannot read rows 0..467 of band 1"));
    CHECK_THROWS_AS(reader.read(300, 0, 28, 1, z.data(), valid.data()), std::invalid_argument);
    CHECK_THROWS_AS(reader.read(0, -1, 1, 1, z.data(), valid.data()), std::invalid_argument);
}

TEST_CASE("DEM windows: a summary streamed a band of rows at a time is what the whole grid holds", "[loaders][tiles]") {
    TempDir dir("dem-window-summary");
    // A float DEM whose heights no int16 code holds, and one stored as tenths of a metre (a band scale of 0.1).
    GDALAllRegister();
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    const std::string floats = dir.file("floats.tif"), tenths = dir.file("tenths.tif");
    {
        GDALDatasetUniquePtr ds(tiff->Create(floats.c_str(), 50, 40, 1, GDT_Float32, nullptr));
        double gt[6] = {0, 10, 0, 400, 0, -10};
        ds->SetGeoTransform(gt);
        std::vector<float> z(50 * 40);
        for (size_t k = 0; k < z.size(); ++k) z[k] = 100.0f + 0.37f * float(k % 101);
        REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 50, 40, z.data(), 50, 40, GDT_Float32, 0, 0, nullptr) ==
                CE_None);
        GDALDatasetUniquePtr t(tiff->Create(tenths.c_str(), 50, 40, 1, GDT_Int16, nullptr));
        t->SetGeoTransform(gt);
        t->GetRasterBand(1)->SetScale(0.1);
        t->GetRasterBand(1)->SetNoDataValue(-32768);
        std::vector<int16_t> q(50 * 40);
        for (size_t k = 0; k < q.size(); ++k) q[k] = int16_t(k % 13 == 0 ? -32768 : int(k * 37 % 20000) - 3000);
        REQUIRE(t->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 50, 40, q.data(), 50, 40, GDT_Int16, 0, 0, nullptr) ==
                CE_None);
    }
    for (const std::string& path :
         {sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"),
          sample("landfire-storm-lake-mt-utm12n-int16-small-nodata.tif"), sample("N44W072.srtm3-white-mountains-nh.hgt"),
          sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif"), floats, tenths}) {
        INFO(path);
        const LoadedDem dem = loadDem(path);
        const DemWindowReader reader(path);
        GridSummaryBuilder builder(reader.width(), reader.height(), reader.metresPerUnit());
        for (int64_t j0 = 0; j0 < reader.height(); j0 += 37) {
            const int64_t rows = std::min<int64_t>(37, reader.height() - j0);
            std::vector<float> z(size_t(rows * reader.width()));
            std::vector<uint8_t> valid(z.size());
            reader.read(0, j0, reader.width(), rows, z.data(), valid.data());
            builder.addRows(j0, rows, z.data(), valid.data());
        }
        const GridSummary s = builder.finish();
        const HeightGrid& g = dem.grid;
        CHECK(s.minHeightM == g.minHeightM());
        CHECK(s.maxHeightM == g.maxHeightM());
        CHECK(s.nodataVertices == g.nodataVertexCount());
        CHECK(s.validCells == g.validCellCount());
        CHECK(s.storage == g.storage());
        if (g.storage() == HeightStorage::Int16) {
            CHECK(s.codeOffset == g.codeOffset());
            CHECK(s.codeScale == g.codeScale());
        }
    }
    // The float DEM stays float; the tenths keep int16 codes at their own scale.
    CHECK(loadDem(floats).grid.storage() == HeightStorage::Float32);
    CHECK(loadDem(tenths).grid.storage() == HeightStorage::Int16);
    CHECK(loadDem(tenths).grid.codeScale() == Approx(0.1));
}
