#include "tracer/scene/scene_renderer.h"

#include "tracer/core/angles.h"
#include "tracer/core/cancel.h"

#include "tracer/scene/optics.h"
#include "tracer/core/parallel.h"
#include "tracer/sampling/rng.h"
#include "tracer/terrain/terrain_renderer.h"
#include "tracer/sampling/warps.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>

namespace terracast {

namespace {

// Shadow rays through dielectrics pass at most this many interfaces before the light counts as blocked.
constexpr int kMaxShadowInterfaces = 16;

float maxComponent(const glm::vec3& v) { return std::max({v.r, v.g, v.b}); }

struct Counters {
    int64_t primary = 0, shadow = 0, reflection = 0, refraction = 0, skyVisibility = 0, sky = 0, samples = 0;
    void count(RayKind kind) {
        switch (kind) {
        case RayKind::Primary: ++primary; break;
        case RayKind::Shadow: ++shadow; break;
        case RayKind::Reflection: ++reflection; break;
        case RayKind::Refraction: ++refraction; break;
        case RayKind::SkyVisibility: ++skyVisibility; break;
        }
    }
    void addTo(SceneRayStats& s) const {
        s.primary += primary;
        s.shadow += shadow;
        s.reflection += reflection;
        s.refraction += refraction;
        s.skyVisibility += skyVisibility;
        s.skyRays += sky;
        s.samples += samples;
    }
};

// What a light offers a point: the unit direction to it, the distance to reach it, and the irradiance it
// brings to a surface facing it.
struct LightSample {
    glm::dvec3 dir;
    double distance;
    glm::vec3 irradiance;
};

// The light as seen from `p`. Without `u` the direction aims at the light's centre (Whitted's hard shadows);
// with a sample `u` in [0, 1)^2 it is spread uniformly over the solid angle the light subtends (the sun's disc,
// or a spherical light), which averages into soft shadows (Cook, Porter and Carpenter 1984, "Distributed ray
// tracing"). The irradiance is the light's whole irradiance either way; only visibility is sampled.
LightSample sampleLight(const SceneLight& light, const glm::dvec3& p, const std::optional<glm::dvec2>& u) {
    if (light.kind == LightKind::Sun) {
        glm::dvec3 dir = light.direction;
        if (u && light.cosAngularRadius < 1.0)
            dir = Frame::around(light.direction).toWorld(squareToUniformCone(*u, light.cosAngularRadius));
        return {dir, kInfinity, light.radiance};
    }
    const glm::dvec3 toCentre = light.position - p;
    const double d = glm::length(toCentre);
    const glm::dvec3 axis = toCentre / d;
    const glm::vec3 irradiance = light.radiance / float(std::max(d * d, 1e-12));
    if (light.kind == LightKind::Point) return {axis, d, irradiance};
    if (!u || d <= light.radiusM) return {axis, std::max(0.0, d - light.radiusM), irradiance};
    // A direction in the cone the sphere subtends, and the distance to the sphere's near surface along it.
    const double cosMax = sphereConeCosine(d, light.radiusM);
    const glm::dvec3 dir = Frame::around(axis).toWorld(squareToUniformCone(*u, cosMax));
    const double along = glm::dot(toCentre, dir);
    const double off2 = std::max(0.0, d * d - along * along);
    const double reach = along - std::sqrt(std::max(0.0, light.radiusM * light.radiusM - off2));
    return {dir, std::max(0.0, reach), irradiance};
}

// Where the samples of one camera sample come from: its pixel, its index, and the pattern. Dimension 0 is
// the film position, 1 the lens, 2 (1D) the shutter time; then each bounce takes one 2D dimension per light
// and one for the glossy lobe. Without distribution (one sample per pixel) every query returns none and the
// tracer aims at centres.
class SampleSource {
public:
    SampleSource(const PixelSampler* sampler, int px, int py, int k, int lights, uint64_t seed)
        : sampler_(sampler), px_(px), py_(py), k_(k), lights_(lights), stream_(seed ^ kSkyStreamKey, px, py, uint64_t(k)) {}
    std::optional<glm::dvec2> light(int depth, int index) const { return get(uint32_t(3 + depth * (lights_ + 1) + index)); }
    std::optional<glm::dvec2> gloss(int depth) const { return get(uint32_t(3 + depth * (lights_ + 1) + lights_)); }
    // The shift of the sky-visibility lattice at a bounce: this sample's own random point.
    glm::dvec2 skyShift(int depth) const { return stream_.uniform2(uint64_t(2 * depth)); }

private:
    std::optional<glm::dvec2> get(uint32_t dimension) const {
        if (!sampler_) return std::nullopt;
        return sampler_->sample(px_, py_, k_, dimension);
    }
    static constexpr uint64_t kSkyStreamKey = 0x736b792d76697321ull;
    const PixelSampler* sampler_;
    int px_, py_, k_, lights_;
    RandomStream stream_;
};

class Tracer {
public:
    Tracer(const Scene& scene, const Sky& sky, const SceneRenderSettings& settings, Counters& counters,
           std::vector<RayRecord>* tree, const SampleSource& samples, bool aerial)
        : scene_(scene), sky_(sky), s_(settings), counters_(counters), tree_(tree), samples_(samples), aerial_(aerial) {}

