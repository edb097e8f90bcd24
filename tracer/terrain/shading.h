// How terrain looks, for both renderers: the sun as a directional light, the albedo ramps (by elevation and by
// slope), the shadow ray a hit sends towards the sun, a plain shading for comparisons, and the full shading of
// a terrain hit under a sky (direct sun, sky light through the open hemisphere, aerial perspective).
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"
#include "tracer/sky/sky.h"
#include "tracer/sky/sky_description.h"
#include "tracer/terrain/surface.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>

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

// One hit's colour under a sky: direct sun (through the air with the physical sky), sky light from the open
// part of the hemisphere (tested with sky-visibility rays when the sky asks for them), and aerial perspective
// along the camera ray.
class TerrainShader {
public:
    // `viewerAltitudeM` places the camera in the atmosphere; `seed` spreads the sky-visibility directions;
    // `smoothNormals` shades with the smooth normal (smoothNormal) rather than each cell's own.
    TerrainShader(const HeightGrid& grid, const TerrainSurface& surface, const Sun& sun, const SkyDescription& sky,
                  double viewerAltitudeM, uint64_t seed, bool smoothNormals = true);

    // What a camera ray that meets no terrain sees.
    glm::vec3 miss(const glm::dvec3& dir) const { return sky_.radiance(dir); }
    // The radiance camera sample `sample` of pixel (px, py) brings back from `hit`; counts the rays it traces.
    // The pixel and sample pick the sky-visibility directions.
    glm::vec3 hit(const HeightFieldHit& hit, const Ray& ray, int px, int py, int64_t& shadowRays, int64_t& skyRays,
                  int sample = 0) const;

private:
    glm::vec3 skyLight(const HeightFieldHit& hit, const glm::dvec3& n, int px, int py, int sample,
                       int64_t& skyRays) const;

    const HeightGrid& grid_;
    const TerrainSurface& surface_;
    Sun sun_;
    int skySamples_;
    uint64_t seed_;
    bool smoothNormals_;
    glm::dvec3 toSun_;
    glm::vec3 sunIrradiance_;
    Sky sky_;
};

}  // namespace terracast
