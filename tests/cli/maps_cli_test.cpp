// The map commands end to end: GeoTIFFs that carry the DEM's CRS and geotransform, read back with GDAL.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kDem =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif";

struct Georef {
    int width = 0, height = 0, bands = 0;
    double gt[6] = {0, 0, 0, 0, 0, 0};
    std::string wkt;
};

Georef readGeoref(const std::string& path) {
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
    REQUIRE(ds);
    Georef g;
    g.width = ds->GetRasterXSize();
    g.height = ds->GetRasterYSize();
    g.bands = ds->GetRasterCount();
    ds->GetGeoTransform(g.gt);
    g.wkt = ds->GetProjectionRef();
    return g;
}

bool sameCrs(const std::string& a, const std::string& b) {
    OGRSpatialReference x, y;
    return x.importFromWkt(a.c_str()) == OGRERR_NONE && y.importFromWkt(b.c_str()) == OGRERR_NONE && x.IsSame(&y);
}

}  // namespace

TEST_CASE("CLI: shadow, horizon and viewshed GeoTIFFs carry the DEM's CRS and geotransform", "[cli][maps]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-maps-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const Georef src = readGeoref(kDem);
    const std::string runs[] = {
        "shadow '" + kDem + "' --sun 250,15 -o '" + (dir / "shadow.tif").string() + "'",
        "horizon '" + kDem + "' --azimuth 250 -o '" + (dir / "horizon.tif").string() + "'",
        "viewshed '" + kDem + "' --observer 325000,5103000 --observer-height 2 -o '" + (dir / "vis.tif").string() + "'",
    };
    for (const auto& args : runs) {
        const auto r = runTerracast(args);
        INFO(args << "\n" << r.err);
        REQUIRE(r.exitCode == 0);
    }
    for (const char* name : {"shadow.tif", "horizon.tif", "vis.tif"}) {
        INFO(name);
        const Georef out = readGeoref((dir / name).string());
        CHECK(out.width == src.width);
        CHECK(out.height == src.height);
        for (int k = 0; k < 6; ++k) CHECK(out.gt[k] == Approx(src.gt[k]).margin(1e-6));
        CHECK(sameCrs(out.wkt, src.wkt));
    }
    // The map view: the DEM's own raster (it stacks on the DEM), RGB and an alpha band that is 0 exactly where
    // the DEM's samples are nodata and belong to no valid cell.
    REQUIRE(runTerracast("render '" + kDem + "' --view map -o '" + (dir / "map.tif").string() + "'").exitCode == 0);
    const Georef map = readGeoref((dir / "map.tif").string());
    CHECK(map.width == src.width);
    CHECK(map.height == src.height);
    CHECK(map.bands == 4);
    for (int k = 0; k < 6; ++k) CHECK(map.gt[k] == Approx(src.gt[k]).margin(1e-6));
    CHECK(sameCrs(map.wkt, src.wkt));
    {
        GDALAllRegister();
        std::unique_ptr<GDALDataset> m(GDALDataset::Open((dir / "map.tif").string().c_str(), GDAL_OF_RASTER));
        std::unique_ptr<GDALDataset> d(GDALDataset::Open(kDem.c_str(), GDAL_OF_RASTER));
        REQUIRE(m);
        REQUIRE(d);
        CHECK(m->GetRasterBand(4)->GetColorInterpretation() == GCI_AlphaBand);
        std::vector<uint8_t> alpha(size_t(src.width * src.height));
        std::vector<float> z(alpha.size());
        REQUIRE(m->GetRasterBand(4)->RasterIO(GF_Read, 0, 0, src.width, src.height, alpha.data(), src.width, src.height,
                                              GDT_Byte, 0, 0) == CE_None);
        REQUIRE(d->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, src.width, src.height, z.data(), src.width, src.height,
                                              GDT_Float32, 0, 0) == CE_None);
        int has = 0;
        const double nodata = d->GetRasterBand(1)->GetNoDataValue(&has);
        REQUIRE(has);
        int64_t transparent = 0, nodataSamples = 0;
        for (size_t k = 0; k < alpha.size(); ++k) {
            transparent += alpha[k] == 0;
            nodataSamples += z[k] == float(nodata);
            if (z[k] != float(nodata)) CHECK((alpha[k] == 255 || alpha[k] == 0));
            if (z[k] == float(nodata)) CHECK(alpha[k] == 0);
        }
        CHECK(nodataSamples > 0);
        // Every nodata sample is transparent; a valid sample only when it touches no valid cell (isolated).
        CHECK(transparent >= nodataSamples);
        CHECK(transparent <= nodataSamples + nodataSamples / 10);
    }
    // An observer outside the DEM is refused with exit 2 and nothing written.
    const auto bad = runTerracast("viewshed '" + kDem + "' --observer 0,0 -o '" + (dir / "none.tif").string() + "'");
    CHECK(bad.exitCode == 2);
    CHECK(lineCount(bad.err) <= 2);  // a units warning may precede the one error line
    CHECK(bad.err.find("--observer") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "none.tif"));
    fs::remove_all(dir);
}

