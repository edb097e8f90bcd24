// The sky options end to end through the real executable: --sun-time and a scene's sun time place the sun where
// NOAA's equations put it over the DEM's centre, and bad sky options or a sun time with nowhere on the Earth to
// place it are refused with one line and exit 2.
#include "support/run_command.h"
#include "support/temp_dir.h"
#include "loaders/image_io.h"
#include "tracer/core/angles.h"
#include "tracer/sky/sun_position.h"

#include <catch2/catch.hpp>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <fstream>
#include <memory>
#include <regex>

using namespace terracast;
using namespace terracast::testing;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

// The longitude and latitude of a raster's centre, straight from GDAL: the geotransform at half its size,
// transformed from its CRS to WGS84.
void rasterCentre(const std::string& path, double& lon, double& lat) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(ds);
    double gt[6];
    REQUIRE(ds->GetGeoTransform(gt) == CE_None);
    double x = gt[0] + 0.5 * ds->GetRasterXSize() * gt[1] + 0.5 * ds->GetRasterYSize() * gt[2];
    double y = gt[3] + 0.5 * ds->GetRasterXSize() * gt[4] + 0.5 * ds->GetRasterYSize() * gt[5];
    OGRSpatialReference source(*ds->GetSpatialRef()), wgs84;
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&source, &wgs84));
    REQUIRE(t);
    REQUIRE(t->Transform(1, &x, &y));
    lon = x;
    lat = y;
}

// The azimuth and elevation a command printed for the sun.
// The sun's azimuth from true north, from grid north, and its elevation, as the run printed them.
bool printedSun(const std::string& err, double& azimuth, double& elevation, double* gridAzimuth = nullptr) {
    std::smatch m;
    if (!std::regex_search(err, m,
                           std::regex("azimuth ([0-9.-]+) from true north \\(([0-9.-]+) from grid north\\), "
                                      "elevation ([0-9.-]+) degrees")))
        return false;
    azimuth = std::stod(m[1]);
    if (gridAzimuth) *gridAzimuth = std::stod(m[2]);
    elevation = std::stod(m[3]);
    return true;
}

}  // namespace

TEST_CASE("CLI: render --sun-time puts the sun where it stands over the DEM then", "[cli][sky]") {
    TempDir dir("sky-cli");
    const std::string out = (dir.path() / "noon.png").string();
    const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --size 48x27 --sun-time 2026-06-21T12:30-07:00");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    double lon = 0, lat = 0;
    rasterCentre(kStHelens, lon, lat);
    const SolarPosition expected = solarPosition({2026, 6, 21, 19, 30, 0.0}, lat, lon);
    double azimuth = 0, elevation = 0;
    double gridAzimuth = 0.0;
    REQUIRE(printedSun(r.err, azimuth, elevation, &gridAzimuth));
    CHECK(azimuth == Approx(expected.azimuthDeg).margin(0.01));
    // The tile is in UTM zone 10 (central meridian 123 W): Transverse Mercator's meridian convergence at its centre,
    // atan(tan(lon - lon0) sin(lat)), turns grid north east of true north there.
    const double convergence = -degrees(std::atan(std::tan(radians(lon + 123.0)) * std::sin(radians(lat))));
    CHECK(gridAzimuth - azimuth == Approx(convergence).margin(0.02));
    CHECK(elevation == Approx(expected.apparentElevationDeg).margin(0.01));
    CHECK(elevation > 60.0);  // a June midday at 46 degrees north
    CHECK(r.err.find("2026-06-21T19:30:00Z") != std::string::npos);
    CHECK(readImage(out).width == 48);
}

TEST_CASE("CLI: a scene's sun time agrees with render's for the same DEM and instant", "[cli][sky][scene]") {
    TempDir dir("sky-cli");
    const std::string scene = (dir.path() / "timed.toml").string();
    std::ofstream(scene) << "[[object]]\ntype = \"heightfield\"\nfile = \"" << kStHelens
                         << "\"\n\n[[light]]\ntype = \"sun\"\ntime = 2026-12-21T16:00:00Z\n";
    const auto s = runTerracast("scene '" + scene + "' -o '" + (dir.path() / "s.png").string() +
                                "' --size 32x18 --allow-paths");
    const auto r = runTerracast("render '" + kStHelens + "' -o '" + (dir.path() / "r.png").string() +
                                "' --size 32x18 --sun-time 2026-12-21T16:00Z");
    INFO(s.err << r.err);
    REQUIRE(s.exitCode == 0);
    REQUIRE(r.exitCode == 0);
    double sa = 0, se = 0, ra = 0, re = 0;
    REQUIRE(printedSun(s.err, sa, se));
    REQUIRE(printedSun(r.err, ra, re));
    CHECK(sa == ra);
    CHECK(se == re);
    CHECK(se > 0.0);
    CHECK(se < 25.0);  // a winter morning
}

TEST_CASE("CLI: sky options and sun times that cannot be honoured are refused", "[cli][sky]") {
    TempDir dir("sky-cli");
    const std::string out = (dir.path() / "x.png").string();
    SECTION("an unknown sky model") {
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --sky cloudy");
        CHECK(r.exitCode == 2);
        CHECK(r.err == "terracast: error: --sky: expected physical, gradient, flat or none, found 'cloudy'\n");
    }
    SECTION("a negative haze") {
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --haze -1");
        CHECK(r.exitCode == 2);
        CHECK(r.err.find("--haze: expected a number in 0..1000, found -1") != std::string::npos);
    }
    SECTION("a time without a zone") {
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --sun-time 2026-06-21T12:00");
        CHECK(r.exitCode == 2);
        CHECK(r.err.find("--sun-time: expected an ISO 8601 time") != std::string::npos);
        CHECK(r.err.find("needs a zone") != std::string::npos);
    }
    SECTION("a height map with no place on the Earth") {
        const std::string png = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";
        const auto r = runTerracast("render '" + png + "' -o '" + out + "' --sun-time 2026-06-21T12:00Z");
        CHECK(r.exitCode == 2);
        CHECK(r.err.find("has no CRS to tell where on the Earth it lies") != std::string::npos);
    }
    SECTION("a scene with a timed sun and no height field") {
        const std::string scene = (dir.path() / "nowhere.toml").string();
        std::ofstream(scene) << "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n\n[[light]]\ntype = \"sun\"\n"
                                "time = \"2026-06-21T12:00Z\"\n";
        const auto r = runTerracast("scene '" + scene + "' -o '" + out + "'");
        CHECK(r.exitCode == 2);
        CHECK(r.err.find("nowhere.toml:6:1: time: placing the sun by time needs a georeferenced height field") !=
              std::string::npos);
    }
    CHECK_FALSE(std::filesystem::exists(out));
}
