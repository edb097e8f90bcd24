// DEMs held as tiles through the executable: with --tile-cache a few tiles large, every map product and render
// writes the same bytes as from the whole grid; a DEM larger than --max-memory allows takes the tiled path by
// itself and renders as the whole grid does; `info` says how the DEM is held.
#include "support/run_command.h"
#include "support/sanitizers.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <gdal_priv.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

using namespace terracast::testing;

namespace {

const std::string kHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
const std::string kWhiteMountains = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/N44W072.srtm3-white-mountains-nh.hgt";

// Runs `args` with and without `tiles` appended; both must succeed and write `out` with the same bytes.
void checkSameBytes(const TempDir& dir, std::vector<std::string> args, const std::string& out,
                    const std::vector<std::string>& tiles) {
    RunSettings settings;
    settings.workDir = dir.path();
    settings.timeoutS = 300.0;
    args.push_back("-o");
    args.push_back(dir.file("whole-" + out));
    const ArgsResult whole = runTerracastArgs(args, settings);
    INFO(args[0] << " whole: " << whole.err);
    REQUIRE(whole.exitCode == 0);
    args.back() = dir.file("tiled-" + out);
    args.insert(args.end(), tiles.begin(), tiles.end());
    const ArgsResult tiled = runTerracastArgs(args, settings);
    INFO(args[0] << " tiled: " << tiled.err);
    REQUIRE(tiled.exitCode == 0);
    const std::string a = slurp(dir.file("whole-" + out)), b = slurp(dir.file("tiled-" + out));
    CHECK(a.size() > 1000);
    CHECK(a == b);
}

}  // namespace

// St Helens: 2 x 2 tiles, nodata along its edges, in a cache that holds less than three. (Three test cases rather
// than one, so that the sanitizer run's shards share them.)
const std::vector<std::string> kFewTiles{"--tile-cache", "500K"};

TEST_CASE("Tiled DEM: every map product from a cache of a few tiles is the whole grid's, byte for byte",
          "[cli][tiles][heavy]") {
    TempDir dir("tiled-cli");
    const std::vector<std::string>& tiles = kFewTiles;
    checkSameBytes(dir, {"shadow", kHelens, "--sun", "135,20"}, "shadow.tif", tiles);
    checkSameBytes(dir, {"horizon", kHelens, "--azimuth", "225"}, "horizon.tif", tiles);
    checkSameBytes(dir, {"viewshed", kHelens, "--observer", "562000,5115000", "--curvature-coeff", "0"}, "viewshed.tif",
                   tiles);
    // The curved earth's lowered copy and sky view's upside-down copy, as tiles over the same source.
    checkSameBytes(dir, {"viewshed", kHelens, "--observer", "562000,5115000"}, "curved.tif", tiles);
    checkSameBytes(dir, {"viewshed", kHelens, "--observer", "562000,5115000", "--values", "height"}, "height.tif",
                   tiles);
    checkSameBytes(dir, {"svf", kHelens, "--directions", "8", "--max-distance", "600"}, "svf.tif", tiles);
}

TEST_CASE("Tiled DEM: every render from a cache of a few tiles is the whole grid's, byte for byte", "[cli][tiles]") {
    TempDir dir("tiled-cli-render");
    const std::vector<std::string>& tiles = kFewTiles;
    checkSameBytes(dir, {"render", kHelens, "--size", "160x120"}, "render.png", tiles);
    checkSameBytes(dir, {"render", kHelens, "--size", "160x120", "--exaggeration", "2.5"}, "tall.png", tiles);
    checkSameBytes(dir, {"render", kHelens, "--view", "map", "--sky-samples", "2"}, "map.png", tiles);
}

TEST_CASE("Tiled DEM: a geographic .hgt's shadow map from a cache of a few tiles is the whole grid's, byte for byte",
          "[cli][tiles]") {
    TempDir dir("tiled-cli-hgt");
    // The White Mountains: 5 x 5 tiles of a geographic .hgt.
    checkSameBytes(dir, {"shadow", kWhiteMountains, "--sun", "250,12"}, "shadow-wm.tif", {"--tile-cache", "1M"});
}

TEST_CASE("Tiled DEM: info says how the DEM is held, and PNG height maps are not tiled", "[cli][tiles]") {
    CommandResult r = runTerracast("info '" + kHelens + "' --tile-cache 4M");
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.out, Catch::Contains("held:        as 2 x 2 tiles of 256 x 256 cells read on demand, a cache of "
                                      "4.0 MiB (2 pyramid levels resident)"));
    r = runTerracast("info '" + kHelens + "'");
    CHECK_THAT(r.out, Catch::Contains("held:        whole, in memory"));
    const std::string puget =
        std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";
    r = runTerracast("info '" + puget + "' --tile-cache 4M");
    CHECK(r.exitCode == 2);
    CHECK(r.err == "terracast: error: " + puget +
                       ": PNG height maps are read whole, not as tiles (convert it to a tiled GeoTIFF to hold it as "
                       "tiles: gdal_translate -co TILED=YES)\n");
    // A curved earth's viewshed traces a lowered copy over the same tiles: its tile reads are the job's.
    TempDir dir("tiled-info");
    r = runTerracast("viewshed '" + kHelens + "' --observer 562000,5115000 --tile-cache 4M -o '" +
                     dir.file("v.tif") + "'");
    CHECK(r.exitCode == 0);
    CHECK_THAT(r.err, Catch::Contains("DEM tiles: 4 loaded"));
}

