// The terrain renderer: a pinhole view of one height grid, lit by a directional sun with ray-traced cast
// shadows and by the sky (open-sky fraction from sky-visibility rays), under a physical, gradient, flat or no
// sky, with aerial perspective in front of distant terrain.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"
#include "tracer/camera/camera.h"
#include "tracer/sampling/film.h"
#include "tracer/sampling/pixel_estimate.h"
#include "tracer/terrain/camera.h"
#include "tracer/sky/sky_description.h"
#include "tracer/terrain/surface.h"
#include "tracer/terrain/shading.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

namespace terracast {

// Everything a terrain render needs besides the grid.
struct TerrainRenderSettings {
    int width = 1280;                          // pixels
    int height = 720;                          // pixels
    PinholeCamera camera;                      // local metres
    // When set, the camera rays come from this camera (orthographic, panorama, fisheye) rather than from
    // `camera`, which then only places the viewer in the atmosphere.
    std::optional<ViewCamera> view;
    PixelSampling sampling;                    // samples per pixel, pattern, filter, adaptive rule
    Sun sun;
    SkyDescription sky;                        // model (physical by default), haze, aerial perspective, ambient,
                                               // sky-visibility rays per hit
    uint64_t seed = 0;                         // for the sky-visibility directions
    bool smoothNormals = true;                 // shade with smooth normals (geometry and shadows unchanged)
    TerrainLook look;                          // terrain colour, solid base, backdrop
    float ambient = 0.18f;                     // shadeTerrainHit's constant ambient, fraction of the sun's
    int threads = 0;                           // worker threads; 0 = all cores
    int tileSize = 32;                         // pixels per side of a work tile
    bool timePhases = false;                   // fill RenderStats' thread-seconds (a clock read per ray)
    // Called now and then with the fraction of pixels done and the rays traced so far (any thread, serialised).
    std::function<void(double fraction, int64_t rays)> progress;
};

// Counts and timings of one render.
struct RenderStats {
    int64_t primaryRays = 0;
    int64_t shadowRays = 0;
    int64_t skyVisibilityRays = 0;
    int64_t hits = 0;
    double seconds = 0.0;
    // With TerrainRenderSettings::timePhases, thread-seconds summed over the threads: camera rays (their walks
    // and the work tiles around them), shadow rays, sky-visibility rays, and shading (normals, colours, the sun's
    // and the sky's light, the air between, the backdrop): the four make up the work tiles' thread time.
    double setupSeconds = 0.0;  // of `seconds`: the shader's set-up (the sky's tables) before any ray
    double cameraRaySeconds = 0.0;
    double shadowRaySeconds = 0.0;
    double skyRaySeconds = 0.0;
    double shadingSeconds = 0.0;
};

// Traces the camera rays of the pixels [x0, x1) x [y0, y1) of a width x height film through `surface`, in
// bundles of up to 8 x 8 pixels (see TerrainSurface::intersectBundle), and calls pixel(x, y, ray, hit) for
// each pixel, a bundle at a time.
template <class Pixel>
void traceCameraRays(const TerrainSurface& surface, const PinholeCamera& camera, int width, int height, int x0,
                     int y0, int x1, int y1, Pixel&& pixel) {
    constexpr int kBundle = 8;
    const double aspect = double(width) / double(height);
    const PinholeCamera::Frame frame = camera.frame();
    std::array<Ray, kBundle * kBundle> rays;
    std::array<std::optional<HeightFieldHit>, kBundle * kBundle> hits;
    for (int by = y0; by < y1; by += kBundle)
        for (int bx = x0; bx < x1; bx += kBundle) {
            const int ex = std::min(bx + kBundle, x1), ey = std::min(by + kBundle, y1);
            size_t n = 0;
            for (int y = by; y < ey; ++y)
                for (int x = bx; x < ex; ++x)
                    rays[n++] = frame.generate((x + 0.5) / width, (y + 0.5) / height, aspect);
            surface.intersectBundle(std::span<const Ray>(rays.data(), n), {0.0, kInfinity},
                                    std::span<std::optional<HeightFieldHit>>(hits.data(), n));
            n = 0;
            for (int y = by; y < ey; ++y)
                for (int x = bx; x < ex; ++x, ++n) pixel(x, y, rays[n], hits[n]);
        }
}

// The order in which the ranks of a launch draw a picture's blocks (blocksX x blocksY of them) when the picture is
// shared over `spans` ranks: span r is the blocks of columns [blocksX r / spans, blocksX (r + 1) / spans), row by
// row, ending (exclusive) at spanEnds[r] in `blocks` (ranks::SpanTasks). One span is picture order.
struct BlockOrder {
    std::vector<std::pair<int, int>> blocks;  // (column, row) of each task
    std::vector<int64_t> spanEnds;
};
BlockOrder blocksBySpans(int blocksX, int blocksY, int spans);

// Renders `grid`, traced through `surface`, into a linear RGB film.
Film renderTerrain(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& settings,
                   RenderStats* stats = nullptr);

}  // namespace terracast
