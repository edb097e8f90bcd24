// `render --lod` and `compare --lod` through the executable: the level of detail changes some pixels and not
// most, is refused where it cannot apply, works over a DEM held as tiles, and compare reports it beside the
// exact methods.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <gdal_priv.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace terracast::testing;

namespace {

const std::string kHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

std::vector<uint8_t> pixels(const std::string& png, int& width, int& height) {
    GDALAllRegister();
    GDALDatasetUniquePtr ds(GDALDataset::Open(png.c_str(), GDAL_OF_RASTER));
    REQUIRE(ds);
    width = ds->GetRasterXSize();
    height = ds->GetRasterYSize();
    std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
    REQUIRE(ds->RasterIO(GF_Read, 0, 0, width, height, rgb.data(), width, height, GDT_Byte, 3, nullptr, 3,
                         3 * width, 1, nullptr) == CE_None);
    return rgb;
}

}  // namespace

TEST_CASE("Level of detail: render --lod changes some pixels but not most, and is refused where it cannot apply",
          "[cli][lod]") {
    TempDir dir("lod-cli");
    const std::string base = "render '" + kHelens + "' --size 200x150 --sky-samples 0 --threads 2 -o '";
    CommandResult exact = runTerracast(base + dir.file("exact.png") + "'");
    INFO(exact.err);
    REQUIRE(exact.exitCode == 0);
    CommandResult lod = runTerracast(base + dir.file("lod.png") + "' --lod 4");
    INFO(lod.err);
    REQUIRE(lod.exitCode == 0);
    int w = 0, h = 0, w2 = 0, h2 = 0;
    const auto a = pixels(dir.file("exact.png"), w, h), b = pixels(dir.file("lod.png"), w2, h2);
    REQUIRE(w == w2);
    REQUIRE(h == h2);
    int64_t differ = 0;
    for (size_t k = 0; k < a.size(); k += 3)
        differ += std::abs(a[k] - b[k]) + std::abs(a[k + 1] - b[k + 1]) + std::abs(a[k + 2] - b[k + 2]) > 6;
    const double share = double(differ) / double(w * h);
    INFO(differ << " of " << w * h << " pixels differ");
    CHECK(share > 0.01);
    CHECK(share < 0.5);

    const auto refused = [&](const std::string& extra, const std::string& message) {
        const CommandResult r = runTerracast(base + dir.file("x.png") + "' " + extra);
        CHECK(r.exitCode == 2);
        CHECK(r.err == "terracast: error: " + message + "\n");
    };
    refused("--lod -2", "--lod: expected pixels per cell in (0, 1e6], found -2");
    refused("--lod 2 --view map", "--lod: expected the perspective view, found --view map");
    refused("--lod 2 --view panorama", "--lod: expected the perspective view, found --view panorama");
    refused("--lod 2 --method embree",
            "--lod: expected a direct method (bilinear, bilinear-double, triangles, nearest), found --method embree");
}