    // Radiance arriving along `ray` (unit direction), travelling through a medium absorbing `sigma` per metre,
    // which is the air when `inAir` (outside every dielectric). `factor` is what the caller multiplies the result
    // by: the ray's share of the light leaving its parent's hit, for the debug tree.
    glm::vec3 trace(const Ray& ray, RayKind kind, int depth, const glm::vec3& weight, const glm::vec3& sigma,
                    bool inAir, const glm::vec3& factor) {
        counters_.count(kind);
        const size_t record = beginRecord(ray, kind, depth, weight);
        SurfaceHit hit;
        glm::vec3 radiance;
        if (!scene_.intersect(ray, {0.0, kInfinity}, hit)) {
            ++counters_.sky;
            radiance = sky_.radiance(ray.dir) + sunDisc(ray.dir);
            endRecord(record, "sky", kInfinity, weight * radiance);
            makeUp(record, radiance, glm::vec3(1.0f), glm::vec3(0.0f), factor * radiance);
            return radiance;
        }
        const glm::vec3 atHit = shade(ray, hit, depth, weight, sigma, inAir, record);
        glm::vec3 passed{1.0f}, inscattered{0.0f};
        if (sigma != glm::vec3(0.0f)) passed = beerLambert(sigma, hit.t);
        // Aerial perspective on every segment through the air: the camera's own, and those of reflections and
        // of rays leaving glass or water (already part of the sky's radiance for rays that miss). The tables
        // hold the air seen from the camera's height, which segments that start elsewhere take as theirs.
        if (inAir && aerial_) {
            glm::vec3 air;
            sky_.air(ray.dir, hit.t, air, inscattered);
            passed *= air;
        }
        radiance = atHit * passed + inscattered;
        endRecord(record, scene_.objects()[size_t(hit.object)].name, hit.t, weight * radiance);
        makeUp(record, atHit, passed, inscattered, factor * radiance);
        return radiance;
    }

private:
    // `record` is the debug tree's record of `ray`.
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, int depth, const glm::vec3& weight, const glm::vec3& sigma,
                    bool inAir, size_t record) {
        const SceneObject& obj = scene_.objects()[size_t(hit.object)];
        const MaterialDescription& m = scene_.materials()[size_t(obj.material)];
        const bool entering = glm::dot(ray.dir, hit.normal) < 0.0;
        const glm::dvec3 n = entering ? hit.normal : -hit.normal;  // facing the ray
        // What diffuse and Phong shading read: a height field's smooth normal, or the surface's own. Reflection,
        // refraction and which lights can reach the point stay with the geometric normal.
        const glm::dvec3 shading = entering ? hit.shadingNormal() : -hit.shadingNormal();
        glm::vec3 radiance{0.0f};

        if (m.kd > 0.0f || m.ks > 0.0f) {
            const glm::vec3 albedo = surfaceColour(obj, m, hit);
            if (m.kd > 0.0f) radiance += skyLight(hit, shading, depth, weight, ray.time, albedo * m.kd, record);
            // Under water the sun's light arrives along its direction refracted by the surface.
            const SceneObject* waterAbove = scene_.waterAbove(hit.point);
            for (size_t li = 0; li < scene_.lights().size(); ++li) {
                const SceneLight& light = scene_.lights()[li];
                LightSample ls = sampleLight(light, hit.point, samples_.light(depth, int(li)));
                if (light.kind == LightKind::Sun) ls.irradiance = sky_.sunlight(ls.irradiance, ls.dir, hit.point.z);
                const SceneObject* water = light.kind == LightKind::Sun ? waterAbove : nullptr;
                glm::dvec3 toLight = ls.dir;
                if (water) {
                    const auto bent = underwaterSunDirection(ls.dir, waterIndex(*water));
                    if (!bent) continue;  // a sun below the horizon does not light the water
                    toLight = *bent;
                }
                // The surface faces away: no shadow ray (and none lights a smooth normal past the terminator).
                const double cosL = std::min(glm::dot(n, toLight), glm::dot(shading, toLight));
                if (cosL <= 0.0) continue;
                const glm::vec3 t = water ? sunThroughWater(hit, ls.dir, toLight, *water, depth, weight, ray.time)
                                          : shadowTransmittance(hit, ls.dir, ls.distance, sigma, depth, weight, ray.time);
                if (t == glm::vec3(0.0f)) continue;
                glm::vec3 local = albedo * m.kd * float(glm::dot(shading, toLight));
                if (m.ks > 0.0f) {
                    const double cosR = glm::dot(reflect(-toLight, shading), -ray.dir);
                    if (cosR > 0.0) local += glm::vec3(m.ks * float(std::pow(cosR, double(m.exponent))));
                }
                radiance += t * ls.irradiance * local;
                if (tree_) (*tree_)[lastShadowRecord_].share = t * ls.irradiance * local;
            }
        }
        if (depth >= s_.maxDepth) return radiance;

        if (maxComponent(m.mirror) > 0.0f) {
            const glm::vec3 w = weight * m.mirror;
            if (maxComponent(w) >= s_.minWeight) {
                const glm::dvec3 r = reflectedDirection(ray.dir, n, m.gloss, depth);
                radiance += m.mirror * trace(spawn(hit, r, ray.time), RayKind::Reflection, depth + 1, w, sigma, inAir,
                                             m.mirror);
            }
        }
        if (m.dielectric) radiance += refractAndReflect(ray, hit, m, entering, n, depth, weight, sigma, inAir);
        return radiance;
    }

