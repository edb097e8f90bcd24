// A level of detail's coarser grid of a DEM held as tiles, kept beside the DEM: the next open takes it instead of
// reading every tile, with the same heights and holes; a file cut short or damaged, or one made before the DEM
// was rewritten, is not taken; heights transformed for one job are never kept.
#include "heightfield/coarser_grid.h"
#include "loaders/summary_sidecar.h"
#include "loaders/tiled_dem.h"
#include "support/rewrite_dem.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal.h>

#include <bit>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace terracast;
using terracast::testing::raiseValidHeights;
using terracast::testing::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";

// A grid over a fresh TiledDem of `path` (its own cache of one tile), and the tiles it read making level 2.
struct Opened {
    std::shared_ptr<TiledDem> tiles;
    HeightGrid grid;
};
Opened open(const std::string& path) {
    auto tiles = std::make_shared<TiledDem>(path, size_t(200) << 10);
    const GridSummary summary = tiles->summary();
    HeightGrid grid(summary, 30.0, 30.0, tiles);
    return {std::move(tiles), std::move(grid)};
}

// Heights and flags of two coarse grids, vertex by vertex.
int64_t differences(const HeightGrid& a, const HeightGrid& b) {
    if (a.width() != b.width() || a.height() != b.height()) return -1;
    int64_t differ = 0;
    for (int64_t j = 0; j < a.height(); ++j)
        for (int64_t i = 0; i < a.width(); ++i) {
            differ += a.vertexValid(i, j) != b.vertexValid(i, j);
            if (a.vertexValid(i, j)) differ += std::bit_cast<uint32_t>(a.at(i, j)) != std::bit_cast<uint32_t>(b.at(i, j));
        }
    return differ;
}

}  // namespace

TEST_CASE("Coarse sidecar: a level of detail's coarser grid is kept beside the DEM and taken while it describes it",
          "[loaders][tiles][lod]") {
    TempDir dir("coarse-sidecar");
    const std::string helens = dir.file("helens.tif");
    fs::copy_file(kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", helens);
    const std::string sidecar = coarseSidecarPath(helens, 1.0, 2);
    CHECK(sidecar == helens + ".terracast-lod2");
    CHECK(coarseSidecarPath(helens, 2.5, 3) == helens + ".x2.5.terracast-lod3");
    // The reference: level 2 of the DEM loaded whole.
    const LoadedDem whole = loadDem(helens);
    const HeightGrid want = coarserGrid(coarserGrid(whole.grid));

    const Opened first = open(helens);
    const HeightGrid made = coarserGrid(first.grid, 2, 2);
    CHECK(first.tiles->cacheStats().loads == first.tiles->layout().tileCount());
    CHECK(differences(made, want) == 0);
    REQUIRE(fs::exists(sidecar));

    SECTION("the next open takes it without reading a tile") {
        const Opened again = open(helens);
        const HeightGrid kept = coarserGrid(again.grid, 2, 2);
        CHECK(again.tiles->cacheStats().loads == 0);
        CHECK(differences(kept, want) == 0);
        // Another level is another file, made by reading the tiles.
        const HeightGrid level1 = coarserGrid(again.grid, 1, 2);
        CHECK(again.tiles->cacheStats().loads == again.tiles->layout().tileCount());
        CHECK(differences(level1, coarserGrid(whole.grid)) == 0);
        CHECK(fs::exists(coarseSidecarPath(helens, 1.0, 1)));
    }
    SECTION("a file cut short, with a damaged height or another shape is made again") {
        const auto size = fs::file_size(sidecar);
        for (const int damage : {0, 1, 2}) {
            const bool cut = damage == 0;
            if (cut) {
                fs::resize_file(sidecar, size - 1);
            } else if (damage == 2) {
                // Width and height swapped: the same size of file, for a grid of another shape.
                std::fstream f(sidecar, std::ios::in | std::ios::out | std::ios::binary);
                const auto n = uintmax_t(want.width() * want.height());
                const int64_t swapped[2] = {want.height(), want.width()};
                REQUIRE(swapped[0] != swapped[1]);
                f.seekp(std::streamoff(size - n - 4 * n - 16));
                f.write(reinterpret_cast<const char*>(swapped), sizeof swapped);
            } else {
                // A valid vertex's height made infinite: the last vertex's height (a valid one in this DEM).
                std::fstream f(sidecar, std::ios::in | std::ios::out | std::ios::binary);
                const float inf = std::numeric_limits<float>::infinity();
                const auto n = uintmax_t(want.width() * want.height());
                REQUIRE(want.vertexValid(want.width() / 2, want.height() / 2));
                const auto k = uintmax_t(want.height() / 2 * want.width() + want.width() / 2);
                f.seekp(std::streamoff(size - n - 4 * n + 4 * k));
                f.write(reinterpret_cast<const char*>(&inf), 4);
            }
            INFO((damage == 0 ? "cut short" : damage == 1 ? "an infinite height" : "width and height swapped"));
            const Opened again = open(helens);
            CHECK(differences(coarserGrid(again.grid, 2, 2), want) == 0);
            CHECK(again.tiles->cacheStats().loads == again.tiles->layout().tileCount());
            CHECK(fs::file_size(sidecar) == size);
        }
    }
    SECTION("a DEM rewritten since gets its new heights, and a new file") {
        raiseValidHeights(helens, 7);
        const Opened again = open(helens);
        const HeightGrid coarse = coarserGrid(again.grid, 2, 2);
        CHECK(again.tiles->cacheStats().loads == again.tiles->layout().tileCount());
        const HeightGrid rewritten = coarserGrid(coarserGrid(loadDem(helens).grid));
        CHECK(differences(coarse, rewritten) == 0);
        CHECK(coarse.at(40, 40) == want.at(40, 40) + 7.0f);
        // ... kept for the next open under the new key.
        const Opened third = open(helens);
        CHECK(differences(coarserGrid(third.grid, 2, 2), rewritten) == 0);
        CHECK(third.tiles->cacheStats().loads == 0);
    }
    SECTION("heights transformed for one job (a viewshed's curved earth) are not kept") {
        HeightTransform lower;
        lower.curvatureCoeff = 0.85714;
        lower.observerXM = 1000.0;
        lower.observerYM = 2000.0;
        lower.earthRadiusM = 6371000.0;
        const HeightGrid curved = first.grid.transformed(lower);
        fs::remove(sidecar);
        (void)coarserGrid(curved, 2, 2);
        CHECK_FALSE(fs::exists(sidecar));
    }
}
