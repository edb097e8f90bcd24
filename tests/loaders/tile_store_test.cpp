// The store of decoded tiles beside a DEM held as tiles: tiles read back from it are the raster's, bit for bit
// (16-bit metres and floats, nodata, under an exaggeration); a second open reads every tile from it; a torn
// record, a store cut short or made for an earlier version of the DEM is never read.
#include "loaders/tile_store.h"
#include "loaders/tiled_dem.h"
#include "support/rewrite_dem.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal.h>

#include <bit>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace terracast;
using terracast::testing::raiseValidHeights;
using terracast::testing::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
constexpr size_t kWholeCache = size_t(1) << 28;

// Every vertex and cell flag of `b` against `a`, a tile at a time (each tile of `b` read once, even through a
// cache of one tile).
void checkSameTiles(const TiledDem& a, const TiledDem& b, bool holes = true) {
    REQUIRE(a.layout().width == b.layout().width);
    REQUIRE(a.layout().height == b.layout().height);
    int64_t heightsDiffer = 0, flagsDiffer = 0, cellsDiffer = 0, valid = 0, invalid = 0;
    for (int64_t tj = 0; tj < a.layout().tilesY(); ++tj)
        for (int64_t ti = 0; ti < a.layout().tilesX(); ++ti) {
            const auto ta = a.tile(ti, tj), tb = b.tile(ti, tj);
            REQUIRE(tb->firstX() == ta->firstX());
            REQUIRE(tb->firstY() == ta->firstY());
            REQUIRE(tb->verticesX() == ta->verticesX());
            REQUIRE(tb->verticesY() == ta->verticesY());
            for (int64_t j = ta->firstY(); j < ta->firstY() + ta->verticesY(); ++j)
                for (int64_t i = ta->firstX(); i < ta->firstX() + ta->verticesX(); ++i) {
                    const bool v = ta->vertexValid(i, j);
                    flagsDiffer += tb->vertexValid(i, j) != v;
                    if (v) {
                        ++valid;
                        heightsDiffer += std::bit_cast<uint32_t>(ta->at(i, j)) != std::bit_cast<uint32_t>(tb->at(i, j));
                    } else {
                        ++invalid;
                    }
                    if (i + 1 < ta->firstX() + ta->verticesX() && j + 1 < ta->firstY() + ta->verticesY())
                        cellsDiffer += ta->cellValid(i, j) != tb->cellValid(i, j);
                }
        }
    CHECK(heightsDiffer == 0);
    CHECK(flagsDiffer == 0);
    CHECK(cellsDiffer == 0);
    CHECK(valid > 0);
    if (holes) CHECK(invalid > 0);  // the validity bits are exercised
}

DemLoadOptions withStore(double exaggeration = 1.0) {
    DemLoadOptions o;
    o.tileStore = true;
    o.exaggeration = exaggeration;
    return o;
}

// St Helens rewritten as Float32 metres (a fraction added, so that they are not whole), nodata kept.
void writeFloatCopy(const std::string& from, const std::string& to) {
    GDALAllRegister();
    GDALDatasetH source = GDALOpen(from.c_str(), GA_ReadOnly);
    REQUIRE(source != nullptr);
    const int w = GDALGetRasterXSize(source), h = GDALGetRasterYSize(source);
    std::vector<float> z(size_t(w) * size_t(h));
    REQUIRE(GDALRasterIO(GDALGetRasterBand(source, 1), GF_Read, 0, 0, w, h, z.data(), w, h, GDT_Float32, 0, 0) == CE_None);
    const double nodata = GDALGetRasterNoDataValue(GDALGetRasterBand(source, 1), nullptr);
    for (size_t q = 0; q < z.size(); ++q)
        if (double(z[q]) != nodata) z[q] += 0.125f * float(q % 5);
    double geo[6];
    GDALGetGeoTransform(source, geo);
    GDALDatasetH out = GDALCreate(GDALGetDriverByName("GTiff"), to.c_str(), w, h, 1, GDT_Float32, nullptr);
    REQUIRE(out != nullptr);
    GDALSetGeoTransform(out, geo);
    GDALSetProjection(out, GDALGetProjectionRef(source));
    GDALSetRasterNoDataValue(GDALGetRasterBand(out, 1), nodata);
    REQUIRE(GDALRasterIO(GDALGetRasterBand(out, 1), GF_Write, 0, 0, w, h, z.data(), w, h, GDT_Float32, 0, 0) == CE_None);
    GDALClose(out);
    GDALClose(source);
}

