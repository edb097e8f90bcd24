// A DEM held as tiles read on demand, with a cache a few tiles large: every vertex, nodata flag and cell flag is
// the whole load's, across tile edges and nodata edges, while the cache stays within its bytes.
#include "heightfield/traversal.h"
#include "loaders/tiled_dem.h"
#include "support/sanitizers.h"
#include "support/temp_dir.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>
#include <gdal.h>

#include <bit>
#include <filesystem>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace terracast;
using terracast::testing::TempDir;

namespace {

std::string sample(const std::string& name) { return std::string(TERRACAST_SOURCE_DIR "/data-samples/") + name; }

// A raster's band 1 as float64, with its size and geotransform; the dataset stays open (the caller closes it) for
// its projection.
struct RasterValues {
    GDALDatasetH dataset = nullptr;
    int width = 0, height = 0;
    std::vector<double> values;
    double geo[6] = {};
};
RasterValues readRaster(const std::string& path) {
    GDALAllRegister();
    RasterValues r;
    r.dataset = GDALOpen(path.c_str(), GA_ReadOnly);
    REQUIRE(r.dataset != nullptr);
    r.width = GDALGetRasterXSize(r.dataset);
    r.height = GDALGetRasterYSize(r.dataset);
    r.values.resize(size_t(r.width) * size_t(r.height));
    REQUIRE(GDALRasterIO(GDALGetRasterBand(r.dataset, 1), GF_Read, 0, 0, r.width, r.height, r.values.data(), r.width,
                         r.height, GDT_Float64, 0, 0) == CE_None);
    GDALGetGeoTransform(r.dataset, r.geo);
    return r;
}

// Every vertex and cell of the tiled DEM against the loaded grid, in an order that revisits evicted tiles; both
// under a vertical exaggeration `k`.
void checkAgainstLoad(const std::string& path, int cacheTiles, double k = 1.0) {
    INFO(path << " exaggerated " << k);
    DemLoadOptions options;
    options.exaggeration = k;
    const LoadedDem dem = loadDem(path, options);
    const HeightGrid& g = dem.grid;
    // The bytes of a full tile (the first one is full in every DEM here).
    const size_t tileBytes = TiledDem(path, size_t(1) << 30, options).tile(0, 0)->bytes();
    const size_t budget = size_t(cacheTiles) * tileBytes + tileBytes / 2;
    const TiledDem tiled(path, budget, options);
    REQUIRE(tiled.layout().width == g.width());
    REQUIRE(tiled.layout().height == g.height());
    // The storage the whole grid chose for the (scaled) heights, and their range.
    CHECK(tiled.summary().storage == g.storage());
    CHECK(tiled.summary().codeScale == g.codeScale());
    CHECK(tiled.summary().minHeightM == g.minHeightM());
    CHECK(tiled.summary().maxHeightM == g.maxHeightM());
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
          "[loaders][tiles][heavy]") {
    // St Helens: 2 x 2 tiles (the edge ones part-filled), nodata along its edges; the White Mountains: 5 x 5 tiles, geographic; Nice: sea
    // and land in a geographic tile.
    checkAgainstLoad(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"), 1);
    checkAgainstLoad(sample("N44W072.srtm3-white-mountains-nh.hgt"), 3);
    checkAgainstLoad(sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif"), 3);
}

TEST_CASE("Tiled DEM: under a vertical exaggeration every tile holds the whole exaggerated grid's heights",
          "[loaders][tiles]") {
    // Metres scaled by 2.5 (int16 codes at 2.5 m) and by 1/3 (floats); decimetres, stored in int16 with a band
    // scale of 0.1, and decimetres that are whole metres (which the unscaled grid codes at 1 m), both doubled:
    // the scaled grid's int16 scale follows the unscaled grid's choice.
    const std::string helens = sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    checkAgainstLoad(helens, 1, 2.5);
    checkAgainstLoad(helens, 1, 1.0 / 3.0);
    TempDir dir("tiled-exaggerated");
    RasterValues read = readRaster(helens);
    GDALDatasetH source = read.dataset;
    const int w = read.width, h = read.height;
    const std::vector<double>& z = read.values;
    double* geo = read.geo;
    for (const bool wholeMetres : {false, true}) {
        const std::string path = dir.file(wholeMetres ? "metres-in-dm.tif" : "dm.tif");
        GDALDatasetH out = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, 1, GDT_Int16, nullptr);
        REQUIRE(out != nullptr);
        GDALSetGeoTransform(out, geo);
        GDALSetProjection(out, GDALGetProjectionRef(source));
        GDALRasterBandH band = GDALGetRasterBand(out, 1);
        GDALSetRasterScale(band, 0.1);
        GDALSetRasterNoDataValue(band, -32768);
        std::vector<int16_t> dm(z.size());
        for (size_t q = 0; q < z.size(); ++q)
            dm[q] = z[q] < -1000.0 ? int16_t(-32768) : int16_t(wholeMetres ? 10.0 * z[q] : 10.0 * z[q] + double(q % 7));
        REQUIRE(GDALRasterIO(band, GF_Write, 0, 0, w, h, dm.data(), w, h, GDT_Int16, 0, 0) == CE_None);
        GDALClose(out);
        DemLoadOptions plain;
        CHECK(loadDem(path, plain).grid.codeScale() == (wholeMetres ? 1.0 : 0.1));
        checkAgainstLoad(path, 1, 2.0);
    }
    GDALClose(source);
    // Each factor keeps its own sidecar beside the unscaled one.
    CHECK_FALSE(std::filesystem::exists(dir.file("dm.tif.terracast-summary")));
    CHECK(TiledDem(dir.file("dm.tif"), size_t(1) << 20).summary().codeScale == 0.1);
    CHECK(std::filesystem::exists(dir.file("dm.tif.terracast-summary")));
    CHECK(std::filesystem::exists(dir.file("dm.tif.x2.terracast-summary")));
    DemLoadOptions doubled;
    doubled.exaggeration = 2.0;
    CHECK(TiledDem(dir.file("dm.tif"), size_t(1) << 20, doubled).summaryOrigin() ==
          "read from " + dir.file("dm.tif.x2.terracast-summary"));
    // A factor that makes a height unusable is refused with the DEM's name, held whole or as tiles.
    doubled.exaggeration = 1e36;
    CHECK_THROWS_WITH(TiledDem(helens, size_t(1) << 20, doubled),
                      Catch::StartsWith(helens + ": a vertical exaggeration of 1e+36 makes a height of"));
    CHECK_THROWS_WITH(loadDem(helens, doubled),
                      Catch::StartsWith(helens + ": a vertical exaggeration of 1e+36 makes heights of up to 2543 m"));
}

TEST_CASE("Tiled DEM: tiles read from a GeoTIFF in 256 x 256 blocks, whose last row and column lie in the blocks "
          "beyond, are the whole load's",
          "[loaders][tiles]") {
    // A tile's window is a block and one more row and column, which the reader takes from the first row and column
    // of the blocks beyond, kept from when those were read. Sizes of 256 k + 1 vertices put the windows on block
    // corners in both directions (rows are mirrored: the raster runs north to south); 16-bit metres with nodata
    // holes straddling block edges (read as integers), and the same as float32 (read as float64), DEFLATE in
    // 256 x 256 blocks; the St Helens heights repeated to 769 x 513.
    const std::string helens = sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    TempDir dir("tiled-blocks");
    RasterValues read = readRaster(helens);
    GDALDatasetH source = read.dataset;
    const int sw = read.width, sh = read.height;
    const std::vector<double>& z = read.values;
    double* geo = read.geo;
    const int w = 769, h = 513;
    for (const GDALDataType type : {GDT_Int16, GDT_Float32}) {
        const std::string path = dir.file(type == GDT_Int16 ? "blocks16.tif" : "blocks32.tif");
        const char* options[] = {"TILED=YES", "BLOCKXSIZE=256", "BLOCKYSIZE=256", "COMPRESS=DEFLATE", nullptr};
        GDALDatasetH out = GDALCreate(GDALGetDriverByName("GTiff"), path.c_str(), w, h, 1, type, const_cast<char**>(options));
        REQUIRE(out != nullptr);
        GDALSetGeoTransform(out, geo);
        GDALSetProjection(out, GDALGetProjectionRef(source));
        GDALRasterBandH band = GDALGetRasterBand(out, 1);
        GDALSetRasterNoDataValue(band, -32768);
        std::vector<double> big(size_t(w) * size_t(h));
        for (int r = 0; r < h; ++r)
            for (int c = 0; c < w; ++c) {
                const double v = z[size_t((r % sh) * sw + c % sw)];
                // Holes across the block edges at row 256 and column 512 (and their corner).
                const bool hole = (std::abs(r - 256) < 3 && c > 200 && c < 300) || (std::abs(c - 512) < 2 && r > 100);
                big[size_t(r) * size_t(w) + size_t(c)] =
                    hole || v < -1000.0 ? -32768.0 : (type == GDT_Int16 ? v : v + 0.25 * double((r + c) % 4));
            }
        REQUIRE(GDALRasterIO(band, GF_Write, 0, 0, w, h, big.data(), w, h, GDT_Float64, 0, 0) == CE_None);
        int bx = 0, by = 0;
        GDALGetBlockSize(band, &bx, &by);
        REQUIRE(bx == 256);
        REQUIRE(by == 256);
        GDALClose(out);
        checkAgainstLoad(path, 1);
    }
    GDALClose(source);
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
