// `render`'s look end to end through the real executable: a drape written with GDAL colours the terrain where
// it was drawn, --colour gives one colour, and the default picture stands on its base before a neutral
// backdrop; bad look options are refused with one line.
#include "support/drape_rasters.h"
#include "support/run_command.h"
#include "support/temp_dir.h"
#include "loaders/dem_loader.h"
#include "loaders/image_io.h"

#include <catch2/catch.hpp>
#include <fmt/core.h>

#include <cmath>

using namespace terracast;
using namespace terracast::testing;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

}  // namespace

TEST_CASE("CLI: render --drape colours the terrain where the drape was drawn", "[cli][drape]") {
    TempDir dir("render-drape");
    const LoadedDem dem = loadDem(kStHelens);
    OGRSpatialReference utm;
    utm.importFromWkt(dem.geo.crsWkt.c_str());
    utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    // In the DEM's own CRS, covering it with a margin: red west of its centre easting, blue east of it.
    const double* gt = dem.geo.geoTransform;
    const double west = gt[0], north = gt[3], width = gt[1] * double(dem.sourceWidth);
    const double height = -gt[5] * double(dem.sourceHeight);
    const std::string drape = dir.file("split.tif");
    writeSplitRaster(drape, utm, west - 500.0, north + 500.0, 30.0, 30.0, int((width + 1000.0) / 30.0),
                     int((height + 1000.0) / 30.0), west + 0.5 * width);
    // Straight down on the DEM's centre, without perspective, the sun overhead and no sky light.
    const double cx = 0.5 * dem.grid.extentXM(), cy = 0.5 * dem.grid.extentYM();
    const std::string out = dir.file("draped.png");
    const std::string camera = fmt::format("eye={0},{1},10000 look={0},{1},0 up=0,1,0", cx, cy);
    const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --size 80x80 --view orthographic --camera '" +
                                camera + "' --sun 0,90 --sky none --drape '" + drape + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const RgbImage image = readImage(out);
    int westRed = 0, westOther = 0, eastBlue = 0, eastOther = 0;
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const float red = image.at(x, y, 0), blue = image.at(x, y, 2);
            if (std::abs(red - blue) < 0.02f) continue;  // the grey backdrop (or black where the terrain is unlit)
            if (x < image.width / 2 - 2) (red > 4.0f * blue ? westRed : westOther)++;
            if (x > image.width / 2 + 1) (blue > 4.0f * red ? eastBlue : eastOther)++;
        }
    CHECK(westRed > 1000);
    CHECK(eastBlue > 1000);
    CHECK(westOther == 0);
    CHECK(eastOther == 0);
}

TEST_CASE("CLI: render's default look stands the DEM on its base before a neutral backdrop", "[cli][base]") {
    TempDir dir("render-look");
    const std::string base = dir.file("default.png"), bare = dir.file("bare.png"), plain = dir.file("plain.png");
    const auto a = runTerracast("render '" + kStHelens + "' -o '" + base + "' --size 96x54");
    const auto b = runTerracast("render '" + kStHelens + "' -o '" + bare + "' --size 96x54 --no-base --background ground");
    const auto c = runTerracast("render '" + kStHelens + "' -o '" + plain + "' --size 96x54 --colour '#ff0000' --sky flat");
    INFO(a.err << b.err << c.err);
    REQUIRE(a.exitCode == 0);
    REQUIRE(b.exitCode == 0);
    REQUIRE(c.exitCode == 0);
    const RgbImage withBase = readImage(base), without = readImage(bare), red = readImage(plain);
    // The top-left corner is backdrop in both: neutral grey (equal channels) with the default, the Earth's
    // ground seen through the air (bluish) without.
    CHECK(withBase.at(1, 1, 0) == Approx(withBase.at(1, 1, 2)).margin(1e-3));
    CHECK(without.at(1, 1, 2) > without.at(1, 1, 0) + 0.01f);
    // Below the DEM's near corner (the automatic view looks from the south-west), the base's walls: the
    // picture's bottom-middle rows differ between the two.
    int differ = 0;
    for (int y = 40; y < 54; ++y)
        for (int x = 30; x < 66; ++x) differ += std::abs(withBase.at(x, y, 1) - without.at(x, y, 1)) > 0.02f;
    CHECK(differ > 50);
    // A plain red terrain has no green or blue of its own: where it is lit, red dominates.
    int reddish = 0;
    for (int y = 0; y < 54; ++y)
        for (int x = 0; x < 96; ++x) reddish += red.at(x, y, 0) > 3.0f * red.at(x, y, 1) + 0.01f;
    CHECK(reddish > 500);
}

TEST_CASE("CLI: render refuses look options that do not fit together", "[cli][base]") {
    TempDir dir("render-look-bad");
    const std::string out = dir.file("x.png");
    const auto check = [&](const std::string& args, const std::string& message) {
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --size 16x9 " + args);
        INFO(args);
        CHECK(r.exitCode == 2);
        CHECK(r.err.find(message) != std::string::npos);
    };
    check("--background studio", "--background: expected neutral, sky or ground, found 'studio'");
    check("--colour '#12345g'", "--colour: expected grey or ramp or a colour as #rrggbb, found '#12345g'");
    check("--view map --colour '#123456'", "--colour: expected grey or ramp, found '#123456'");
    check("--drape '" + kStHelens + "' --colour grey", "--drape and --colour both set the terrain's colour: give one");
    check("--drape /nonexistent/ortho.tif", "/nonexistent/ortho.tif");
}
