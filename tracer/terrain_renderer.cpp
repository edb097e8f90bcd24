#include "tracer/terrain_renderer.h"

#include "tracer/core/angles.h"

#include "tracer/core/parallel.h"
#include "tracer/sampling/rng.h"
#include "tracer/sky/sky.h"
#include "tracer/sampling/warps.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

namespace terracast {

namespace {

glm::vec3 mix(const glm::vec3& a, const glm::vec3& b, float w) { return a + (b - a) * w; }
}  // namespace

glm::dvec3 Sun::direction() const {
    return directionFromDegrees(azimuthDeg, elevationDeg);
}

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

namespace {
const glm::vec3 kSunColour{1.0f, 0.96f, 0.90f};
const glm::vec3 kSkyAmbient{0.80f, 0.88f, 1.0f};

// The surface normal on the side the ray arrived from.
glm::dvec3 facingNormal(const HeightFieldHit& hit, const glm::dvec3& rayDir) {
    return glm::dot(hit.normal, rayDir) > 0.0 ? -hit.normal : hit.normal;
}
}  // namespace

std::optional<Ray> sunShadowRay(const HeightFieldHit& hit, const glm::dvec3& rayDir, const TerrainRenderSettings& s) {
    const glm::dvec3 toSun = s.sun.direction();
    if (toSun.z <= 0.0 || glm::dot(facingNormal(hit, rayDir), toSun) <= 0.0) return std::nullopt;
    return Ray{spawnOrigin(hit, toSun), toSun};
}

glm::vec3 shadeTerrainHit(const HeightGrid& grid, const HeightFieldHit& hit, const glm::dvec3& rayDir, bool sunVisible,
                          const TerrainRenderSettings& s) {
    const glm::dvec3 n = facingNormal(hit, rayDir);
    const glm::vec3 albedo = elevationAlbedo(hit.pointM.z, grid.minHeightM(), grid.maxHeightM());
    const float direct = sunVisible ? float(std::max(0.0, glm::dot(n, s.sun.direction()))) * s.sun.intensity : 0.0f;
    const float skyLight = s.ambient * float(0.5 + 0.5 * n.z);
    return albedo * (direct * kSunColour + skyLight * kSkyAmbient);
}

namespace {

// One hit's colour under the render's sky: direct sun (through the air with the physical sky), sky light from
// the open part of the hemisphere (tested with sky-visibility rays when the sky asks for them), and aerial
// perspective along the camera ray.
class TerrainShader {
public:
    TerrainShader(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s)
        : grid_(grid), surface_(surface), s_(s), toSun_(s.sun.direction()),
          sunIrradiance_((s.sky.kind == SkyKind::Physical ? glm::vec3(1.0f) : kSunColour) * s.sun.intensity),
          sky_(s.sky, SkySun{toSun_, sunIrradiance_}, s.camera.eyeM.z) {}

    glm::vec3 miss(const glm::dvec3& dir) const { return sky_.radiance(dir); }

    glm::vec3 hit(const HeightFieldHit& hit, const Ray& ray, int px, int py, int64_t& shadowRays,
                  int64_t& skyRays) const {
        const glm::dvec3 n = glm::dot(hit.normal, ray.dir) > 0.0 ? -hit.normal : hit.normal;
        const glm::vec3 albedo = elevationAlbedo(hit.pointM.z, grid_.minHeightM(), grid_.maxHeightM());
        glm::vec3 light{0.0f};
        if (const auto shadowRay = sunShadowRay(hit, ray.dir, s_)) {
            ++shadowRays;
            if (!surface_.occluded(*shadowRay, {0.0, kInfinity}))
                light += sky_.sunlight(sunIrradiance_, toSun_, hit.pointM.z) * float(glm::dot(n, toSun_));
        }
        light += skyLight(hit, n, px, py, skyRays);
        return sky_.throughAir(albedo * light, ray.dir, hit.t);
    }

private:
    // The sky's light on a surface so oriented, times the open fraction of the hemisphere when the sky asks for
    // visibility rays (see the scene renderer's sky light).
    glm::vec3 skyLight(const HeightFieldHit& hit, const glm::dvec3& n, int px, int py, int64_t& skyRays) const {
        if (sky_.ambientScale() <= 0.0f) return glm::vec3(0.0f);
        const glm::vec3 open = sky_.ambient(n.z);
        const int count = s_.sky.samples;
        if (count <= 0) return open;
        skyRays += count;
        return open * openSkyFraction(n, count, RandomStream(s_.seed, px, py).uniform2(0), [&](const glm::dvec3& dir) {
                   return surface_.occluded(Ray{spawnOrigin(hit, dir), dir}, {0.0, kInfinity});
               });
    }

    const HeightGrid& grid_;
    const TerrainSurface& surface_;
    const TerrainRenderSettings& s_;
    glm::dvec3 toSun_;
    glm::vec3 sunIrradiance_;
    Sky sky_;
};

}  // namespace

Film renderTerrain(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& s,
                   RenderStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    Film film(s.width, s.height);
    const TerrainShader shader(grid, surface, s);

    std::atomic<int64_t> primary{0}, shadow{0}, sky{0}, hits{0}, pixelsDone{0};
    std::mutex progressMutex;
    const int64_t totalPixels = int64_t(s.width) * s.height;

    parallelForTiles(s.width, s.height, s.tileSize, s.threads, [&](int x0, int y0, int x1, int y1) {
        int64_t nPrimary = 0, nShadow = 0, nSky = 0, nHits = 0;
        traceCameraRays(surface, s.camera, s.width, s.height, x0, y0, x1, y1,
                        [&](int x, int y, const Ray& ray, const std::optional<HeightFieldHit>& hit) {
                            ++nPrimary;
                            if (!hit) {
                                film.set(x, y, shader.miss(ray.dir));
                                return;
                            }
                            ++nHits;
                            film.set(x, y, shader.hit(*hit, ray, x, y, nShadow, nSky));
                        });
        primary += nPrimary;
        shadow += nShadow;
        sky += nSky;
        hits += nHits;
        const int64_t done = pixelsDone += int64_t(x1 - x0) * (y1 - y0);
        if (s.progress) {
            std::lock_guard lock(progressMutex);
            s.progress(double(done) / double(totalPixels), primary.load() + shadow.load() + sky.load());
        }
    });

    if (stats) {
        stats->primaryRays = primary;
        stats->shadowRays = shadow;
        stats->skyVisibilityRays = sky;
        stats->hits = hits;
        stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return film;
}

}  // namespace terracast
