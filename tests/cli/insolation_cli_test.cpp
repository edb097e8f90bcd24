// `terracast insolation` end to end: a flat georeferenced DEM's day against GRASS r.sun, a real DEM's bands and
// metadata, the weights of --day-step, and the refusals.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace terracast::testing;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

// A flat DEM at `heightM`, columns x rows samples of `stepDeg` degrees centred on (lon, lat), in WGS 84.
void writeFlatLonLat(const std::string& path, double lon, double lat, float heightM, int columns = 11, int rows = 11,
                     double stepDeg = 0.001) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    std::unique_ptr<GDALDataset> ds(driver->Create(path.c_str(), columns, rows, 1, GDT_Float32, nullptr));
    REQUIRE(ds);
    double gt[6] = {lon - 0.5 * columns * stepDeg, stepDeg, 0.0, lat + 0.5 * rows * stepDeg, 0.0, -stepDeg};
    ds->SetGeoTransform(gt);
    OGRSpatialReference wgs;
    wgs.importFromEPSG(4326);
    char* wkt = nullptr;
    wgs.exportToWkt(&wkt);
    ds->SetProjection(wkt);
    CPLFree(wkt);
    std::vector<float> z(size_t(columns) * size_t(rows), heightM);
    REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, columns, rows, z.data(), columns, rows, GDT_Float32, 0, 0) ==
            CE_None);
}

// Band `band` (1-based) of a GeoTIFF at sample (x, y), row 0 at the north.
double sample(const std::string& path, int band, int x, int y) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(ds);
    double v = 0.0;
    REQUIRE(ds->GetRasterBand(band)->RasterIO(GF_Read, x, y, 1, 1, &v, 1, 1, GDT_Float64, 0, 0) == CE_None);
    return v;
}

// Every band of a raster, read once (opening the file for each sample costs a tenth of a second under the
// sanitizers).
struct Bands {
    int width = 0;
    std::vector<std::vector<double>> values;
    explicit Bands(const std::string& path) {
        GDALAllRegister();
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        REQUIRE(ds);
        width = ds->GetRasterXSize();
        const int height = ds->GetRasterYSize();
        for (int b = 1; b <= ds->GetRasterCount(); ++b) {
            std::vector<double>& v = values.emplace_back(size_t(width) * size_t(height));
            REQUIRE(ds->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, width, height, v.data(), width, height,
                                                   GDT_Float64, 0, 0) == CE_None);
        }
    }
    double operator()(int band, int x, int y) const { return values[size_t(band - 1)][size_t(y) * size_t(width) + size_t(x)]; }
};

}  // namespace