TEST_CASE("Tiled DEM: a DEM larger than --max-memory allows is held as tiles by itself", "[cli][tiles]") {
    // Resident memory under the sanitizers is theirs as much as the grid's: the plain build measures it.
    if (!kResidentMemoryIsMeaningful) return;
    TempDir dir("tiled-auto");
    // 8193 x 4097 int16 vertices (a tiled, compressed GeoTIFF of smooth hills): about 450 MB to hold whole,
    // far more than a 300 MB limit leaves beside the process's libraries.
    const std::string big = dir.file("hills.tif");
    {
        GDALAllRegister();
        const int w = 8193, h = 4097;
        char** options = nullptr;
        options = CSLSetNameValue(options, "TILED", "YES");
        options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
        GDALDatasetUniquePtr ds(
            GetGDALDriverManager()->GetDriverByName("GTiff")->Create(big.c_str(), w, h, 1, GDT_Int16, options));
        CSLDestroy(options);
        REQUIRE(ds);
        double transform[6] = {500000.0, 10.0, 0.0, 5000000.0, 0.0, -10.0};
        ds->SetGeoTransform(transform);
        std::vector<int16_t> row(w);
        for (int j = 0; j < h; ++j) {
            for (int i = 0; i < w; ++i)
                row[size_t(i)] = int16_t(800.0 + 400.0 * std::sin(i * 0.004) * std::cos(j * 0.0031) + 0.01 * ((i * 7 + j * 13) % 101));
            REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, j, w, 1, row.data(), w, 1, GDT_Int16, 0, 0, nullptr) ==
                    CE_None);
        }
    }
    const CommandResult info = runTerracast("info '" + big + "' --max-memory 300M");
    INFO(info.err);
    CHECK(info.exitCode == 0);
    CHECK_THAT(info.out, Catch::Contains("held:        as 32 x 16 tiles of 256 x 256 cells read on demand"));
    checkSameBytes(dir, {"render", big, "--size", "96x64", "--sky-samples", "1"}, "render.png",
                   {"--max-memory", "300M"});
}

TEST_CASE("Tiled DEM: summaries count the tiles read and the reads the cache answered", "[cli][tiles]") {
    TempDir dir("tiled-traffic");
    RunSettings settings;
    settings.workDir = dir.path();
    // St Helens is 2 x 2 tiles: a shadow mask of every vertex reads each of them at least once.
    const ArgsResult tiled = runTerracastArgs({"shadow", kHelens, "-o", dir.file("t.tif"), "--tile-cache", "500K"}, settings);
    INFO(tiled.err);
    REQUIRE(tiled.exitCode == 0);
    const size_t at = tiled.err.find("DEM tiles: ");
    REQUIRE(at != std::string::npos);
    const long loads = std::stol(tiled.err.substr(at + 11));
    CHECK(loads >= 4);
    CHECK(tiled.err.find("% of ", at) != std::string::npos);
    const ArgsResult render = runTerracastArgs({"render", kHelens, "-o", dir.file("r.png"), "--size", "64x48",
                                                "--tile-cache", "500K"}, settings);
    INFO(render.err);
    REQUIRE(render.exitCode == 0);
    CHECK(render.err.find("; tiles: ") != std::string::npos);
    // A DEM held whole says nothing of tiles.
    const ArgsResult whole = runTerracastArgs({"shadow", kHelens, "-o", dir.file("w.tif")}, settings);
    REQUIRE(whole.exitCode == 0);
    CHECK(whole.err.find("tiles: ") == std::string::npos);
}

TEST_CASE("Tiled DEM: --tile-store keeps the tiles decoded beside the DEM, and renders from it are the whole grid's",
          "[cli][tiles]") {
    TempDir dir("tiled-store");
    const std::string dem = dir.file("helens.tif");
    std::filesystem::copy_file(kHelens, dem);
    const std::vector<std::string> stored{"--tile-cache", "500K", "--tile-store"};
    // The first run makes the store and fills it; the second reads every tile from it. Both as the whole grid.
    checkSameBytes(dir, {"render", dem, "--size", "160x120"}, "first.png", stored);
    REQUIRE(std::filesystem::exists(dem + ".terracast-tiles"));
    RunSettings settings;
    settings.workDir = dir.path();
    const ArgsResult again = runTerracastArgs({"render", dem, "--size", "160x120", "-o", dir.file("again.png"),
                                               "--tile-cache", "500K", "--tile-store"}, settings);
    INFO(again.err);
    REQUIRE(again.exitCode == 0);
    CHECK(slurp(dir.file("again.png")) == slurp(dir.file("whole-first.png")));
    const size_t at = again.err.find("tiles: ");
    REQUIRE(at != std::string::npos);
    const long loads = std::stol(again.err.substr(at + 7));
    CHECK(loads >= 4);
    CHECK_THAT(again.err, Catch::Contains("(" + std::to_string(loads) + " from the tile store, 0 written to it)"));
    CommandResult info = runTerracast("info '" + dem + "' --tile-cache 4M --tile-store");
    CHECK(info.exitCode == 0);
    CHECK_THAT(info.out, Catch::Contains("tile store:  found " + dem + ".terracast-tiles ("));
    // Held whole, the option does nothing, and says so.
    info = runTerracast("info '" + dem + "' --tile-store");
    CHECK(info.exitCode == 0);
    CHECK_THAT(info.err, Catch::Contains(dem + ": --tile-store has no effect: the DEM is held whole in memory"));
}