// Overwrites `n` bytes of `file` at `offset` with `byte`.
void scribble(const std::string& file, int64_t offset, int n, char byte) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    REQUIRE(f);
    f.seekp(offset);
    const std::string bytes(size_t(n), byte);
    f.write(bytes.data(), n);
}

}  // namespace

TEST_CASE("Tile store: tiles read back from the store are the raster's, and a second open reads them all from it",
          "[loaders][tiles]") {
    TempDir dir("tile-store");
    const std::string helens = dir.file("helens.tif"), floats = dir.file("helens-float.tif");
    fs::copy_file(kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", helens);
    writeFloatCopy(helens, floats);
    const std::string hgt = dir.file("N44W072.hgt");
    fs::copy_file(kSamples + "N44W072.srtm3-white-mountains-nh.hgt", hgt);
    for (const auto& [path, values] : {std::pair{helens, TileStore::Values::WholeMetres},
                                       std::pair{floats, TileStore::Values::FloatMetres},
                                       std::pair{hgt, TileStore::Values::WholeMetres}}) {
        INFO(path);
        const TiledDem plain(path, kWholeCache);
        CHECK(plain.store() == nullptr);
        CHECK(plain.storeOrigin().empty());
        const int64_t tiles = plain.layout().tileCount();
        {
            // A cache of one tile: the second pass reads every tile again, from the store.
            const TiledDem first(path, 1, withStore());
            REQUIRE(first.store() != nullptr);
            CHECK(first.store()->fresh());
            CHECK(first.store()->values() == values);
            CHECK(first.storeOrigin() == "made " + TileStore::pathFor(path));
            checkSameTiles(plain, first, path != hgt);
            CHECK(first.store()->writes() == tiles);
            checkSameTiles(plain, first, path != hgt);
            CHECK(first.store()->writes() == tiles);
            CHECK(first.store()->reads() >= tiles - 1);
            CHECK(first.store()->reads() == first.cacheStats().loads - tiles);
        }
        const TiledDem second(path, kWholeCache, withStore());
        REQUIRE(second.store() != nullptr);
        CHECK_FALSE(second.store()->fresh());
        CHECK(second.storeOrigin() == "found " + TileStore::pathFor(path));
        checkSameTiles(plain, second, path != hgt);
        CHECK(second.store()->reads() == tiles);
        CHECK(second.store()->writes() == 0);
        CHECK(second.store()->diskBytes() > second.store()->fullBytes() / 2);
        CHECK(second.store()->diskBytes() <= second.store()->fullBytes());
    }
    // Exaggerated heights come from the store's unexaggerated ones, as from the raster (whole metres made floats,
    // then scaled); the transformed copies share the store.
    for (const double k : {2.5, 1.0 / 3.0}) {
        INFO("exaggeration " << k);
        DemLoadOptions plain;
        plain.exaggeration = k;
        const TiledDem reference(helens, kWholeCache, plain);
        const TiledDem stored(helens, kWholeCache, withStore(k));
        REQUIRE(stored.store() != nullptr);
        checkSameTiles(reference, stored);
        CHECK(stored.store()->reads() == stored.layout().tileCount());
    }
}

TEST_CASE("Tile store: a torn record, a store cut short or one made for an earlier DEM is not read",
          "[loaders][tiles]") {
    TempDir dir("tile-store-torn");
    const std::string helens = dir.file("helens.tif");
    fs::copy_file(kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", helens);
    const std::string store = TileStore::pathFor(helens);
    const TiledDem plain(helens, kWholeCache);
    const int64_t tiles = plain.layout().tileCount();
    {
        const TiledDem first(helens, kWholeCache, withStore());
        checkSameTiles(plain, first);
        REQUIRE(first.store()->writes() == tiles);
    }
    const int64_t size = int64_t(fs::file_size(store));
    // The header is one page (a short key): records start at 4096, each a whole number of pages.
    const int64_t record = (size - 4096) / tiles;
    REQUIRE(record * tiles + 4096 == size);
    REQUIRE(record % 4096 == 0);

    SECTION("a record with changed bytes is read from the raster and written again") {
        // Tile 1's heights, and a single byte of tile 2's.
        scribble(store, 4096 + record + 2000, 16, '\x5a');
        scribble(store, 4096 + 2 * record + 60001, 1, '\x7f');
        const TiledDem again(helens, kWholeCache, withStore());
        CHECK_FALSE(again.store()->fresh());
        checkSameTiles(plain, again);
        CHECK(again.store()->writes() == 2);
        CHECK(again.store()->reads() == tiles - 2);
        // ... and mended for the next open.
        const TiledDem mended(helens, kWholeCache, withStore());
        checkSameTiles(plain, mended);
        CHECK(mended.store()->reads() == tiles);
    }
    SECTION("a store cut short is made again") {
        fs::resize_file(store, uintmax_t(size - 1));
        const TiledDem again(helens, kWholeCache, withStore());
        CHECK(again.store()->fresh());
        checkSameTiles(plain, again);
        CHECK(again.store()->reads() == 0);
        CHECK(int64_t(fs::file_size(store)) == size);
    }
    SECTION("a DEM rewritten since gets a new store, holding its new heights") {
        // The same raster with every height 7 m higher, in a file of the same size: only the file's times tell.
        raiseValidHeights(helens, 7);
        const TiledDem rewritten(helens, kWholeCache);
        const TiledDem again(helens, kWholeCache, withStore());
        CHECK(again.store()->fresh());
        checkSameTiles(rewritten, again);
        CHECK(again.store()->reads() == 0);
        // The heights really changed: a store read under the old key would have given the old ones.
        CHECK(rewritten.at(300, 300) == plain.at(300, 300) + 7.0f);
    }
}

TEST_CASE("Tile store: records of edge tiles round-trip, and a record never written is missing", "[loaders][tiles]") {
    TempDir dir("tile-store-records");
    // 300 x 260 vertices: tiles of 257 x 257, 44 x 257, 257 x 4 and 44 x 4 vertices.
    const TileLayout layout{300, 260};
    std::string why;
    const auto store = TileStore::open(dir.file("s.terracast-tiles"), "some raster;", layout,
                                       TileStore::Values::FloatMetres, why);
    REQUIRE(store != nullptr);
    CHECK(why.empty());
    CHECK(store->fresh());
    CHECK(store->diskBytes() < store->fullBytes() / 2);  // sparse until tiles are written
    const int64_t w = 44, h = 4;
    std::vector<float> z(size_t(w * h));
    std::vector<uint8_t> valid(z.size());
    for (size_t k = 0; k < z.size(); ++k) {
        z[k] = 100.0f + 0.5f * float(k);
        valid[k] = uint8_t(k % 3 != 0 || k > 100);
    }
    store->write(3, w, h, z.data(), valid.data());
    std::vector<float> back(z.size());
    std::vector<uint8_t> backValid(z.size(), 9);
    REQUIRE(store->read(3, w, h, back.data(), backValid.data()));
    CHECK(back == z);
    CHECK(backValid == valid);
    CHECK_FALSE(store->read(0, 257, 257, std::vector<float>(257 * 257).data(), std::vector<uint8_t>(257 * 257).data()));
    CHECK_FALSE(store->read(4, w, h, back.data(), backValid.data()));  // no such tile
    // Another key, layout or kind of value makes a new store over the old one.
    const auto other = TileStore::open(dir.file("s.terracast-tiles"), "another raster;", layout,
                                       TileStore::Values::FloatMetres, why);
    REQUIRE(other != nullptr);
    CHECK(other->fresh());
    CHECK_FALSE(other->read(3, w, h, back.data(), backValid.data()));
    // A raster with no local file gets none.
    CHECK(TileStore::open(dir.file("t.terracast-tiles"), "", layout, TileStore::Values::FloatMetres, why) == nullptr);
    CHECK(why == "the raster cannot be named by its files (an in-memory or network source, or a VRT of VRTs)");
}