    // The dielectric part: Fresnel-weighted reflection and refraction; one refraction ray per colour channel when
    // the indices differ (dispersion), each carrying its own channel.
    glm::vec3 refractAndReflect(const Ray& ray, const SurfaceHit& hit, const MaterialDescription& m, bool entering,
                                const glm::dvec3& n, int depth, const glm::vec3& weight, const glm::vec3& sigma,
                                bool inAir) {
        const double cosI = -glm::dot(ray.dir, n);
        const glm::vec3 inside = m.absorptionPerM;
        const glm::vec3 sigmaAfter = entering ? inside : glm::vec3(0.0f);
        glm::vec3 reflectance, result{0.0f};
        const int channels = m.dispersive ? 3 : 1;
        for (int c = 0; c < channels; ++c) {
            const double ior = m.ior[c];
            const double etaFrom = entering ? 1.0 : ior, etaTo = entering ? ior : 1.0;
            const double f = m.fresnel == FresnelModel::Exact ? fresnelDielectric(cosI, etaFrom, etaTo)
                                                              : fresnelSchlick(cosI, etaFrom, etaTo);
            glm::vec3 mask = m.dispersive ? glm::vec3(0.0f) : glm::vec3(1.0f);
            if (m.dispersive) mask[c] = 1.0f;
            if (m.dispersive)
                reflectance[c] = float(f);
            else
                reflectance = glm::vec3(float(f));
            const glm::vec3 w = weight * mask * float(1.0 - f);
            if (f >= 1.0 || maxComponent(w) < s_.minWeight) continue;
            if (const auto t = refract(ray.dir, n, etaFrom, etaTo))
                result += mask * float(1.0 - f) * trace(spawn(hit, *t, ray.time), RayKind::Refraction, depth + 1, w,
                                                        sigmaAfter, !entering, mask * float(1.0 - f));
        }
        const glm::vec3 w = weight * reflectance;
        if (maxComponent(w) >= s_.minWeight) {
            const glm::dvec3 r = glm::normalize(reflect(ray.dir, n));
            result += reflectance * trace(spawn(hit, r, ray.time), RayKind::Reflection, depth + 1, w, sigma, inAir,
                                          reflectance);
        }
        return result;
    }

