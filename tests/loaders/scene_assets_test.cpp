// Draped rasters: an RGB orthophoto, in the DEM's CRS or in another one, lands on the right part of the grid.
// Rasters are written with GDAL and warped by the loader through GDAL's warper; expected positions come from
// OGR's transformation of the split line into the DEM's CRS.
#include "support/temp_dir.h"
#include "loaders/dem_loader.h"
#include "loaders/errors.h"
#include "loaders/scene_assets.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <string>

using namespace terracast;
using terracast::testing::TempDir;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR "/data-samples/") + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

// Writes a 3-band Byte GeoTIFF: red where x < splitX (in its CRS), blue elsewhere.
void writeSplitRaster(const std::string& path, const OGRSpatialReference& srs, double x0, double y0, double dx, double dy,
                      int width, int height, double splitX) {
    GDALAllRegister();
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
    GDALDatasetUniquePtr ds(driver->Create(path.c_str(), width, height, 3, GDT_Byte, nullptr));
    REQUIRE(ds);
    double gt[6] = {x0, dx, 0.0, y0, 0.0, -dy};
    ds->SetGeoTransform(gt);
    ds->SetSpatialRef(&srs);
    std::vector<uint8_t> band(size_t(width) * size_t(height));
    for (int c = 0; c < 3; ++c) {
        for (int j = 0; j < height; ++j)
            for (int i = 0; i < width; ++i) {
                const bool west = x0 + (i + 0.5) * dx < splitX;
                band[size_t(j) * size_t(width) + size_t(i)] = uint8_t(c == 0 ? (west ? 255 : 0) : c == 2 ? (west ? 0 : 255) : 0);
            }
        REQUIRE(ds->GetRasterBand(c + 1)->RasterIO(GF_Write, 0, 0, width, height, band.data(), width, height, GDT_Byte, 0,
                                                   0) == CE_None);
    }
}

}  // namespace

TEST_CASE("A drape in the DEM's CRS lands on the grid split where it was drawn", "[loaders][drape]") {
    TempDir dir("drape");
    const LoadedDem dem = loadDem(kStHelens);
    OGRSpatialReference srs;
    srs.importFromWkt(dem.geo.crsWkt.c_str());
    const double* gt = dem.geo.geoTransform;
    const double extentX = gt[1] * double(dem.sourceWidth), extentY = -gt[5] * double(dem.sourceHeight);
    // A coarser raster (90 m pixels) over the same footprint, split at 30 % of the width.
    const double split = gt[0] + 0.3 * extentX;
    const std::string path = (dir.path() / "ortho.tif").string();
    writeSplitRaster(path, srs, gt[0], gt[3], 90.0, 90.0, int(extentX / 90.0) + 1, int(extentY / 90.0) + 1, split);
    const DrapeImage drape = loadDrape(path, dem.geo, dem.grid.width(), dem.grid.height());
    CHECK(drape.width == dem.grid.width());
    CHECK(drape.height == dem.grid.height());
    for (double v : {0.1, 0.5, 0.9}) {
        const glm::vec3 west = drape.sample(0.25, v), east = drape.sample(0.36, v);
        CHECK(west.r > 0.9f);
        CHECK(west.b < 0.1f);
        CHECK(east.b > 0.9f);
        CHECK(east.r < 0.1f);
    }
}

TEST_CASE("A drape in geographic coordinates is warped onto the UTM grid", "[loaders][drape]") {
    TempDir dir("drape-geo");
    const LoadedDem dem = loadDem(kStHelens);
    OGRSpatialReference utm, wgs;
    utm.importFromWkt(dem.geo.crsWkt.c_str());
    wgs.importFromEPSG(4326);
    wgs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    utm.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    // The DEM's centre in longitude and latitude, and a split meridian through it.
    const double* gt = dem.geo.geoTransform;
    double cx = gt[0] + 0.5 * gt[1] * double(dem.sourceWidth), cy = gt[3] + 0.5 * gt[5] * double(dem.sourceHeight);
    std::unique_ptr<OGRCoordinateTransformation> toGeo(OGRCreateCoordinateTransformation(&utm, &wgs));
    std::unique_ptr<OGRCoordinateTransformation> toUtm(OGRCreateCoordinateTransformation(&wgs, &utm));
    double lon = cx, lat = cy;
    REQUIRE(toGeo->Transform(1, &lon, &lat));
    // A 0.001-degree raster covering the DEM with margin; split at the centre meridian.
    writeSplitRaster((dir.path() / "ortho-wgs84.tif").string(), wgs, lon - 0.2, lat + 0.2, 0.001, 0.001, 400, 400, lon);
    const DrapeImage drape = loadDrape((dir.path() / "ortho-wgs84.tif").string(), dem.geo, dem.grid.width(), dem.grid.height());
    // Along the meridian the split's easting changes slightly with latitude (grid convergence): check at three
    // latitudes, each against OGR's own projection of the meridian.
    for (double dLat : {-0.04, 0.0, 0.04}) {
        double x = lon, y = lat + dLat;
        REQUIRE(toUtm->Transform(1, &x, &y));
        // Grid u of the split: vertex 0 is the centre of the first pixel.
        const double u = (x - (gt[0] + 0.5 * gt[1])) / (gt[1] * double(dem.sourceWidth - 1));
        const double v = ((y - (gt[3] + gt[5] * (double(dem.sourceHeight) - 0.5))) / (-gt[5] * double(dem.sourceHeight - 1)));
        REQUIRE(u > 0.1);
        REQUIRE(u < 0.9);
        REQUIRE(v > 0.05);
        REQUIRE(v < 0.95);
        const double margin = 3.0 * 100.0 / (gt[1] * double(dem.sourceWidth - 1));  // ~ three 0.001-degree pixels
        CHECK(drape.sample(u - margin, v).r > 0.9f);
        CHECK(drape.sample(u + margin, v).b > 0.9f);
    }
}

TEST_CASE("A missing drape file is refused with its name", "[loaders][drape]") {
    const LoadedDem dem = loadDem(kStHelens);
    CHECK_THROWS_WITH(loadDrape("/nonexistent/ortho.tif", dem.geo, dem.grid.width(), dem.grid.height()),
                      "/nonexistent/ortho.tif: no such file");
}