TEST_CASE("Level of detail: render --lod over a DEM held as tiles keeps the coarser grids its cache can hold",
          "[cli][lod][tiles]") {
    TempDir dir("lod-tiles-cli");
    // A copy: the coarser grids are kept beside the DEM, and the source tree is no place for them.
    const std::string helens = dir.file("helens.tif");
    std::filesystem::copy_file(kHelens, helens);
    const std::string base = "render '" + helens + "' --size 200x150 --sky-samples 0 --threads 2 --lod 0.5 --verbose -o '";
    const CommandResult whole = runTerracast(base + dir.file("whole.png") + "'");
    INFO(whole.err);
    REQUIRE(whole.exitCode == 0);
    CHECK_THAT(whole.err, Catch::Contains("the first keeping every other vertex"));
    // The DEM is 2 x 2 tiles. A cache of 500 KiB holds every coarser grid (about 290 KiB): the same levels as in
    // memory, the same picture.
    const CommandResult roomy = runTerracast(base + dir.file("roomy.png") + "' --tile-cache 500K");
    INFO(roomy.err);
    REQUIRE(roomy.exitCode == 0);
    CHECK_THAT(roomy.err, Catch::Contains("the first keeping every other vertex"));
    CHECK_THAT(roomy.err, Catch::Contains("tiles: "));
    int w = 0, h = 0, w2 = 0, h2 = 0;
    CHECK(pixels(dir.file("whole.png"), w, h) == pixels(dir.file("roomy.png"), w2, h2));
    // A cache of 150 KiB: level 1 does not fit, level 2 (every 4th vertex) does, and takes over where level 1
    // would have ended; the tiles serve what is nearer.
    const CommandResult tight = runTerracast(base + dir.file("tight.png") + "' --tile-cache 150K");
    INFO(tight.err);
    REQUIRE(tight.exitCode == 0);
    CHECK_THAT(tight.err, Catch::Contains("the first keeping every 4th vertex"));
    CHECK_THAT(tight.err, Catch::Contains("coarser grid 1 would not fit in the tile cache"));
    const CommandResult exact =
        runTerracast("render '" + helens + "' --size 200x150 --sky-samples 0 --threads 2 -o '" + dir.file("exact.png") + "'");
    REQUIRE(exact.exitCode == 0);
    const auto a = pixels(dir.file("exact.png"), w, h), b = pixels(dir.file("tight.png"), w2, h2), c = pixels(dir.file("whole.png"), w2, h2);
    int64_t tightDiffer = 0, wholeDiffer = 0;
    for (size_t k = 0; k < a.size(); k += 3) {
        tightDiffer += std::abs(a[k] - b[k]) + std::abs(a[k + 1] - b[k + 1]) + std::abs(a[k + 2] - b[k + 2]) > 6;
        wholeDiffer += std::abs(a[k] - c[k]) + std::abs(a[k + 1] - c[k + 1]) + std::abs(a[k + 2] - c[k + 2]) > 6;
    }
    INFO(tightDiffer << " and " << wholeDiffer << " pixels differ from the exact picture");
    // Fewer coarse levels, and the first of them farther out: nearer the exact picture than the whole grid's.
    CHECK(tightDiffer > 0);
    CHECK(tightDiffer < wholeDiffer);
}

TEST_CASE("Level of detail: compare --lod reports the coarse surface beside the exact methods", "[cli][lod]") {
    const CommandResult r =
        runTerracast("compare '" + kHelens + "' --size 160x120 --methods bilinear --lod 2 --threads 2");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const size_t row = r.out.find("\nbilinear+lod2 ");
    REQUIRE(row != std::string::npos);
    // name, build s, memory (a number and a unit), camera and shadow rays per second, agreement with the
    // reference's hits and misses: high, not perfect.
    std::istringstream fields(r.out.substr(row + 1, r.out.find('\n', row + 1) - row - 1));
    std::string name, unit;
    double build = 0.0, memory = 0.0, primary = 0.0, shadow = 0.0, agreement = 0.0;
    fields >> name >> build >> memory >> unit >> primary >> shadow >> agreement;
    REQUIRE(fields);
    CHECK(primary > 0.0);
    CHECK(agreement > 0.9);
    CHECK(agreement < 1.0);
    CHECK_THAT(r.out, Catch::Contains("\nbilinear "));
}

TEST_CASE("Level of detail: compare over a DEM held as tiles tells the tiles each entry read", "[cli][lod][tiles]") {
    TempDir dir("lod-compare-tiles");
    const std::string helens = dir.file("helens.tif");
    std::filesystem::copy_file(kHelens, helens);
    const std::string command = "compare '" + helens + "' --size 160x120 --methods bilinear --lod 0.5 --threads 2 "
                                "--tile-cache 150K --json '" + dir.file("r.json") + "'";
    // The first run makes the coarser grid (level 2 fits in 150 KiB, level 1 does not) and keeps it beside the
    // DEM; the second takes it, leaving the file as it was.
    const std::string kept = helens + ".terracast-lod2";
    std::filesystem::file_time_type made;
    for (const int run : {1, 2}) {
        const CommandResult r = runTerracast(command);
        INFO(r.err);
        REQUIRE(r.exitCode == 0);
        const size_t line = r.out.find("tiles read from the DEM: ");
        REQUIRE(line != std::string::npos);
        const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
        INFO(text);
        CHECK_THAT(text, Catch::Contains("(of 4 tiles, a cache of 150.0 KiB)"));
        for (const char* entry : {"bilinear-double ", "bilinear ", "bilinear+lod0.5 "}) CHECK_THAT(text, Catch::Contains(entry));
        std::ifstream json(dir.file("r.json"));
        const std::string report((std::istreambuf_iterator<char>(json)), std::istreambuf_iterator<char>());
        CHECK_THAT(report, Catch::Contains("\"tile_loads\": "));
        REQUIRE(std::filesystem::exists(kept));
        if (run == 1) made = std::filesystem::last_write_time(kept);
        else CHECK(std::filesystem::last_write_time(kept) == made);
    }
}