    // The fraction of a light's radiance that reaches `hit` along `dir`: zero behind an opaque object;
    // through dielectrics, the Fresnel transmission at each interface and Beer-Lambert absorption inside
    // (without bending the ray: Whitted's transparent shadows).
    glm::vec3 shadowTransmittance(const SurfaceHit& from, const glm::dvec3& dir, double distance, glm::vec3 sigma,
                                  int depth, const glm::vec3& weight, double time) {
        counters_.count(RayKind::Shadow);
        Ray ray = spawn(from, dir, time);
        const size_t record = beginRecord(ray, RayKind::Shadow, depth + 1, weight);
        lastShadowRecord_ = record;
        const double reach = distance - from.errorM;
        if (scene_.occludedByOpaque(ray, {0.0, reach})) {
            endRecord(record, "blocked", 0.0, glm::vec3(0.0f));
            return glm::vec3(0.0f);
        }
        glm::vec3 t{1.0f};
        if (scene_.hasDielectric()) {
            double left = reach;
            for (int k = 0; k < kMaxShadowInterfaces; ++k) {
                SurfaceHit hit;
                if (!scene_.intersect(ray, {0.0, left}, hit)) break;
                if (sigma != glm::vec3(0.0f)) t *= beerLambert(sigma, hit.t);
                const MaterialDescription& m =
                    scene_.materials()[size_t(scene_.objects()[size_t(hit.object)].material)];
                const bool entering = glm::dot(ray.dir, hit.normal) < 0.0;
                const double cosI = std::abs(glm::dot(ray.dir, hit.normal));
                for (int c = 0; c < 3; ++c) {
                    const double ior = m.ior[c];
                    const double etaFrom = entering ? 1.0 : ior, etaTo = entering ? ior : 1.0;
                    t[c] *= float(1.0 - (m.fresnel == FresnelModel::Exact ? fresnelDielectric(cosI, etaFrom, etaTo)
                                                                           : fresnelSchlick(cosI, etaFrom, etaTo)));
                }
                sigma = entering ? m.absorptionPerM : glm::vec3(0.0f);
                left -= hit.t;
                ray = spawn(hit, dir, time);
                if (k + 1 == kMaxShadowInterfaces) t = glm::vec3(0.0f);
            }
            if (std::isfinite(left) && sigma != glm::vec3(0.0f)) t *= beerLambert(sigma, left);
        }
        endRecord(record, "light", distance, t);
        return t;
    }

    // The index of refraction of a water object's material (the green channel's, should it be dispersive: the
    // sun's light then follows one direction under water).
    float waterIndex(const SceneObject& water) const { return scene_.materials()[size_t(water.material)].ior.g; }

