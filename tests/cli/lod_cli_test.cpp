// `render --lod` and `compare --lod` through the executable: the level of detail changes some pixels and not
// most, is refused where it cannot apply, and compare reports it beside the exact methods.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <gdal_priv.h>

#include <cmath>
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
    refused("--lod 2 --tile-cache 500K", kHelens + ": --lod needs the DEM held in memory, and it is held as tiles "
                                                   "(it does not fit in --max-memory, or --tile-cache asks for tiles)");
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
