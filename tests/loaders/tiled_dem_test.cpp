// A DEM held as tiles read on demand, with a cache a few tiles large: every vertex, nodata flag and cell flag is
// the whole load's, across tile edges and nodata edges, while the cache stays within its bytes.
#include "heightfield/traversal.h"
#include "loaders/tiled_dem.h"
#include "support/sanitizers.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>
#include <gdal.h>

#include <bit>
#include <cmath>
#include <random>
#include <string>

using namespace terracast;

namespace {

std::string sample(const std::string& name) { return std::string(TERRACAST_SOURCE_DIR "/data-samples/") + name; }

// Every vertex and cell of the tiled DEM against the loaded grid, in an order that revisits evicted tiles.
void checkAgainstLoad(const std::string& path, int cacheTiles) {
    INFO(path);
    const LoadedDem dem = loadDem(path);
    const HeightGrid& g = dem.grid;
    // The bytes of a full tile (the first one is full in every DEM here).
    const size_t tileBytes = TiledDem(path, size_t(1) << 30).tile(0, 0)->bytes();
    const size_t budget = size_t(cacheTiles) * tileBytes + tileBytes / 2;
    const TiledDem tiled(path, budget);
    REQUIRE(tiled.layout().width == g.width());
    REQUIRE(tiled.layout().height == g.height());
    CHECK(tiled.summary().storage == g.storage());
    CHECK(tiled.summary().validCells == g.validCellCount());
    int64_t heightsDiffer = 0, flagsDiffer = 0, cellsDiffer = 0;
    // Columns first: each column of vertices crosses every tile row, so tiles are evicted and read again. Under the
    // sanitizers every tenth column (each crossing every tile row still).
    for (int64_t i = 0; i < g.width(); i += terracast::testing::kSweepDivisor)
        for (int64_t j = 0; j < g.height(); ++j) {
            const bool valid = g.vertexValid(i, j);
            flagsDiffer += tiled.vertexValid(i, j) != valid;
            if (valid) heightsDiffer += std::bit_cast<uint32_t>(tiled.at(i, j)) != std::bit_cast<uint32_t>(g.at(i, j));
            if (i < g.cellsX() && j < g.cellsY()) cellsDiffer += tiled.cellValid(i, j) != g.cellValid(i, j);
        }
    CHECK(heightsDiffer == 0);
    CHECK(flagsDiffer == 0);
    CHECK(cellsDiffer == 0);
    const TileCacheStats stats = tiled.cacheStats();
    INFO(stats.loads << " tile reads, " << stats.evictions << " evictions, peak " << stats.peakBytes << " bytes");
    CHECK(stats.peakBytes <= budget);
    if (tiled.layout().tileCount() > cacheTiles) CHECK(stats.evictions > 0);
}

}  // namespace

TEST_CASE("Tiled DEM: every vertex and cell flag equals the whole load's with a cache of a few tiles",
          "[loaders][tiles]") {
    // St Helens: 2 x 2 tiles (the edge ones part-filled), nodata along its edges; the White Mountains: 5 x 5 tiles, geographic; Nice: sea
    // and land in a geographic tile.
    checkAgainstLoad(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"), 1);
    checkAgainstLoad(sample("N44W072.srtm3-white-mountains-nh.hgt"), 3);
    checkAgainstLoad(sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif"), 3);
}

TEST_CASE("Tiled DEM: opening refuses what loading refuses, without reading it whole", "[loaders][tiles]") {
    CHECK_THROWS_AS(TiledDem(sample("no-such.tif"), 1 << 20), InputError);
    CHECK_THROWS_WITH(TiledDem(sample("README.md"), 1 << 20), Catch::Contains("README.md"));
}

TEST_CASE("Tiled DEM: rays through a grid of tiles read on demand hit as through the whole load",
          "[loaders][tiles]") {
    for (const char* name : {"usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif",
                             "N44W072.srtm3-white-mountains-nh.hgt"}) {
        INFO(name);
        const LoadedDem whole = loadDem(sample(name));
        const size_t tileBytes = TiledDem(sample(name), size_t(1) << 30).tile(0, 0)->bytes();
        const LoadedDem tiled = openTiledDem(sample(name), 2 * tileBytes);
        const HeightGrid& a = whole.grid;
        const HeightGrid& b = tiled.grid;
        REQUIRE(b.tiled());
        CHECK(b.width() == a.width());
        CHECK(b.cellSizeXM() == a.cellSizeXM());
        CHECK(b.cellSizeYM() == a.cellSizeYM());
        CHECK(tiled.geo.crsWkt == whole.geo.crsWkt);
        CHECK(tiled.geo.originX == whole.geo.originX);
        CHECK(tiled.driver == whole.driver);
        std::mt19937_64 rng(3);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        int64_t hits = 0, differ = 0;
        for (int k = 0; k < 2000 / terracast::testing::kSweepDivisor; ++k) {
            const glm::dvec3 o{u(rng) * a.extentXM(), u(rng) * a.extentYM(),
                               a.minHeightM() + (a.maxHeightM() - a.minHeightM()) * (0.5 + u(rng))};
            const double az = 2.0 * M_PI * u(rng), el = -0.4 * u(rng);
            const Ray ray{o, {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)}};
            const auto ha = intersect(a, ray, {0.0, kInfinity}, CellMethod::Bilinear);
            const auto hb = intersect(b, ray, {0.0, kInfinity}, CellMethod::Bilinear);
            hits += ha.has_value();
            differ += ha.has_value() != hb.has_value() || (ha && std::bit_cast<uint64_t>(ha->t) != std::bit_cast<uint64_t>(hb->t));
            differ += occluded(a, ray, {0.0, 3000.0}, CellMethod::Triangles) !=
                      occluded(b, ray, {0.0, 3000.0}, CellMethod::Triangles);
        }
        CHECK(hits > 500 / terracast::testing::kSweepDivisor);
        CHECK(differ == 0);
        const TileCacheStats stats = b.tileSource()->cacheStats();
        INFO(stats.loads << " tile reads");
        if (TileLayout{a.width(), a.height()}.tileCount() > 2) CHECK(stats.evictions > 0);
        CHECK(stats.peakBytes <= 2 * tileBytes);
    }
}

TEST_CASE("Tiled DEM: GDAL's own cache of decoded blocks is held to its bound while a DEM is read as tiles",
          "[loaders][tiles]") {
    // GDAL's default (5 % of the machine's memory) would let it keep every block of a DEM read once.
    const int64_t saved = GDALGetCacheMax64();
    GDALSetCacheMax64(int64_t{1} << 30);
    {
        const TiledDem tiled(sample("N44W072.srtm3-white-mountains-nh.hgt"), 1 << 20);
        CHECK(GDALGetCacheMax64() == TiledDem::kSourceBlockCacheBytes);
        for (int64_t tj = 0; tj < tiled.layout().tilesY(); ++tj)
            for (int64_t ti = 0; ti < tiled.layout().tilesX(); ++ti) CHECK(tiled.tile(ti, tj));
        CHECK(GDALGetCacheUsed64() <= TiledDem::kSourceBlockCacheBytes);
    }
    // A lower bound someone set is kept.
    GDALSetCacheMax64(int64_t{4} << 20);
    { const TiledDem tiled(sample("N44W072.srtm3-white-mountains-nh.hgt"), 1 << 20); }
    CHECK(GDALGetCacheMax64() == int64_t{4} << 20);
    GDALSetCacheMax64(saved);
}