    // The direction towards a sun in direction `toSun` (in the air) as seen from under a flat water surface of
    // index `eta`: light from it crosses the surface and bends towards the vertical by Snell's law,
    // sin(under) = sin(above) / eta, in the same vertical plane. None for a sun at or below the horizon.
    static std::optional<glm::dvec3> underwaterSunDirection(const glm::dvec3& toSun, double eta) {
        if (toSun.z <= 0.0) return std::nullopt;
        const double sinAbove = std::sqrt(std::max(0.0, 1.0 - toSun.z * toSun.z));
        if (sinAbove == 0.0) return glm::dvec3(0.0, 0.0, 1.0);
        const double sinUnder = sinAbove / eta;
        const double scale = sinUnder / sinAbove;
        return glm::normalize(glm::dvec3(toSun.x * scale, toSun.y * scale, std::sqrt(1.0 - sinUnder * sinUnder)));
    }

    // The fraction of a sun's light (its irradiance on a surface facing it, in the air) that reaches `hit` under
    // `water`'s surface, per unit of the cosine between the surface and the underwater direction `under`: with a
    // flat interface the refracted direction is one constant, so one ray follows the light's exact path, from
    // `hit` up along `under` to the surface, then on along `toSun` through the air. Along it: the terrain and
    // other opaque objects under water, Beer-Lambert over the path in the water, the Fresnel transmittance of
    // the surface at the sun's incidence (no total internal reflection from the air's side), the air's own
    // shadow ray, and the beam's change of cross-section: a beam of unit cross-section in the air lights
    // cos(above) of the surface, spread under water over a beam of cross-section cos(above) / cos(under).
    glm::vec3 sunThroughWater(const SurfaceHit& hit, const glm::dvec3& toSun, const glm::dvec3& under,
                              const SceneObject& water, int depth, const glm::vec3& weight, double time) {
        const auto& surface = static_cast<const WaterPrimitive&>(*water.primitive);
        const MaterialDescription& m = scene_.materials()[size_t(water.material)];
        counters_.count(RayKind::Shadow);
        const Ray up = spawn(hit, under, time);
        const double inWater = (surface.level() - hit.point.z) / under.z;
        const size_t record = beginRecord(up, RayKind::Shadow, depth + 1, weight);
        if (scene_.occludedByOpaque(up, {0.0, inWater})) {
            endRecord(record, "blocked", 0.0, glm::vec3(0.0f));
            return glm::vec3(0.0f);
        }
        glm::vec3 t = beerLambert(m.absorptionPerM, inWater) * float(toSun.z / under.z);
        for (int c = 0; c < 3; ++c)
            t[c] *= float(1.0 - (m.fresnel == FresnelModel::Exact ? fresnelDielectric(toSun.z, 1.0, m.ior[c])
                                                                  : fresnelSchlick(toSun.z, 1.0, m.ior[c])));
        endRecord(record, "water surface", inWater, t);
        // Where the light crosses the surface, as the surface itself finds it (with its rounding bound); beyond
        // the water's rectangle, the same point on its plane.
        SurfaceHit exit;
        if (!surface.intersect(up, {0.0, kInfinity}, exit)) {
            exit.point = hit.point + under * inWater;
            exit.point.z = surface.level();
            exit.normal = {0.0, 0.0, 1.0};
            exit.errorM = std::max(hit.errorM, 1e-9 * std::abs(exit.point.z));
        }
        return t * shadowTransmittance(exit, toSun, kInfinity, glm::vec3(0.0f), depth, weight, time);
    }

