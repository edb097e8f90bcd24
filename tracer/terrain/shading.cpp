#include "tracer/terrain/shading.h"

#include "heightfield/shading_normals.h"

#include "tracer/core/angles.h"
#include "tracer/core/ticks.h"
#include "tracer/sampling/rng.h"
#include "tracer/sampling/warps.h"
#include "tracer/terrain/solid_base.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace terracast {

namespace {

glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, float w) { return a + (b - a) * w; }

const glm::vec3 kSunColour{1.0f, 0.96f, 0.90f};
const glm::vec3 kSkyAmbient{0.80f, 0.88f, 1.0f};

// The surface normal on the side the ray arrived from.
glm::dvec3 facingNormal(const HeightFieldHit& hit, const glm::dvec3& rayDir) {
    return glm::dot(hit.normal, rayDir) > 0.0 ? -hit.normal : hit.normal;
}

}  // namespace

glm::dvec3 Sun::direction() const { return directionFromDegrees(azimuthDeg, elevationDeg); }

glm::vec3 elevationAlbedo(double heightM, double minHeightM, double maxHeightM) {
    struct Stop {
        float at;
        glm::vec3 colour;
    };
    static constexpr Stop ramp[] = {
        {0.00f, {0.20f, 0.36f, 0.16f}},  // lowland green
        {0.35f, {0.42f, 0.45f, 0.22f}},  // upland olive
        {0.65f, {0.45f, 0.35f, 0.25f}},  // brown
        {0.85f, {0.50f, 0.48f, 0.46f}},  // rock
        {1.00f, {0.90f, 0.90f, 0.92f}},  // snow
    };
    const double span = maxHeightM - minHeightM;
    const float w = span > 0.0 ? float(std::clamp((heightM - minHeightM) / span, 0.0, 1.0)) : 0.3f;
    for (size_t k = 1; k < std::size(ramp); ++k)
        if (w <= ramp[k].at)
            return mix(ramp[k - 1].colour, ramp[k].colour, (w - ramp[k - 1].at) / (ramp[k].at - ramp[k - 1].at));
    return ramp[std::size(ramp) - 1].colour;
}

glm::vec3 slopeAlbedo(double normalZ) {
    // Grass on gentle slopes, scree on steeper ones, bare rock on cliffs.
    const glm::vec3 grass{0.22f, 0.36f, 0.15f}, scree{0.45f, 0.40f, 0.33f}, rock{0.38f, 0.37f, 0.36f};
    const double slopeDeg = degrees(std::acos(std::clamp(normalZ, -1.0, 1.0)));
    if (slopeDeg < 20.0) return glm::mix(grass, scree, float(slopeDeg / 20.0) * 0.3f);
    if (slopeDeg < 40.0) return glm::mix(glm::mix(grass, scree, 0.3f), scree, float((slopeDeg - 20.0) / 20.0));
    return glm::mix(scree, rock, float(std::min(1.0, (slopeDeg - 40.0) / 20.0)));
}

std::optional<Ray> sunShadowRay(const HeightFieldHit& hit, const glm::dvec3& rayDir, const Sun& sun) {
    const glm::dvec3 toSun = sun.direction();
    if (toSun.z <= 0.0 || glm::dot(facingNormal(hit, rayDir), toSun) <= 0.0) return std::nullopt;
    return Ray{spawnOrigin(hit, toSun), toSun};
}

glm::vec3 shadeTerrainHit(const HeightGrid& grid, const HeightFieldHit& hit, const glm::dvec3& rayDir, bool sunVisible,
                          const Sun& sun, float ambient) {
    const glm::dvec3 n = facingNormal(hit, rayDir);
    const glm::vec3 albedo = elevationAlbedo(hit.pointM.z, grid.minHeightM(), grid.maxHeightM());
    const float direct = sunVisible ? float(std::max(0.0, glm::dot(n, sun.direction()))) * sun.intensity : 0.0f;
    const float skyLight = ambient * float(0.5 + 0.5 * n.z);
    return albedo * (direct * kSunColour + skyLight * kSkyAmbient);
}

std::optional<Backdrop> parseBackdrop(std::string_view name) {
    if (name == "neutral") return Backdrop::Neutral;
    if (name == "sky") return Backdrop::Sky;
    if (name == "ground") return Backdrop::Ground;
    return std::nullopt;
}

TerrainShader::TerrainShader(const HeightGrid& grid, const TerrainSurface& surface, const Sun& sun,
                             const SkyDescription& sky, double viewerAltitudeM, uint64_t seed, bool smoothNormals,
                             TerrainLook look)
    : grid_(grid), surface_(surface), sun_(sun), skySamples_(sky.samples), seed_(seed), smoothNormals_(smoothNormals),
      toSun_(sun.direction()),
      sunIrradiance_((sky.kind == SkyKind::Physical ? glm::vec3(1.0f) : kSunColour) * sun.intensity),
      sky_(sky, SkySun{toSun_, sunIrradiance_}, viewerAltitudeM), look_(std::move(look)),
      floorM_(solidBaseFloorM(grid)) {}

