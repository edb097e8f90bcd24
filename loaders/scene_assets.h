// Loading what a scene file names: the DEM of each height-field object and the raster draped by a material.
#pragma once

#include "loaders/dem_loader.h"
#include "tracer/scene/scene_assets.h"
#include "tracer/scene/scene_description.h"

#include <string>
#include <vector>

namespace terracast {

struct LoadedSceneAssets {
    SceneAssets assets;
    std::vector<GeoReference> geo;       // per height field, in object order
    std::vector<std::string> warnings;   // one line each
    double bytes = 0.0;                  // memory held by grids and drapes
};

// Loads each height field's DEM (with its own cell size and height scale, scaled by its exaggeration) and each
// material's drape, resampled onto the first height field's grid through its georeference (or stretched over
// the footprint when either raster has none). Errors are InputErrors prefixed with the scene file's
// `path:line:column` of the key that named the file. `maxBytes` bounds each DEM as in loadDem.
LoadedSceneAssets loadSceneAssets(const SceneDescription& scene, double maxBytes = 0.0);

// Sets the azimuth and elevation of every sun given by a `time`: where the sun stands at that instant over the
// centre of the first height field (NOAA's solar position, apparent elevation). Returns one line per such sun
// saying where it put it. Throws InputError at the light's `path:line:column` when the scene has no
// georeferenced height field to place it on the Earth.
std::vector<std::string> placeTimedSuns(SceneDescription& scene, const LoadedSceneAssets& loaded);

// Reads an RGB(A) or grey raster as linear RGB, warped onto the lattice of `dem` when both are georeferenced:
// `width` x `height` samples at the DEM's vertices, row 0 at the north edge.
DrapeImage loadDrape(const std::string& path, const GeoReference& dem, int64_t width, int64_t height);

// Reads an image texture (any raster GDAL reads: PNG, JPEG, TIFF; RGB or grey) at its own size as linear RGB:
// 8-bit values are sRGB-encoded, others linear reflectance in [0, 1].
DrapeImage loadTexture(const std::string& path);

// Reads an equirectangular environment image (EXR or Radiance HDR: linear radiance; PNG and other 8-bit
// files: sRGB) for `[sky] model = "image"`. Refuses a picture with a negative or non-finite value, naming
// the pixel.
EnvironmentImage loadEnvironment(const std::string& path);

}  // namespace terracast