    glm::vec3 surfaceColour(const SceneObject& obj, const MaterialDescription& m, const SurfaceHit& hit) const {
        if (obj.kind != ObjectKind::HeightField) {
            // Textures repeat every textureScale units of the primitive's (u, v).
            const glm::dvec2 uv = hit.uv / m.textureScale;
            if (const auto& texture = scene_.textures()[size_t(obj.material)]) return texture->sampleRepeated(uv.x, uv.y);
            if (m.checker) {
                const int64_t parity = int64_t(std::floor(uv.x)) + int64_t(std::floor(uv.y));
                return (parity & 1) == 0 ? m.colour : m.checkerColour;
            }
            return m.colour;
        }
        const auto* hf = static_cast<const HeightFieldPrimitive*>(obj.primitive.get());
        switch (m.terrain) {
        case TerrainColouring::Slope: return slopeAlbedo(hit.shadingNormal().z);
        case TerrainColouring::Drape: {
            const auto& drape = scene_.drapes()[size_t(obj.material)];
            if (drape) return drape->sample(hit.uv.x, hit.uv.y);
            break;
        }
        case TerrainColouring::Plain: return m.colour;
        case TerrainColouring::Elevation: break;
        }
        return elevationAlbedo(hit.point.z - hf->offset().z, hf->grid().minHeightM(), hf->grid().maxHeightM());
    }

    // Light from the sky on a diffuse surface of reflectance `diffuse` (albedo times kd): the sky's light on a
    // surface so oriented, times the open fraction of the hemisphere when the sky asks for visibility rays
    // (cosine-weighted directions about the normal, each tested against opaque objects), so that valleys and the
    // ground under objects get less of it. Weighting visibility rather than each ray's radiance keeps open ground
    // free of noise. `record` is the debug tree's record of the ray that met the surface.
    glm::vec3 skyLight(const SurfaceHit& hit, const glm::dvec3& n, int depth, const glm::vec3& weight, double time,
                       const glm::vec3& diffuse, size_t record) {
        if (sky_.ambientScale() <= 0.0f) return glm::vec3(0.0f);
        const glm::vec3 open = sky_.ambient(n);
        const int count = scene_.sky().samples;
        if (count <= 0) {
            if (tree_) (*tree_)[record].skyLight = diffuse * open;
            return diffuse * open;
        }
        return diffuse * open * openSkyFraction(n, count, samples_.skyShift(depth), [&](const glm::dvec3& dir) {
                   counters_.count(RayKind::SkyVisibility);
                   const Ray ray = spawn(hit, dir, time);
                   const size_t visibility = beginRecord(ray, RayKind::SkyVisibility, depth + 1, weight);
                   const bool blocked = scene_.occludedByOpaque(ray, {0.0, kInfinity});
                   endRecord(visibility, blocked ? "blocked" : "sky", blocked ? 0.0 : kInfinity,
                             blocked ? glm::vec3(0.0f) : open);
                   // Each open direction adds its part of the sky's light.
                   if (tree_ && !blocked) (*tree_)[visibility].share = diffuse * open / float(count);
                   return blocked;
               });
    }

    // The sun's disc, seen directly or in a mirror: its irradiance spread over the disc's solid angle (reddened
    // by the air between the camera and the sun with the physical sky).
    glm::vec3 sunDisc(const glm::dvec3& dir) const {
        glm::vec3 l{0.0f};
        for (const SceneLight& light : scene_.lights()) {
            if (light.kind != LightKind::Sun || light.cosAngularRadius >= 1.0) continue;
            if (glm::dot(dir, light.direction) >= light.cosAngularRadius)
                l += sky_.sunlight(light.radiance, light.direction, sky_.viewerAltitudeM()) /
                     float(2.0 * kPi * (1.0 - light.cosAngularRadius));
        }
        return l;
    }

    // The mirror direction, or with a gloss exponent a direction drawn from Phong's power-cosine lobe around
    // it (folded back above the surface when the lobe dips below it).
    glm::dvec3 reflectedDirection(const glm::dvec3& dir, const glm::dvec3& n, float gloss, int depth) const {
        const glm::dvec3 r = glm::normalize(reflect(dir, n));
        if (gloss <= 0.0f) return r;
        const auto u = samples_.gloss(depth);
        if (!u) return r;
        glm::dvec3 g = Frame::around(r).toWorld(squareToPhongLobe(*u, double(gloss)));
        if (glm::dot(g, n) <= 0.0) g = glm::normalize(reflect(g, n));
        return g;
    }

