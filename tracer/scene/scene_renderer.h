// The Whitted ray tracer over a Scene: shadow rays to each light, mirror reflection, refraction weighted by
// Fresnel with total internal reflection, Beer-Lambert absorption inside media, a sky for escaping rays.
#pragma once

#include "tracer/camera/camera.h"
#include "tracer/sampling/film.h"
#include "tracer/sampling/pixel_estimate.h"
#include "tracer/scene/scene.h"
#include "tracer/sky/sky.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace terracast {

enum class RayKind { Primary, Shadow, Reflection, Refraction, SkyVisibility };
const char* rayKindName(RayKind kind);

// Pixel sampling (samples per pixel, pattern, filter, adaptive rule) comes from PixelSampling.
struct SceneRenderSettings : PixelSampling {
    int width = 960;
    int height = 540;
    int maxDepth = 6;           // reflection and refraction bounces after the primary ray
    double minWeight = 0.01;    // a secondary ray is not traced when its path weight falls below this
    uint64_t seed = 0;
    int threads = 0;            // 0 = all cores
    int tileSize = 16;
    float exposure = 1.0f;
    // Called now and then with the fraction of pixels done and the rays traced so far (serialised).
    std::function<void(double fraction, int64_t rays)> progress;
};

// Rays traced, by kind. `skyRays` counts rays of any kind except shadow and sky-visibility rays that left the
// scene; `skyVisibility` counts the hemisphere rays that test how much sky a diffuse surface sees.
struct SceneRayStats {
    int64_t primary = 0;
    int64_t shadow = 0;
    int64_t reflection = 0;
    int64_t refraction = 0;
    int64_t skyVisibility = 0;
    int64_t skyRays = 0;
    int64_t samples = 0;        // camera samples taken (pixels times samples per pixel, or fewer when adaptive)
    double seconds = 0.0;
    int64_t total() const { return primary + shadow + reflection + refraction + skyVisibility; }
};

// One ray of a pixel's ray tree (debug mode).
struct RayRecord {
    RayKind kind = RayKind::Primary;
    int depth = 0;
    glm::dvec3 origin{0.0};
    glm::dvec3 dir{0.0};
    std::string hit;              // object name, "sky", "light" (shadow ray reached the light) or "blocked"
    double t = 0.0;               // distance to the hit (infinity for the sky)
    glm::vec3 weight{1.0f};       // path weight of the ray
    glm::vec3 contribution{0.0f}; // radiance the ray returns, times its weight; for a shadow ray, the
                                  // transmittance towards the light (0 when blocked), unweighted
    // How the radiance the ray returns is made, so that a tree adds up: what leaves its hit towards it
    // (`atHit`: the sky light added without rays, plus the `share` of each of its child records), times what
    // crosses the medium on the way (`passed`: Beer-Lambert in glass or water, the air's transmittance with
    // aerial perspective), plus the light the air scatters into it (`inscattered`, the haze). For a ray that
    // meets no object, `atHit` is the sky's radiance.
    glm::vec3 share{0.0f};        // what this ray adds to its parent's atHit (for a camera ray, to the pixel)
    glm::vec3 atHit{0.0f};
    glm::vec3 skyLight{0.0f};     // part of atHit: the sky's light on a diffuse hit, when no rays measure it
    glm::vec3 passed{1.0f};
    glm::vec3 inscattered{0.0f};
};

// The camera the description asks for, framing the scene automatically where eye or look_at are unset.
ViewCamera makeSceneCamera(const Scene& scene, const CameraDescription& camera, double aspect);

// The distance along the view axis from the camera to what the centre of pixel (x, y) of a width x height
// picture sees (for focusing a thin lens on it); none when that ray reaches the sky.
std::optional<double> focusDistanceAt(const Scene& scene, const ViewCamera& camera, int x, int y, int width,
                                      int height);

// Renders the scene into a linear RGB film (radiance times exposure).
Film renderScene(const Scene& scene, const ViewCamera& camera, const SceneRenderSettings& settings,
                 SceneRayStats* stats = nullptr);

// Traces one pixel's samples and records every ray; returns the pixel's value.
glm::vec3 tracePixel(const Scene& scene, const ViewCamera& camera, const SceneRenderSettings& settings, int x, int y,
                     std::vector<RayRecord>* tree, SceneRayStats* stats = nullptr);

// The sky of a render: the scene's sky model lit by its first sun, seen from `viewerAltitudeM` (the camera's).
Sky makeSceneSky(const Scene& scene, double viewerAltitudeM);

}  // namespace terracast