TEST_CASE("CLI: map products' --verbose tells each phase's seconds, which add up to the whole", "[cli][maps]") {
    const TempDir dir("map-phases");
    const std::string out = (dir.path() / "product.tif").string();
    const std::string number = "([0-9]+\\.[0-9]+)";
    const std::regex phases("phases: reading the DEM and making the grid " + number + " s, set-up " + number +
                            " s, output tiles \\(computed, each written as it is finished\\) " + number + " s, COG " +
                            number + " s; total " + number + " s");
    for (const std::string& command :
         {"shadow '" + kDem + "' --sun 135,20", "horizon '" + kDem + "' --azimuth 90", "svf '" + kDem + "'",
          "insolation '" + kDem + "' --date 2026-06-21 --step 2h",
          "viewshed '" + kDem + "' --observer 325000,5103000 --observer-height 2"}) {
        INFO(command);
        const auto r = runTerracast(command + " -o '" + out + "' --threads 2 --verbose");
        REQUIRE(r.exitCode == 0);
        std::smatch m;
        REQUIRE(std::regex_search(r.err, m, phases));
        const double load = std::stod(m[1]), setup = std::stod(m[2]), tiles = std::stod(m[3]), cog = std::stod(m[4]),
                     total = std::stod(m[5]);
        // The phases follow one another within the whole (the rest: checks and the summary's own counting).
        CHECK(load + setup + tiles + cog <= total + 0.002);
        CHECK(load + setup + tiles + cog >= 0.8 * total - 0.002);
        CHECK(load > 0.0);
        CHECK(tiles > 0.0);
        CHECK(cog > 0.0);
        // A viewshed's set-up makes the curved earth's copy of the grid and the sight bounds.
        if (command.rfind("viewshed", 0) == 0) CHECK(setup > 0.0);
        // Without --verbose, the summary alone.
        const auto quiet = runTerracast(command + " -o '" + out + "' --threads 2");
        REQUIRE(quiet.exitCode == 0);
        CHECK(quiet.err.find("phases:") == std::string::npos);
    }
}

