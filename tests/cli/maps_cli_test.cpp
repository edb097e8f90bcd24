// The map commands end to end: GeoTIFFs that carry the DEM's CRS and geotransform, read back with GDAL.
#include "support/run_command.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <filesystem>
#include <memory>

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
    // The map view: one pixel per cell, pixel edges on the samples' centres, same CRS.
    REQUIRE(runTerracast("render '" + kDem + "' --view map -o '" + (dir / "map.tif").string() + "'").exitCode == 0);
    const Georef map = readGeoref((dir / "map.tif").string());
    CHECK(map.width == src.width - 1);
    CHECK(map.height == src.height - 1);
    CHECK(map.bands == 3);
    CHECK(map.gt[0] == Approx(src.gt[0] + 0.5 * src.gt[1]));
    CHECK(map.gt[3] == Approx(src.gt[3] + 0.5 * src.gt[5]));
    CHECK(map.gt[1] == Approx(src.gt[1]));
    CHECK(sameCrs(map.wkt, src.wkt));
    // An observer outside the DEM is refused with exit 2 and nothing written.
    const auto bad = runTerracast("viewshed '" + kDem + "' --observer 0,0 -o '" + (dir / "none.tif").string() + "'");
    CHECK(bad.exitCode == 2);
    CHECK(lineCount(bad.err) <= 2);  // a units warning may precede the one error line
    CHECK(bad.err.find("--observer") != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "none.tif"));
    fs::remove_all(dir);
}