    static Ray spawn(const SurfaceHit& hit, const glm::dvec3& dir, double time) {
        return {offsetOrigin(hit, dir), dir, time};
    }

    size_t beginRecord(const Ray& ray, RayKind kind, int depth, const glm::vec3& weight) {
        if (!tree_) return 0;
        tree_->push_back({kind, depth, ray.origin, ray.dir, "", 0.0, weight, glm::vec3(0.0f)});
        return tree_->size() - 1;
    }
    void endRecord(size_t k, const std::string& what, double t, const glm::vec3& contribution) {
        if (!tree_) return;
        (*tree_)[k].hit = what;
        (*tree_)[k].t = t;
        (*tree_)[k].contribution = contribution;
    }
    void makeUp(size_t k, const glm::vec3& atHit, const glm::vec3& passed, const glm::vec3& inscattered,
                const glm::vec3& share) {
        if (!tree_) return;
        (*tree_)[k].atHit = atHit;
        (*tree_)[k].passed = passed;
        (*tree_)[k].inscattered = inscattered;
        (*tree_)[k].share = share;
    }

    const Scene& scene_;
    const Sky& sky_;
    const SceneRenderSettings& s_;
    Counters& counters_;
    std::vector<RayRecord>* tree_;
    SampleSource samples_;
    bool aerial_;
    size_t lastShadowRecord_ = 0;  // the debug tree's record of the last shadow ray towards a light
};

// One camera sample: its film position (drawn in proportion to the pixel filter, so that every sample weighs
// the same: PixelFilter::offsetOf), lens point and time from the sampler, traced.
glm::vec3 cameraSample(const Scene& scene, const Sky& sky, const ViewCamera& camera, const SceneRenderSettings& s,
                          const PixelSampler* sampler, int x, int y, int k, Counters& counters,
                          std::vector<RayRecord>* tree) {
    glm::dvec2 offset{0.0}, lens{0.5};
    double time = 0.0;
    if (sampler) {
        offset = s.filter.offsetOf(sampler->sample(x, y, k, 0));
        lens = sampler->sample(x, y, k, 1);
        time = sampler->sample1D(x, y, k, 2);
    }
    const auto ray = camera.generate((x + 0.5 + offset.x) / s.width, (y + 0.5 + offset.y) / s.height, lens, time);
    if (!ray) return glm::vec3(0.0f);  // outside a fisheye's circle: black
    // Aerial perspective needs one centre of projection: the orthographic camera's rays have none.
    const bool aerial = sky.aerialPerspective() && camera.kind() != CameraKind::Orthographic;
    Tracer tracer(scene, sky, s, counters, tree, SampleSource(sampler, x, y, k, int(scene.lights().size()), s.seed),
                  aerial);
    return tracer.trace(*ray, RayKind::Primary, 0, glm::vec3(1.0f), glm::vec3(0.0f), true, glm::vec3(1.0f));
}

glm::vec3 pixelValue(const Scene& scene, const Sky& sky, const ViewCamera& camera, const SceneRenderSettings& s,
                     const PixelSampler* sampler, int x, int y, Counters& counters, std::vector<RayRecord>* tree) {
    return s.exposure * estimatePixel(s, sampler, cancelFlag(), [&](int k) {
               ++counters.samples;
               return cameraSample(scene, sky, camera, s, sampler, x, y, k, counters, tree);
           });
}

}  // namespace

const char* rayKindName(RayKind kind) {
    switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
    case RayKind::SkyVisibility: return "sky-visibility";
    }
    return "ray";
}

Sky makeSceneSky(const Scene& scene, double viewerAltitudeM) {
    std::optional<SkySun> sun;
    for (const SceneLight& light : scene.lights())
        if (light.kind == LightKind::Sun) {
            sun = SkySun{light.direction, light.radiance};
            break;
        }
    return Sky(scene.sky(), sun, viewerAltitudeM);
}

