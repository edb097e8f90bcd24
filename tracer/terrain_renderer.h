// The terrain renderer: a pinhole view of one height grid, lit by a directional sun with ray-traced cast
// shadows, a constant ambient term and a gradient sky for rays that miss.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"
#include "tracer/camera.h"
#include "tracer/film.h"

#include <cstdint>
#include <functional>

namespace terracast {

// The sun as a directional light.
struct Sun {
    double azimuthDeg = 315.0;   // compass direction towards the sun, clockwise from north
    double elevationDeg = 35.0;  // angle above the horizon
    float intensity = 1.0f;      // irradiance scale on a surface facing the sun

    // Unit vector from the ground towards the sun (x east, y north, z up).
    glm::dvec3 direction() const;
};

// Everything a terrain render needs besides the grid.
struct TerrainRenderSettings {
    int width = 1280;                          // pixels
    int height = 720;                          // pixels
    PinholeCamera camera;                      // local metres
    Sun sun;
    CellMethod method = CellMethod::Bilinear;  // cell intersector
    float ambient = 0.18f;                     // constant ambient light, fraction of the sun's
    int threads = 0;                           // worker threads; 0 = all cores
    int tileSize = 32;                         // pixels per side of a work tile
    // Called now and then with the fraction of pixels done and the rays traced so far (any thread, serialised).
    std::function<void(double fraction, int64_t rays)> progress;
};

// Counts and timings of one render.
struct RenderStats {
    int64_t primaryRays = 0;
    int64_t shadowRays = 0;
    int64_t hits = 0;
    double seconds = 0.0;
};

// Renders `grid` into a linear RGB film.
Film renderTerrain(const HeightGrid& grid, const TerrainRenderSettings& settings, RenderStats* stats = nullptr);

// The sky seen along a unit direction: a gradient from a pale horizon to a deeper zenith.
glm::vec3 gradientSky(const glm::dvec3& dir);

// Terrain albedo from a height ramp: lowland green, upland brown, rock grey, snow white.
glm::vec3 elevationAlbedo(double heightM, double minHeightM, double maxHeightM);

}  // namespace terracast
