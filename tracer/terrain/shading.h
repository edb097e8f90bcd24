// How terrain looks, for both renderers: the sun as a directional light, the albedo ramps (by elevation and by
// slope), the shadow ray a hit sends towards the sun, a plain shading for comparisons, and the full shading of
// a terrain hit under a sky (direct sun, sky light through the open hemisphere, aerial perspective).
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"
#include "tracer/scene/scene_assets.h"
#include "tracer/sky/sky.h"
#include "tracer/sky/sky_description.h"
#include "tracer/terrain/surface.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>

namespace terracast {

// The sun as a directional light.
struct Sun {
    double azimuthDeg = 315.0;   // compass direction towards the sun, clockwise from north
    double elevationDeg = 35.0;  // angle above the horizon
    float intensity = 1.0f;      // irradiance scale on a surface facing the sun

    // Unit vector from the ground towards the sun (x east, y north, z up).
    glm::dvec3 direction() const;
};

// Terrain albedo from a height ramp: lowland green, upland brown, rock grey, snow white.
glm::vec3 elevationAlbedo(double heightM, double minHeightM, double maxHeightM);
// Terrain albedo from the slope (the normal's z component): grass, scree, bare rock.
glm::vec3 slopeAlbedo(double normalZ);

// The shadow ray a hit needs towards the sun, or none when the surface faces away from it (or the sun is down).
std::optional<Ray> sunShadowRay(const HeightFieldHit& hit, const glm::dvec3& rayDir, const Sun& sun);

// A plain look for comparisons (no sky model): height-ramp albedo times the sun (when `sunVisible`) plus a
// constant `ambient` term, a fraction of the sun's light.
glm::vec3 shadeTerrainHit(const HeightGrid& grid, const HeightFieldHit& hit, const glm::dvec3& rayDir, bool sunVisible,
                          const Sun& sun, float ambient);

// What camera rays that meet nothing show.
enum class Backdrop {
    Neutral,  // a plain grey backdrop, lighter towards the horizon (the default for pictures)
    Sky,      // the sky model above the horizon and the sky's colour at the horizon below it
    Ground,   // the sky model in every direction: below the horizon, the Earth's ground seen through the air
};
std::optional<Backdrop> parseBackdrop(std::string_view name);

// How the terrain looks besides its light: its colour, whether it stands on a solid base (solid_base.h), and
// the backdrop.
struct TerrainLook {
    enum class Colouring { Ramp, Plain, Drape };
    Colouring colouring = Colouring::Ramp;    // the elevation ramp (elevationAlbedo), one colour, or a drape
    glm::vec3 plain{0.6f};                    // Plain: the albedo (linear RGB)
    std::shared_ptr<const DrapeImage> drape;  // Drape: an image over the grid's footprint
    bool solidBase = false;                   // walls from the grid's edges down to solidBaseFloorM
    Backdrop backdrop = Backdrop::Ground;
};

// The albedo of the base's walls: a neutral earth colour.
inline constexpr glm::vec3 kSolidBaseAlbedo{0.36f, 0.33f, 0.30f};

// One hit's colour under a sky: direct sun (through the air with the physical sky), sky light from the open
// part of the hemisphere (tested with sky-visibility rays when the sky asks for them), and aerial perspective
// along the camera ray.
class TerrainShader {
public:
    // `viewerAltitudeM` places the camera in the atmosphere; `seed` spreads the sky-visibility directions;
    // `smoothNormals` shades with the smooth normal (smoothNormal) rather than each cell's own.
    TerrainShader(const HeightGrid& grid, const TerrainSurface& surface, const Sun& sun, const SkyDescription& sky,
                  double viewerAltitudeM, uint64_t seed, bool smoothNormals = true, TerrainLook look = {});

    // What a camera ray that meets nothing sees: the backdrop.
    glm::vec3 miss(const glm::dvec3& dir) const;
    // The radiance of a camera ray that meets the solid base's wall (or none without a base, or when the ray
    // meets no wall nearer than tMax); counts the shadow ray it traces.
    std::optional<glm::vec3> base(const Ray& ray, double tMax, int64_t& shadowRays) const;
    // The radiance camera sample `sample` of pixel (px, py) brings back from `hit`; counts the rays it traces.
    // The pixel and sample pick the sky-visibility directions.
    glm::vec3 hit(const HeightFieldHit& hit, const Ray& ray, int px, int py, int64_t& shadowRays, int64_t& skyRays,
                  int sample = 0) const;

    // With `on`, the shadow and sky-visibility rays' time is added up per thread (render --verbose), in ticks of
    // tracer/core/ticks.h, each interval less the cost of its reads; off by default, when it costs nothing.
    void timeSecondaryRays(bool on);
    // The ticks this thread spent tracing shadow rays and sky-visibility rays since its last call (0 unless
    // timed).
    struct RayTicks {
        uint64_t shadow = 0;
        uint64_t sky = 0;
    };
    static RayTicks takeSecondaryRayTicks();

private:
    // `sky`: a sky-visibility ray, else a shadow ray (towards the sun).
    bool occluded(const Ray& ray, bool sky) const;

    glm::vec3 albedo(const HeightFieldHit& hit) const;
    glm::vec3 skyLight(const HeightFieldHit& hit, const glm::dvec3& n, int px, int py, int sample,
                       int64_t& skyRays) const;

    const HeightGrid& grid_;
    const TerrainSurface& surface_;
    Sun sun_;
    int skySamples_;
    uint64_t seed_;
    bool smoothNormals_;
    bool timeRays_ = false;
    uint64_t tickReadCost_ = 0;  // tickReadCost() while rays are timed
    glm::dvec3 toSun_;
    glm::vec3 sunIrradiance_;
    Sky sky_;
    TerrainLook look_;
    double floorM_ = 0.0;
};

}  // namespace terracast