TEST_CASE("CLI: map products declare what they hold: bands, units, types, pixel-is-point", "[cli][maps]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-maps-meta-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string hgt = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/N44W072.srtm3-white-mountains-nh.hgt";
    const std::string runs[] = {
        "shadow '" + kDem + "' --sun 250,15 -o '" + (dir / "point.tif").string() + "'",
        "shadow '" + kDem + "' --sun 250,15 --sun-size 0.53 -o '" + (dir / "disc.tif").string() + "'",
        "horizon '" + kDem + "' --azimuths 0:360:90 --max-distance 900 -o '" + (dir / "four.tif").string() + "'",
        "svf '" + kDem + "' --directions 8 -o '" + (dir / "svf.tif").string() + "'",
        "horizon '" + hgt + "' --azimuth 90 --threads 2 -o '" + (dir / "hgt.tif").string() + "'",
    };
    for (const auto& args : runs) {
        const auto r = runTerracast(args);
        INFO(args << "\n" << r.err);
        REQUIRE(r.exitCode == 0);
        CHECK(r.err.find("horizon walks") + r.err.find("shadow walks") != 2 * std::string::npos);  // the summary
    }
    GDALAllRegister();
    auto open = [](const fs::path& p) {
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(p.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        REQUIRE(ds);
        return ds;
    };
    {
        // A point sun: bytes 0/1 with 255 for nodata; a disc: the hidden share as Float32.
        auto point = open(dir / "point.tif");
        GDALRasterBand* b = point->GetRasterBand(1);
        CHECK(b->GetRasterDataType() == GDT_Byte);
        int has = 0;
        CHECK(b->GetNoDataValue(&has) == 255.0);
        CHECK(has);
        CHECK(std::string(b->GetDescription()).find("shadow") != std::string::npos);
        auto disc = open(dir / "disc.tif");
        CHECK(disc->GetRasterBand(1)->GetRasterDataType() == GDT_Float32);
        CHECK(std::string(disc->GetMetadataItem("TERRACAST_SUN_SIZE_DEG")) == "0.53");
        // The source declares pixel-is-area and so do they.
        CHECK(std::string(point->GetMetadataItem("AREA_OR_POINT")) == "Area");
    }
    {
        // One band per azimuth in order, in degrees, with the settings in the metadata.
        auto four = open(dir / "four.tif");
        REQUIRE(four->GetRasterCount() == 4);
        CHECK(std::string(four->GetRasterBand(2)->GetDescription()) == "horizon angle towards azimuth 90 degrees");
        CHECK(std::string(four->GetRasterBand(4)->GetUnitType()) == "degree");
        CHECK(std::string(four->GetMetadataItem("TERRACAST_MAX_DISTANCE_M")) == "900");
        auto svf = open(dir / "svf.tif");
        REQUIRE(svf->GetRasterCount() == 3);
        CHECK(std::string(svf->GetRasterBand(1)->GetDescription()).find("sky-view factor") != std::string::npos);
        CHECK(std::string(svf->GetRasterBand(3)->GetUnitType()) == "degree");
        // Values in range: a sky-view factor in [0, 1] on valid vertices.
        std::vector<float> v(size_t(svf->GetRasterXSize() * svf->GetRasterYSize()));
        REQUIRE(svf->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, svf->GetRasterXSize(), svf->GetRasterYSize(), v.data(),
                                                 svf->GetRasterXSize(), svf->GetRasterYSize(), GDT_Float32, 0, 0) == CE_None);
        int64_t inRange = 0, nodata = 0;
        for (float x : v) {
            nodata += x == -9999.0f;
            inRange += x >= 0.0f && x <= 1.0f;
        }
        CHECK(nodata > 0);
        CHECK(inRange + nodata == int64_t(v.size()));
    }
    {
        // SRTM .hgt declares pixel-is-point: the output says so too, over the same corners.
        auto hgt = open(dir / "hgt.tif");
        CHECK(std::string(hgt->GetMetadataItem("AREA_OR_POINT")) == "Point");
        const Georef src = readGeoref(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/N44W072.srtm3-white-mountains-nh.hgt");
        double gt[6];
        hgt->GetGeoTransform(gt);
        for (int k = 0; k < 6; ++k) CHECK(gt[k] == Approx(src.gt[k]).margin(1e-9));
    }
    // An observer inside the raster's outer half-pixel is on the DEM (as gdal_viewshed takes it); one pixel
    // further out is not: west of the first valid sample of a row in the DEM's west column.
    const Georef src = readGeoref(kDem);
    int row = -1;
    {
        auto dem = open(kDem);
        GDALRasterBand* b = dem->GetRasterBand(1);
        int has = 0;
        const double nodata = b->GetNoDataValue(&has);
        for (int r = 1; r + 1 < src.height && row < 0; ++r) {
            float z[2];
            REQUIRE(b->RasterIO(GF_Read, 0, r - 1, 1, 2, z, 1, 2, GDT_Float32, 0, 0) == CE_None);
            if (!has || (z[0] != nodata && z[1] != nodata)) row = r;
        }
    }
    REQUIRE(row > 0);
    const double x0 = src.gt[0] + 0.5 * src.gt[1], yS = src.gt[3] + (row - 0.5) * src.gt[5];
    const auto edge = runTerracast(fmt::format("viewshed '{}' --observer {},{} -o '{}'", kDem, x0 - 0.4 * src.gt[1], yS,
                                               (dir / "edge.tif").string()));
    INFO(edge.err);
    CHECK(edge.exitCode == 0);
    const auto out = runTerracast(fmt::format("viewshed '{}' --observer {},{} -o '{}'", kDem, x0 - 0.6 * src.gt[1], yS,
                                              (dir / "out.tif").string()));
    CHECK(out.exitCode == 2);
    fs::remove_all(dir);
}

TEST_CASE("CLI: shadow --sun-time writes one band per time, in order, with the sun where it stands then",
          "[cli][maps]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-maps-times-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string helens =
        std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
    // Mt St Helens (46.2 N, 122.2 W) on the June solstice: before sunrise at 12:00Z (05:00 local), high at 20:00Z.
    const auto r = runTerracast("shadow '" + helens + "' --sun-time 2026-06-21T12:00Z/2026-06-21T20:00Z/4h -o '" +
                                (dir / "day.tif").string() + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    GDALAllRegister();
    std::unique_ptr<GDALDataset> ds(GDALDataset::Open((dir / "day.tif").string().c_str(), GDAL_OF_RASTER));
    REQUIRE(ds);
    REQUIRE(ds->GetRasterCount() == 3);  // 12:00, 16:00 and 20:00: END included
    const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
    double shadowedShare[3];
    for (int b = 1; b <= 3; ++b) {
        const std::string d = ds->GetRasterBand(b)->GetDescription();
        CHECK(d.find(b == 1 ? "T12:00:00Z" : b == 2 ? "T16:00:00Z" : "T20:00:00Z") != std::string::npos);
        std::vector<uint8_t> v(size_t(w) * size_t(h));
        REQUIRE(ds->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, w, h, v.data(), w, h, GDT_Byte, 0, 0) == CE_None);
        int64_t shadowed = 0, valid = 0;
        for (uint8_t x : v) {
            valid += x != 255;
            shadowed += x == 1;
        }
        shadowedShare[b - 1] = double(shadowed) / double(valid);
    }
    // The sun 3 degrees below the horizontal: only vertices whose terrain falls away to the north-east see it.
    CHECK(shadowedShare[0] > 0.8);
    CHECK(shadowedShare[0] < 0.97);
    CHECK(shadowedShare[2] < 0.02);  // the sun at 62 degrees from the south-east
    CHECK(shadowedShare[1] > shadowedShare[2]);
    // A bad range is one line, exit 2, nothing written.
    const auto bad = runTerracast("shadow '" + helens + "' --sun-time 2026-06-21T12:00Z/2026-06-21T10:00Z/1h -o '" +
                                  (dir / "bad.tif").string() + "'");
    CHECK(bad.exitCode == 2);
    CHECK(bad.err.find("END is before START") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "bad.tif"));
    fs::remove_all(dir);
}