ViewCamera makeSceneCamera(const Scene& scene, const CameraDescription& d, double aspect) {
    glm::dvec3 eye, look;
    if (d.eye && d.lookAt) {
        eye = *d.eye;
        look = *d.lookAt;
    } else {
        // Frame the terrain (or every bounded object) from the south-west, 30 degrees down, as `render` does.
        Bounds3 box = scene.bounds();
        if (!box.finite()) box = {glm::dvec3(-1.0), glm::dvec3(1.0)};
        const glm::dvec3 centre = box.centre();
        const double pitch = radians(30.0), azimuth = radians(45.0);
        glm::dvec3 forward = directionFromRadians(azimuth, -pitch);
        if (d.lookAt && !d.eye) forward = glm::normalize(*d.lookAt - centre + forward * 1e-9);
        const double tanV = std::tan(radians(d.fovDeg) * 0.5), tanH = tanV * aspect;
        const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
        const glm::dvec3 up = glm::cross(right, forward);
        double distance = 0.0;
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 corner{k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z};
            const glm::dvec3 r = corner - centre;
            const double along = glm::dot(r, forward);
            distance = std::max({distance, std::abs(glm::dot(r, right)) / tanH - along,
                                 std::abs(glm::dot(r, up)) / tanV - along});
        }
        look = d.lookAt.value_or(centre);
        eye = d.eye.value_or(centre - 1.05 * distance * forward);
        if (d.eye && !d.lookAt) look = centre;
    }
    CameraDescription desc = d;
    if (desc.kind == CameraKind::Orthographic && desc.orthoHeightM <= 0.0) {
        const Bounds3 box = scene.bounds();
        desc.orthoHeightM = box.finite() ? glm::length(box.hi - box.lo) : 2.0;
    }
    return ViewCamera(desc, eye, look, aspect);
}

std::optional<double> focusDistanceAt(const Scene& scene, const ViewCamera& camera, int x, int y, int width,
                                      int height) {
    // The lens centre sees what a pinhole would.
    const auto ray = camera.generate((x + 0.5) / width, (y + 0.5) / height, {0.5, 0.5}, 0.0);
    SurfaceHit hit;
    if (!ray || !scene.intersect(*ray, {0.0, kInfinity}, hit)) return std::nullopt;
    return glm::dot(hit.point - camera.eye(), camera.forward());
}

glm::vec3 tracePixel(const Scene& scene, const ViewCamera& camera, const SceneRenderSettings& s, int x, int y,
                     std::vector<RayRecord>* tree, SceneRayStats* stats) {
    Counters counters;
    const auto sampler = s.makeSampler(s.seed);
    const Sky sky = makeSceneSky(scene, camera.eye().z);
    const glm::vec3 value = pixelValue(scene, sky, camera, s, sampler.get(), x, y, counters, tree);
    if (stats) counters.addTo(*stats);
    return value;
}

Film renderScene(const Scene& scene, const ViewCamera& camera, const SceneRenderSettings& s, SceneRayStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    Film film(s.width, s.height);
    std::mutex mutex;
    SceneRayStats total;
    int64_t pixelsDone = 0;
    const int64_t pixels = int64_t(s.width) * s.height;
    const auto sampler = s.makeSampler(s.seed);
    const Sky sky = makeSceneSky(scene, camera.eye().z);
    parallelForTiles(s.width, s.height, s.tileSize, s.threads, [&](int x0, int y0, int x1, int y1) {
        Counters counters;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                if (cancelFlag().load(std::memory_order_relaxed)) return;  // parallelForTiles throws Cancelled
                film.set(x, y, pixelValue(scene, sky, camera, s, sampler.get(), x, y, counters, nullptr));
            }
        std::lock_guard lock(mutex);
        counters.addTo(total);
        pixelsDone += int64_t(x1 - x0) * (y1 - y0);
        if (s.progress) s.progress(double(pixelsDone) / double(pixels), total.total());
    });
    total.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (stats) *stats = total;
    return film;
}

}  // namespace terracast
