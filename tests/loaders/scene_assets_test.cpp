// Draped rasters: an RGB orthophoto, in the DEM's CRS or in another one, lands on the right part of the grid,
// and colours the terrain of a rendered scene.
// Rasters are written with GDAL and warped by the loader through GDAL's warper; expected positions come from
// OGR's transformation of the split line into the DEM's CRS.
#include "support/drape_rasters.h"
#include "support/temp_dir.h"
#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"
#include "loaders/scene_assets.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <string>
#include <vector>

using namespace terracast;
using terracast::testing::TempDir;
using terracast::testing::writeSplitRaster;

namespace {

const std::string kStHelens =
    std::string(TERRACAST_SOURCE_DIR "/data-samples/") + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

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

namespace {

// The sRGB decoding of an 8-bit level (IEC 61966-2-1), the reference for what a byte raster means.
double linearOfLevel(int level) {
    const double c = level / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

}  // namespace

TEST_CASE("A drape written at test time colours the rendered terrain where it was drawn", "[loaders][drape][scene]") {
    // A flat 400 x 400 m DEM (10 m pixels, UTM zone 10) and, over the same footprint, an 8 x 8 RGB raster in
    // four quadrants: red in the north-west, green in the north-east, blue in the south-west and mid grey in
    // the south-east. Seen from straight above with the sun overhead and no sky, each terrain point shows its
    // drape colour times the sun's irradiance: the quadrant colours themselves.
    TempDir dir("drape-scene");
    OGRSpatialReference utm;
    utm.importFromEPSG(32610);
    const double x0 = 560000.0, y0 = 5120000.0;
    GDALAllRegister();
    GDALDriver* tiff = GetGDALDriverManager()->GetDriverByName("GTiff");
    const std::string demPath = dir.file("flat.tif"), drapePath = dir.file("quadrants.tif");
    {
        GDALDatasetUniquePtr dem(tiff->Create(demPath.c_str(), 40, 40, 1, GDT_Float32, nullptr));
        REQUIRE(dem);
        double gt[6] = {x0, 10.0, 0.0, y0, 0.0, -10.0};
        dem->SetGeoTransform(gt);
        dem->SetSpatialRef(&utm);
        std::vector<float> heights(40 * 40, 250.0f);
        REQUIRE(dem->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 40, 40, heights.data(), 40, 40, GDT_Float32, 0, 0) ==
                CE_None);
    }
    // Quadrant colours as bytes, rows from the north.
    const int colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {128, 128, 128}};  // NW, NE, SW, SE
    {
        GDALDatasetUniquePtr drape(tiff->Create(drapePath.c_str(), 8, 8, 3, GDT_Byte, nullptr));
        REQUIRE(drape);
        double gt[6] = {x0, 50.0, 0.0, y0, 0.0, -50.0};
        drape->SetGeoTransform(gt);
        drape->SetSpatialRef(&utm);
        for (int c = 0; c < 3; ++c) {
            std::vector<uint8_t> band(64);
            for (int j = 0; j < 8; ++j)
                for (int i = 0; i < 8; ++i) band[size_t(j * 8 + i)] = uint8_t(colours[(j >= 4) * 2 + (i >= 4)][c]);
            REQUIRE(drape->GetRasterBand(c + 1)->RasterIO(GF_Write, 0, 0, 8, 8, band.data(), 8, 8, GDT_Byte, 0, 0) ==
                    CE_None);
        }
    }

    SceneDescription d;
    MaterialDescription photo;
    photo.name = "photo";
    photo.terrain = TerrainColouring::Drape;
    photo.drapePath = drapePath;
    d.materials.push_back(photo);
    ObjectDescription terrain;
    terrain.kind = ObjectKind::HeightField;
    terrain.filePath = demPath;
    terrain.material = "photo";
    d.objects.push_back(terrain);
    LightDescription sun;
    sun.elevationDeg = 90.0;
    d.lights.push_back(sun);
    d.sky.kind = SkyKind::None;
    const LoadedSceneAssets loaded = loadSceneAssets(d);
    const Scene scene(d, loaded.assets);
    const HeightGrid& grid = scene.terrain()->grid();
    REQUIRE(grid.width() == 40);
    const double extent = grid.extentXM();  // vertices at pixel centres: 39 cells of 10 m
    d.camera.kind = CameraKind::Orthographic;
    d.camera.eye = glm::dvec3(0.5 * extent, 0.5 * extent, 1000.0);
    d.camera.lookAt = glm::dvec3(0.5 * extent, 0.5 * extent, 0.0);
    d.camera.up = {0, 1, 0};  // north up, east right
    d.camera.orthoHeightM = extent;
    SceneRenderSettings s;
    s.width = s.height = 40;
    s.threads = 2;
    const Film film = renderScene(scene, makeSceneCamera(scene, d.camera, 1.0), s);
    // The middle of each quadrant, away from the seams where the warp and the lookup blend neighbours.
    const int centres[4][2] = {{10, 10}, {29, 10}, {10, 29}, {29, 29}};  // NW, NE, SW, SE (x, y from the top)
    for (int q = 0; q < 4; ++q) {
        INFO("quadrant " << q);
        for (int dy = -4; dy <= 4; ++dy)
            for (int dx = -4; dx <= 4; ++dx) {
                const glm::vec3 v = film.get(centres[q][0] + dx, centres[q][1] + dy);
                for (int c = 0; c < 3; ++c) CHECK(double(v[c]) == Approx(linearOfLevel(colours[q][c])).margin(2e-3));
            }
    }
}