TEST_CASE("CLI: viewshed from many observers counts them and a vector file in another CRS gives the same count",
          "[cli][maps]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-maps-observers-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string helens =
        std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
    const double pts[3][2] = {{562000.0, 5115000.0}, {563500.0, 5116500.0}, {561000.0, 5113500.0}};
    {
        std::ofstream csv(dir / "obs.csv");
        csv << "x,y\n";
        for (const auto& p : pts) csv << fmt::format("{},{}\n", p[0], p[1]);
    }
    // The same points as WGS84 GeoJSON, converted here by OGR from the DEM's CRS.
    {
        GDALAllRegister();
        std::unique_ptr<GDALDataset> d(GDALDataset::Open(helens.c_str(), GDAL_OF_RASTER));
        REQUIRE(d);
        OGRSpatialReference utm, wgs;
        utm.importFromWkt(d->GetProjectionRef());
        utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        wgs.importFromEPSG(4326);
        wgs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&utm, &wgs));
        REQUIRE(t);
        std::ofstream json(dir / "obs.geojson");
        json << "{\"type\":\"FeatureCollection\",\"features\":[";
        for (int k = 0; k < 3; ++k) {
            double x = pts[k][0], y = pts[k][1];
            REQUIRE(t->Transform(1, &x, &y));
            json << (k ? "," : "") << fmt::format("{{\"type\":\"Feature\",\"properties\":{{}},\"geometry\":{{\"type\":"
                                                  "\"Point\",\"coordinates\":[{:.12f},{:.12f}]}}}}",
                                                  x, y);
        }
        json << "]}\n";
    }
    auto run = [&](const std::string& args) {
        const auto r = runTerracast("viewshed '" + helens + "' " + args);
        INFO(args << "\n" << r.err);
        REQUIRE(r.exitCode == 0);
    };
    run("--observers '" + (dir / "obs.csv").string() + "' -o '" + (dir / "count.tif").string() + "'");
    run("--observers '" + (dir / "obs.geojson").string() + "' -o '" + (dir / "json.tif").string() + "'");
    for (int k = 0; k < 3; ++k)
        run(fmt::format("--observer {},{} -o '{}'", pts[k][0], pts[k][1], (dir / fmt::format("one{}.tif", k)).string()));
    run(fmt::format("--observer {},{} --max-distance 2000 -o '{}'", pts[0][0], pts[0][1], (dir / "near.tif").string()));
    auto read = [](const fs::path& p) {
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(p.string().c_str(), GDAL_OF_RASTER));
        REQUIRE(ds);
        std::vector<float> v(size_t(ds->GetRasterXSize()) * size_t(ds->GetRasterYSize()));
        REQUIRE(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, ds->GetRasterXSize(), ds->GetRasterYSize(), v.data(),
                                               ds->GetRasterXSize(), ds->GetRasterYSize(), GDT_Float32, 0, 0) == CE_None);
        return v;
    };
    const auto count = read(dir / "count.tif"), json = read(dir / "json.tif"), near = read(dir / "near.tif");
    const auto a = read(dir / "one0.tif"), b = read(dir / "one1.tif"), c = read(dir / "one2.tif");
    int64_t seenByTwo = 0, mismatched = 0, cut = 0;
    for (size_t k = 0; k < count.size(); ++k) {
        if (a[k] == 255.0f) {
            CHECK(count[k] == 255.0f);
            continue;
        }
        REQUIRE(count[k] == a[k] + b[k] + c[k]);
        seenByTwo += count[k] >= 2.0f;
        mismatched += json[k] != count[k];  // the GeoJSON's points, back from 12 decimals of a degree
        cut += a[k] == 1.0f && near[k] == 0.0f;
        if (near[k] == 1.0f) CHECK(a[k] == 1.0f);
    }
    CHECK(seenByTwo > 1000);
    CHECK(mismatched <= int64_t(count.size() / 1000));
    CHECK(cut > 100);  // visible, but beyond 2 km
    fs::remove_all(dir);
}

