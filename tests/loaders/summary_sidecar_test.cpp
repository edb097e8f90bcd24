// The summary sidecar of a DEM held as tiles: saved by the first open, read by the next ones only while it
// describes the DEM as it is (the file, a VRT's sources), made again otherwise; the summary read is the one a
// pass over the raster makes.
#include "loaders/summary_sidecar.h"
#include "loaders/tiled_dem.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using namespace terracast;
using terracast::testing::TempDir;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";

void checkSameSummary(const GridSummary& a, const GridSummary& b) {
    CHECK(a.width == b.width);
    CHECK(a.height == b.height);
    CHECK(a.minHeightM == b.minHeightM);
    CHECK(a.maxHeightM == b.maxHeightM);
    CHECK(a.nodataVertices == b.nodataVertices);
    CHECK(a.validCells == b.validCells);
    CHECK(a.storage == b.storage);
    CHECK(a.codeOffset == b.codeOffset);
    CHECK(a.codeScale == b.codeScale);
    CHECK(a.pyramid.offset == b.pyramid.offset);
    CHECK(a.pyramid.scale == b.pyramid.scale);
    CHECK(a.pyramid.codesPerMetre == b.pyramid.codesPerMetre);
    CHECK(a.tileMaxCodes == b.tileMaxCodes);
    CHECK(a.tileMinCodes == b.tileMinCodes);
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// Moves a file's modification time by `seconds`, as a rewrite of the file would.
void touch(const fs::path& file, int seconds) {
    fs::last_write_time(file, fs::last_write_time(file) + std::chrono::seconds(seconds));
}

}  // namespace

TEST_CASE("Summary sidecar: saved by the first open, read by the next, made again when the DEM changes",
          "[loaders][tiles]") {
    TempDir dir("sidecar");
    const fs::path dem = fs::path(dir.file("helens.tif"));
    fs::copy_file(kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", dem);
    const std::string sidecar = summarySidecarPath(dem.string());
    CHECK(sidecar == dem.string() + ".terracast-summary");

    const TiledDem first(dem.string(), size_t(1) << 24);
    CHECK(startsWith(first.summaryOrigin(), "one pass over the raster, saved to"));
    REQUIRE(fs::exists(sidecar));
    const TiledDem second(dem.string(), size_t(1) << 24);
    CHECK(second.summaryOrigin() == "read from " + sidecar);
    checkSameSummary(second.summary(), first.summary());

    SECTION("a DEM rewritten since is streamed again") {
        touch(dem, 5);
        const TiledDem again(dem.string(), size_t(1) << 24);
        CHECK(startsWith(again.summaryOrigin(), "one pass"));
        checkSameSummary(again.summary(), first.summary());
        // ... and the new sidecar serves the next open.
        CHECK(TiledDem(dem.string(), size_t(1) << 24).summaryOrigin() == "read from " + sidecar);
    }
    SECTION("a sidecar cut short, or another DEM's, is not read") {
        const auto size = fs::file_size(sidecar);
        fs::resize_file(sidecar, size - 3);
        CHECK(startsWith(TiledDem(dem.string(), size_t(1) << 24).summaryOrigin(), "one pass"));
        CHECK(fs::file_size(sidecar) == size);
        const fs::path other = fs::path(dir.file("storm-lake.tif"));
        fs::copy_file(kSamples + "landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", other);
        fs::copy_file(sidecar, summarySidecarPath(other.string()));
        CHECK(startsWith(TiledDem(other.string(), size_t(1) << 24).summaryOrigin(), "one pass"));
    }
    SECTION("a grid's summary stored under its key reads back; under another key it does not") {
        const std::string key = "a key";
        const std::string path = dir.file("stored.terracast-summary");
        REQUIRE(writeSummarySidecar(path, key, first.summary()).empty());
        const auto back = readSummarySidecar(path, key, first.summary().width, first.summary().height);
        REQUIRE(back);
        checkSameSummary(*back, first.summary());
        CHECK_FALSE(readSummarySidecar(path, "another key", first.summary().width, first.summary().height));
        CHECK_FALSE(readSummarySidecar(path, key, first.summary().width + 1, first.summary().height));
    }
}

TEST_CASE("Summary sidecar: a VRT's sidecar is made again when one of its sources changes", "[loaders][tiles]") {
    TempDir dir("sidecar-vrt");
    const fs::path source = fs::path(dir.file("helens.tif"));
    fs::copy_file(kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", source);
    const fs::path vrt = fs::path(dir.file("mosaic.vrt"));
    REQUIRE(std::system(("gdalbuildvrt -q '" + vrt.string() + "' '" + source.string() + "'").c_str()) == 0);
    CHECK(startsWith(TiledDem(vrt.string(), size_t(1) << 24).summaryOrigin(), "one pass"));
    CHECK(startsWith(TiledDem(vrt.string(), size_t(1) << 24).summaryOrigin(), "read from"));
    touch(source, 5);  // the VRT itself is unchanged
    CHECK(startsWith(TiledDem(vrt.string(), size_t(1) << 24).summaryOrigin(), "one pass"));
    // A VRT of that VRT: GDAL does not list the inner VRT's sources, so no sidecar could see them change.
    const fs::path outer = fs::path(dir.file("outer.vrt"));
    REQUIRE(std::system(("gdalbuildvrt -q '" + outer.string() + "' '" + vrt.string() + "'").c_str()) == 0);
    const TiledDem nested(outer.string(), size_t(1) << 24);
    CHECK(nested.summaryOrigin() == "one pass over the raster (not saved: its files cannot all be checked for "
                                    "changes (a network or in-memory source, or a VRT of VRTs))");
    CHECK_FALSE(fs::exists(summarySidecarPath(outer.string())));
}