TEST_CASE("CLI: insolation of a flat DEM over a June day matches GRASS r.sun", "[cli][maps]") {
    // r.sun 8.2 on a flat cell at 45 N, 500 m, day 172, step 0.05 h, Linke 3, albedo 0.2: beam 7691.773 and
    // diffuse 1278.647 Wh/m^2, 15.4 hours of sun (whole steps; its day is 15.43 h). terracast places the sun by
    // the instant (2026-06-21, 3-minute steps); r.sun by its declination formula in solar time.
    TempDir dir("insolation-cli");
    const std::string dem = (dir.path() / "flat.tif").string(), out = (dir.path() / "sun.tif").string();
    writeFlatLonLat(dem, 0.0, 45.0, 500.0f);
    const auto r = runTerracast("insolation '" + dem + "' --date 2026-06-21 --step 3m -o '" + out + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(sample(out, 1, 5, 5) == Approx(7691.773).epsilon(0.01));
    CHECK(sample(out, 2, 5, 5) == Approx(1278.647).epsilon(0.01));
    CHECK(sample(out, 3, 5, 5) == 0.0);
    CHECK(sample(out, 4, 5, 5) == Approx(7691.773 + 1278.647).epsilon(0.01));
    CHECK(sample(out, 5, 5, 5) == Approx(15.43).margin(0.1));
    // Half a year later the day is 8.9 hours long (the same formula: cos w0 = -tan(lat) tan(decl)).
    const auto w = runTerracast("insolation '" + dem + "' --date 2026-12-21 --step 3m -o '" + out + "'");
    REQUIRE(w.exitCode == 0);
    const double w0 = std::acos(-std::tan(45.0 * M_PI / 180.0) * std::tan(-23.44 * M_PI / 180.0));
    CHECK(sample(out, 5, 5, 5) == Approx(2.0 * w0 * 12.0 / M_PI).margin(0.1));
}

TEST_CASE("CLI: insolation places the sun over each block of vertices, so a tall DEM's days lengthen northwards",
          "[cli][maps]") {
    // Flat ground from 40 to 45 N (101 rows of 0.05 degree, as tall as one local frame holds) on 2026-06-21.
    // Vertex rows 0-63 see the sun from their block's centre row 31.5 (41.575 N), rows 64-100 from row 82
    // (44.1 N): their days last 2 acos(-tan(lat) tan(decl)) / 15 degrees an hour, with the solstice's
    // declination 23.44 degrees.
    TempDir dir("insolation-cli");
    const std::string dem = (dir.path() / "tall.tif").string(), out = (dir.path() / "sun.tif").string();
    writeFlatLonLat(dem, 10.0, 42.5, 0.0f, 11, 101, 0.05);
    const auto r = runTerracast("insolation '" + dem + "' --date 2026-06-21 --step 3m -o '" + out + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const auto dayLength = [](double latDeg) {
        return 2.0 * std::acos(-std::tan(latDeg * M_PI / 180.0) * std::tan(23.44 * M_PI / 180.0)) * 12.0 / M_PI;
    };
    // Samples are read with row 0 at the north: vertex row j is sample row 100 - j.
    CHECK(sample(out, 5, 5, 100 - 10) == Approx(dayLength(40.0 + 31.5 * 0.05)).margin(0.1));
    CHECK(sample(out, 5, 5, 100 - 96) == Approx(dayLength(40.0 + 82 * 0.05)).margin(0.1));
    CHECK(sample(out, 5, 5, 100 - 96) - sample(out, 5, 5, 100 - 10) > 0.2);
}

TEST_CASE("CLI: insolation writes five labelled bands and --day-step weighs each day computed", "[cli][maps]") {
    TempDir dir("insolation-cli");
    const std::string one = (dir.path() / "one.tif").string(), three = (dir.path() / "three.tif").string(),
                      span = (dir.path() / "span.tif").string();
    const auto a = runTerracast("insolation '" + kStHelens + "' --date 2026-03-01 --step 1h -o '" + one + "'");
    INFO(a.err);
    REQUIRE(a.exitCode == 0);
    CHECK(a.err.find("vertex-sun positions") != std::string::npos);  // the summary
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(one.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(ds);
    REQUIRE(ds->GetRasterCount() == 5);
    CHECK(std::string(ds->GetRasterBand(4)->GetDescription()) == "global irradiation");
    CHECK(std::string(ds->GetRasterBand(4)->GetUnitType()) == "Wh/m2");
    CHECK(std::string(ds->GetRasterBand(5)->GetUnitType()) == "h");
    CHECK(std::string(ds->GetMetadataItem("TERRACAST_LINKE_TURBIDITY")) == "3");
    CHECK(std::string(ds->GetMetadataItem("TERRACAST_DATES")) == "2026-03-01/2026-03-01");
    // Global is the sum of the parts; nodata stays nodata; the crater's shaded walls get less than its rim.
    int sampled = 0;
    const Bands oneBands(one);
    for (int y = 20; y < 460; y += 37)
        for (int x = 15; x < 320; x += 29) {
            const double g = oneBands(4, x, y);
            if (g == -9999.0) continue;
            ++sampled;
            CHECK(g == Approx(oneBands(1, x, y) + oneBands(2, x, y) + oneBands(3, x, y)).epsilon(1e-5));
            CHECK(oneBands(5, x, y) <= 12.0);  // an equinox day is 12 hours long
        }
    CHECK(sampled > 100);
    // Three days with --day-step 2: March 1 counts twice (for the 1st and 2nd), March 3 once.
    const auto b = runTerracast("insolation '" + kStHelens + "' --date 2026-03-03 --step 1h -o '" + three + "'");
    const auto c = runTerracast("insolation '" + kStHelens +
                                "' --date 2026-03-01/2026-03-03 --day-step 2 --step 1h -o '" + span + "'");
    REQUIRE(b.exitCode == 0);
    REQUIRE(c.exitCode == 0);
    const Bands spanBands(span), threeBands(three);
    for (int band : {1, 2, 5})
        CHECK(spanBands(band, 160, 230) ==
              Approx(2.0 * oneBands(band, 160, 230) + threeBands(band, 160, 230)).epsilon(1e-5));
}

TEST_CASE("CLI: insolation refuses what it cannot honour in one line", "[cli][maps]") {
    TempDir dir("insolation-cli");
    const std::string out = (dir.path() / "x.tif").string();
    const std::string png = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";
    struct Bad {
        std::string args, expect;
    };
    const Bad cases[] = {
        {"--date 2026-02-30", "--date: expected a date YYYY-MM-DD"},
        {"--date 2026-06-21/2026-06-01", "END is before START"},
        {"--date 2026-06-21 --step 5x", "--step: expected a whole number > 0 with a unit"},
        {"--date 2026-06-21 --linke 0", "--linke: expected a Linke turbidity in [0.5, 10], found 0"},
        {"--date 2026-06-21 --albedo 1.5", "--albedo: expected a ground reflectance in [0, 1], found 1.5"},
        {"--date 2000-01-01/2026-12-31 --step 10s", "more than 200000"},
    };
    for (const Bad& bad : cases) {
        const auto r = runTerracast("insolation '" + kStHelens + "' " + bad.args + " -o '" + out + "'");
        INFO(bad.args << "\n" << r.err);
        CHECK(r.exitCode != 0);
        CHECK(r.err.find(bad.expect) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
    // A height map without a CRS cannot tell where the sun stands.
    const auto r = runTerracast("insolation '" + png + "' --date 2026-06-21 -o '" + out + "'");
    INFO(r.err);
    CHECK(r.exitCode != 0);
    CHECK(r.err.find("has no CRS") != std::string::npos);
    CHECK(!std::filesystem::exists(out));
}