TEST_CASE("CLI: viewshed --values height and angle write what a target needs and the angle it is seen at",
          "[cli][maps]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-maps-values-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::string base = "viewshed '" + kDem + "' --observer 325000,5103000 --observer-height 2 ";
    const std::string vis = (dir / "vis.tif").string(), need = (dir / "need.tif").string(),
                      angle = (dir / "angle.tif").string();
    for (const std::string& args : {base + "-o '" + vis + "'", base + "--values height -o '" + need + "'",
                                    base + "--values angle -o '" + angle + "'"}) {
        const auto r = runTerracast(args);
        INFO(args << "\n" << r.err);
        REQUIRE(r.exitCode == 0);
    }
    GDALAllRegister();
    auto read = [](const std::string& path, std::string& unit, double& noData) {
        std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        REQUIRE(ds);
        GDALRasterBand* b = ds->GetRasterBand(1);
        unit = b->GetUnitType();
        noData = b->GetNoDataValue();
        std::vector<double> v(size_t(ds->GetRasterXSize()) * size_t(ds->GetRasterYSize()));
        REQUIRE(b->RasterIO(GF_Read, 0, 0, ds->GetRasterXSize(), ds->GetRasterYSize(), v.data(), ds->GetRasterXSize(),
                            ds->GetRasterYSize(), GDT_Float64, 0, 0) == CE_None);
        return v;
    };
    std::string unitV, unitN, unitA;
    double ndV = 0, ndN = 0, ndA = 0;
    const auto v = read(vis, unitV, ndV), n = read(need, unitN, ndN), a = read(angle, unitA, ndA);
    CHECK(unitN == "m");
    CHECK(unitA == "degree");
    // Where the ground is seen it needs no height and has an angle; where it is hidden it needs some and has none.
    int64_t seen = 0, hidden = 0;
    for (size_t k = 0; k < v.size(); ++k) {
        if (v[k] == ndV) {
            CHECK(n[k] == ndN);
            continue;
        }
        if (n[k] > 0.0 && n[k] < 0.01) continue;  // grazing sight lines
        INFO("sample " << k);
        CHECK((v[k] == 1.0) == (n[k] == 0.0));
        CHECK((v[k] == 1.0) == (a[k] != ndA));
        (v[k] == 1.0 ? seen : hidden) += 1;
        if (v[k] == 1.0) CHECK(std::abs(a[k]) < 90.0);
    }
    CHECK(seen > 100);
    CHECK(hidden > 100);
    // Angles and heights are for one observer; a value name must be known.
    const auto many = runTerracast("viewshed '" + kDem + "' --observers '" + (dir / "x.csv").string() +
                                   "' --values height -o '" + (dir / "m.tif").string() + "'");
    CHECK(many.exitCode != 0);
    CHECK(many.err.find("--values: angle and height are for one --observer") != std::string::npos);
    const auto bad = runTerracast(base + "--values depth -o '" + (dir / "b.tif").string() + "'");
    CHECK(bad.exitCode != 0);
    CHECK(bad.err.find("--values: expected visible, angle or height, found 'depth'") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("CLI: the map view GeoTIFF is written a tile at a time, from a DEM held whole or as tiles, with the "
          "picture's pixels",
          "[cli][maps][tiles]") {
    TempDir dir("map-view-tiles");
    const std::string args = "render '" + kDem + "' --view map --sky-samples 4";
    const auto whole = runTerracast(args + " -o '" + dir.file("whole.tif") + "'");
    INFO(whole.err);
    REQUIRE(whole.exitCode == 0);
    CHECK(whole.err.find("output tile") != std::string::npos);
    // Held as tiles behind a cache of a few tiles: the same bytes.
    const auto tiled = runTerracast(args + " --tile-cache 500K -o '" + dir.file("tiled.tif") + "'");
    INFO(tiled.err);
    REQUIRE(tiled.exitCode == 0);
    CHECK(tiled.err.find("tiles: ") != std::string::npos);
    CHECK(slurp(dir.file("whole.tif")) == slurp(dir.file("tiled.tif")));
    // --resume keeps what an interrupted run finished (here: nothing left to do) and writes the same bytes.
    const auto resumed = runTerracast(args + " --resume -o '" + dir.file("tiled.tif") + "'");
    INFO(resumed.err);
    REQUIRE(resumed.exitCode == 0);
    CHECK(slurp(dir.file("whole.tif")) == slurp(dir.file("tiled.tif")));
    CHECK(runTerracast(args + " --resume -o '" + dir.file("resumed.png") + "'").exitCode == 2);
    // A cloud-optimized layout, and the same colours as the PNG picture of the same view (rendered whole, rows
    // north first in both files).
    GDALAllRegister();
    std::unique_ptr<GDALDataset> tif(GDALDataset::Open(dir.file("whole.tif").c_str(), GDAL_OF_RASTER));
    REQUIRE(tif);
    const char* layout = tif->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
    CHECK(std::string(layout ? layout : "") == "COG");
    const auto png = runTerracast(args + " -o '" + dir.file("view.png") + "'");
    REQUIRE(png.exitCode == 0);
    std::unique_ptr<GDALDataset> pic(GDALDataset::Open(dir.file("view.png").c_str(), GDAL_OF_RASTER));
    REQUIRE(pic);
    const int w = tif->GetRasterXSize(), h = tif->GetRasterYSize();
    REQUIRE(pic->GetRasterXSize() == w);
    REQUIRE(pic->GetRasterYSize() == h);
    int64_t differ = 0, lit = 0;
    for (int b = 1; b <= 3; ++b) {
        std::vector<uint8_t> a(size_t(w) * size_t(h)), c(a.size());
        REQUIRE(tif->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, w, h, a.data(), w, h, GDT_Byte, 0, 0) == CE_None);
        REQUIRE(pic->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, w, h, c.data(), w, h, GDT_Byte, 0, 0) == CE_None);
        for (size_t k = 0; k < a.size(); ++k) {
            differ += a[k] != c[k];
            lit += a[k] > 40;
        }
    }
    CHECK(lit > int64_t(w) * h);
    CHECK(differ == 0);
}