glm::vec3 TerrainShader::miss(const glm::dvec3& dir) const {
    switch (look_.backdrop) {
    case Backdrop::Ground: return sky_.radiance(dir);
    case Backdrop::Sky: {
        if (dir.z >= 0.0) return sky_.radiance(dir);
        glm::dvec3 level{dir.x, dir.y, 0.0};
        if (glm::dot(level, level) < 1e-24) level = {0.0, 1.0, 0.0};  // straight down: any azimuth
        return sky_.radiance(glm::normalize(level));
    }
    case Backdrop::Neutral: {
        // Linear grey 0.60 at and above the horizon, falling to 0.30 straight down.
        const float below = float(std::clamp(-dir.z, 0.0, 1.0));
        return glm::vec3(0.60f - 0.30f * below);
    }
    }
    return glm::vec3(0.0f);
}

namespace {

thread_local uint64_t secondaryRayTicks[2] = {0, 0};  // shadow rays, sky-visibility rays

}  // namespace

TerrainShader::RayTicks TerrainShader::takeSecondaryRayTicks() {
    const RayTicks ticks{secondaryRayTicks[0], secondaryRayTicks[1]};
    secondaryRayTicks[0] = secondaryRayTicks[1] = 0;
    return ticks;
}

bool TerrainShader::occluded(const Ray& ray, bool sky) const {
    if (!timeRays_) return surface_.occluded(ray, {0.0, kInfinity});
    const uint64_t start = readTicks();
    const bool blocked = surface_.occluded(ray, {0.0, kInfinity});
    secondaryRayTicks[sky] += ticksSince(start, tickReadCost_);
    return blocked;
}

void TerrainShader::timeSecondaryRays(bool on) {
    timeRays_ = on;
    tickReadCost_ = on ? tickReadCost() : 0;
}

std::optional<glm::vec3> TerrainShader::base(const Ray& ray, double tMax, int64_t& shadowRays) const {
    if (!look_.solidBase) return std::nullopt;
    const auto wall = intersectSolidBase(grid_, floorM_, ray, tMax);
    if (!wall) return std::nullopt;
    // Lambert under the sun (unless the terrain shadows the wall) and the sky light a wall receives.
    glm::vec3 light = sky_.ambient(wall->normal);
    const double cosSun = glm::dot(wall->normal, toSun_);
    if (cosSun > 0.0 && toSun_.z > -1.0) {
        ++shadowRays;
        const Ray toward{wall->point + wall->normal * (1e-6 * (1.0 + glm::length(wall->point))), toSun_};
        if (!occluded(toward, false)) light += sky_.sunlight(sunIrradiance_, toSun_, wall->point.z) * float(cosSun);
    }
    return sky_.throughAir(kSolidBaseAlbedo * light, ray.dir, wall->t);
}

glm::vec3 TerrainShader::albedo(const HeightFieldHit& hit) const {
    switch (look_.colouring) {
    case TerrainLook::Colouring::Ramp: break;
    case TerrainLook::Colouring::Plain: return look_.plain;
    case TerrainLook::Colouring::Drape:
        if (look_.drape)
            return look_.drape->sample((double(hit.cellX) + hit.u) / double(grid_.cellsX()),
                                       (double(hit.cellY) + hit.v) / double(grid_.cellsY()));
        break;
    }
    return elevationAlbedo(hit.pointM.z, grid_.minHeightM(), grid_.maxHeightM());
}

glm::vec3 TerrainShader::hit(const HeightFieldHit& hit, const Ray& ray, int px, int py, int64_t& shadowRays,
                             int64_t& skyRays, int sample) const {
    // The shading normal, on the side the ray came from; whether the sun can reach the point is the geometric
    // surface's to say (sunShadowRay), so smooth shading changes no shadow.
    glm::dvec3 n = facingNormal(hit, ray.dir);
    if (smoothNormals_) {
        const glm::dvec3 smooth = surface_.smoothNormalAt(hit);
        n = glm::dot(hit.normal, ray.dir) > 0.0 ? -smooth : smooth;
    }
    const glm::vec3 albedo = this->albedo(hit);
    glm::vec3 light{0.0f};
    if (const auto shadowRay = sunShadowRay(hit, ray.dir, sun_)) {
        ++shadowRays;
        if (!occluded(*shadowRay, false))
            light += sky_.sunlight(sunIrradiance_, toSun_, hit.pointM.z) * float(std::max(0.0, glm::dot(n, toSun_)));
    }
    light += skyLight(hit, n, px, py, sample, skyRays);
    return sky_.throughAir(albedo * light, ray.dir, hit.t);
}

// The sky's light on a surface so oriented, times the open fraction of the hemisphere when the sky asks for
// visibility rays (see the scene renderer's sky light).
glm::vec3 TerrainShader::skyLight(const HeightFieldHit& hit, const glm::dvec3& n, int px, int py, int sample,
                                  int64_t& skyRays) const {
    if (sky_.ambientScale() <= 0.0f) return glm::vec3(0.0f);
    const glm::vec3 open = sky_.ambient(n);
    const int count = skySamples_;
    if (count <= 0) return open;
    skyRays += count;
    return open * openSkyFraction(n, count, RandomStream(seed_, px, py, uint64_t(sample)).uniform2(0), [&](const glm::dvec3& dir) {
               return occluded(Ray{spawnOrigin(hit, dir), dir}, true);
           });
}

}  // namespace terracast
