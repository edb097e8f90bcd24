// The 16-bit PNG height maps `bench --file-to-picture` writes read back, through the DEM loader `render` uses, as
// the grid's heights rounded to whole metres and clamped to 0..65535, rows the right way up.
#include "loaders/height_png.h"
#include "heightfield/fractal_terrain.h"
#include "loaders/dem_loader.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace terracast;

TEST_CASE("encodeHeightPng16: a fractal grid reads back as its heights in whole metres", "[cli][bench]") {
    FractalTerrainOptions fo;
    fo.size = 129;
    fo.seed = 7;
    const HeightGrid grid = fractalTerrain(fo);
    DemLoadOptions lo;
    lo.imageCellSizeM = 30.0;
    const LoadedDem dem = loadDemFromBytes(encodeHeightPng16(grid), "fractal.png", lo);
    REQUIRE(dem.grid.width() == grid.width());
    REQUIRE(dem.grid.height() == grid.height());
    CHECK(dem.grid.cellSizeXM() == 30.0);
    for (int64_t j = 0; j < grid.height(); ++j)
        for (int64_t i = 0; i < grid.width(); ++i) {
            const float expected = float(std::clamp(std::lround(grid.at(i, j)), 0L, 65535L));
            if (dem.grid.at(i, j) != expected) {
                INFO("vertex " << i << ", " << j << ": " << grid.at(i, j));
                REQUIRE(dem.grid.at(i, j) == expected);
            }
        }
}

TEST_CASE("encodeHeightPng16: heights outside 0..65535 are clamped", "[cli][bench]") {
    // Samples spanning both ends and the byte boundaries the Sub filter must carry no borrow across.
    const std::vector<float> heights{-20.0f, 0.4f, 255.0f, 256.0f, 255.6f, 70000.0f, 65535.0f, 1.5f, 512.0f};
    const HeightGrid grid(3, 3, 30.0, 30.0, heights);
    const LoadedDem dem = loadDemFromBytes(encodeHeightPng16(grid), "clamped.png", {});
    const float expected[] = {0, 0, 255, 256, 256, 65535, 65535, 2, 512};
    for (int64_t j = 0; j < 3; ++j)
        for (int64_t i = 0; i < 3; ++i) {
            INFO("vertex " << i << ", " << j);
            CHECK(dem.grid.at(i, j) == expected[j * 3 + i]);
        }
}
