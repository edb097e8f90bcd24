#include "tracer/scene_renderer.h"

#include "tracer/optics.h"
#include "tracer/parallel.h"
#include "tracer/terrain_renderer.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>

namespace terracast {

namespace {

constexpr double kPi = 3.14159265358979323846;
// Shadow rays through dielectrics pass at most this many interfaces before the light counts as blocked.
constexpr int kMaxShadowInterfaces = 16;

float maxComponent(const glm::vec3& v) { return std::max({v.r, v.g, v.b}); }

// A counter-based random number: the same (pixel, sample, seed, dimension) always gives the same value, so a
// picture does not depend on how pixels are shared among threads (SplitMix64 finaliser, Steele et al. 2014).
double hashUniform(uint64_t a, uint64_t b, uint64_t c, uint64_t d) {
    uint64_t z = a * 0x9E3779B97F4A7C15ull ^ (b + 0xBF58476D1CE4E5B9ull) * 0x94D049BB133111EBull ^
                 (c + 0x632BE59BD9B4E019ull) * 0xD6E8FEB86659FD93ull ^ d;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
}

glm::vec3 slopeAlbedo(double normalZ) {
    // Grass on gentle slopes, scree on steeper ones, bare rock on cliffs.
    const glm::vec3 grass{0.22f, 0.36f, 0.15f}, scree{0.45f, 0.40f, 0.33f}, rock{0.38f, 0.37f, 0.36f};
    const double slopeDeg = std::acos(std::clamp(normalZ, -1.0, 1.0)) * 180.0 / kPi;
    if (slopeDeg < 20.0) return glm::mix(grass, scree, float(slopeDeg / 20.0) * 0.3f);
    if (slopeDeg < 40.0) return glm::mix(glm::mix(grass, scree, 0.3f), scree, float((slopeDeg - 20.0) / 20.0));
    return glm::mix(scree, rock, float(std::min(1.0, (slopeDeg - 40.0) / 20.0)));
}

struct Counters {
    int64_t primary = 0, shadow = 0, reflection = 0, refraction = 0, sky = 0;
    void count(RayKind kind) {
        switch (kind) {
        case RayKind::Primary: ++primary; break;
        case RayKind::Shadow: ++shadow; break;
        case RayKind::Reflection: ++reflection; break;
        case RayKind::Refraction: ++refraction; break;
        }
    }
    void addTo(SceneRayStats& s) const {
        s.primary += primary;
        s.shadow += shadow;
        s.reflection += reflection;
        s.refraction += refraction;
        s.skyRays += sky;
    }
};

// What a light offers a point: the unit direction to it, the distance, and the radiance arriving.
struct LightSample {
    glm::dvec3 dir;
    double distance;
    glm::vec3 irradiance;
};

LightSample sampleLight(const SceneLight& light, const glm::dvec3& p) {
    if (light.kind == LightKind::Sun) return {light.direction, kInfinity, light.radiance};
    // Point and (for now, from their centre) sphere lights fall off with the square of the distance.
    const glm::dvec3 toLight = light.position - p;
    const double d = glm::length(toLight);
    const double reach = light.kind == LightKind::Sphere ? std::max(0.0, d - light.radiusM) : d;
    return {toLight / d, reach, light.radiance / float(std::max(d * d, 1e-12))};
}

class Tracer {
public:
    Tracer(const Scene& scene, const SceneRenderSettings& settings, Counters& counters, std::vector<RayRecord>* tree)
        : scene_(scene), s_(settings), counters_(counters), tree_(tree) {}

    // Radiance arriving along `ray` (unit direction), travelling through a medium absorbing `sigma` per metre.
    glm::vec3 trace(const Ray& ray, RayKind kind, int depth, const glm::vec3& weight, const glm::vec3& sigma) {
        counters_.count(kind);
        const size_t record = beginRecord(ray, kind, depth, weight);
        SurfaceHit hit;
        glm::vec3 radiance;
        if (!scene_.intersect(ray, {0.0, kInfinity}, hit)) {
            ++counters_.sky;
            radiance = skyRadiance(scene_, ray.dir) + sunDisc(ray.dir);
            endRecord(record, "sky", kInfinity, weight * radiance);
            return radiance;
        }
        radiance = shade(ray, hit, depth, weight, sigma);
        if (sigma != glm::vec3(0.0f)) radiance *= beerLambert(sigma, hit.t);
        endRecord(record, scene_.objects()[size_t(hit.object)].name, hit.t, weight * radiance);
        return radiance;
    }

private:
    glm::vec3 shade(const Ray& ray, const SurfaceHit& hit, int depth, const glm::vec3& weight, const glm::vec3& sigma) {
        const SceneObject& obj = scene_.objects()[size_t(hit.object)];
        const MaterialDescription& m = scene_.materials()[size_t(obj.material)];
        const bool entering = glm::dot(ray.dir, hit.normal) < 0.0;
        const glm::dvec3 n = entering ? hit.normal : -hit.normal;  // facing the ray
        glm::vec3 radiance{0.0f};

        if (m.kd > 0.0f || m.ks > 0.0f) {
            const glm::vec3 albedo = surfaceColour(obj, m, hit);
            // Sky light: the sky's colour straight up, stronger on surfaces facing up.
            radiance += scene_.sky().ambient * float(0.5 + 0.5 * n.z) * albedo * m.kd * skyAmbient();
            for (const SceneLight& light : scene_.lights()) {
                const LightSample ls = sampleLight(light, hit.point);
                const double cosL = glm::dot(n, ls.dir);
                if (cosL <= 0.0) continue;  // the surface faces away: no shadow ray
                const glm::vec3 t = shadowTransmittance(hit, ls.dir, ls.distance, sigma, depth, weight);
                if (t == glm::vec3(0.0f)) continue;
                glm::vec3 local = albedo * m.kd * float(cosL);
                if (m.ks > 0.0f) {
                    const double cosR = glm::dot(reflect(-ls.dir, n), -ray.dir);
                    if (cosR > 0.0) local += glm::vec3(m.ks * float(std::pow(cosR, double(m.exponent))));
                }
                radiance += t * ls.irradiance * local;
            }
        }
        if (depth >= s_.maxDepth) return radiance;

        if (maxComponent(m.mirror) > 0.0f) {
            const glm::vec3 w = weight * m.mirror;
            if (maxComponent(w) >= s_.minWeight) {
                const glm::dvec3 r = glm::normalize(reflect(ray.dir, n));
                radiance += m.mirror * trace(spawn(hit, r, ray.time), RayKind::Reflection, depth + 1, w, sigma);
            }
        }
        if (m.dielectric) radiance += refractAndReflect(ray, hit, m, entering, n, depth, weight, sigma);
        return radiance;
    }

    // The dielectric part: Fresnel-weighted reflection and refraction; one refraction ray per colour channel when
    // the indices differ (dispersion), each carrying its own channel.
    glm::vec3 refractAndReflect(const Ray& ray, const SurfaceHit& hit, const MaterialDescription& m, bool entering,
                                const glm::dvec3& n, int depth, const glm::vec3& weight, const glm::vec3& sigma) {
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
                result += mask * float(1.0 - f) *
                          trace(spawn(hit, *t, ray.time), RayKind::Refraction, depth + 1, w, sigmaAfter);
        }
        const glm::vec3 w = weight * reflectance;
        if (maxComponent(w) >= s_.minWeight) {
            const glm::dvec3 r = glm::normalize(reflect(ray.dir, n));
            result += reflectance * trace(spawn(hit, r, ray.time), RayKind::Reflection, depth + 1, w, sigma);
        }
        return result;
    }

    // The fraction of a light's radiance that reaches `hit` along `dir`: zero behind an opaque object;
    // through dielectrics, the Fresnel transmission at each interface and Beer-Lambert absorption inside
    // (without bending the ray: Whitted's transparent shadows).
    glm::vec3 shadowTransmittance(const SurfaceHit& from, const glm::dvec3& dir, double distance, glm::vec3 sigma,
                                  int depth, const glm::vec3& weight) {
        counters_.count(RayKind::Shadow);
        Ray ray = spawn(from, dir, 0.0);
        const size_t record = beginRecord(ray, RayKind::Shadow, depth + 1, weight);
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
                    t[c] *= float(1.0 - fresnelSchlick(cosI, entering ? 1.0 : ior, entering ? ior : 1.0));
                }
                sigma = entering ? m.absorptionPerM : glm::vec3(0.0f);
                left -= hit.t;
                ray = spawn(hit, dir, 0.0);
                if (k + 1 == kMaxShadowInterfaces) t = glm::vec3(0.0f);
            }
            if (std::isfinite(left) && sigma != glm::vec3(0.0f)) t *= beerLambert(sigma, left);
        }
        endRecord(record, "light", distance, t);
        return t;
    }

    glm::vec3 surfaceColour(const SceneObject& obj, const MaterialDescription& m, const SurfaceHit& hit) const {
        if (obj.kind != ObjectKind::HeightField) return m.colour;
        const auto* hf = static_cast<const HeightFieldPrimitive*>(obj.primitive.get());
        switch (m.terrain) {
        case TerrainColouring::Slope: return slopeAlbedo(hit.normal.z);
        case TerrainColouring::Drape: {
            const auto& drape = scene_.drapes()[size_t(obj.material)];
            if (drape) return drape->sample(hit.uv.x, hit.uv.y);
            break;
        }
        case TerrainColouring::Elevation: break;
        }
        return elevationAlbedo(hit.point.z - hf->offset().z, hf->grid().minHeightM(), hf->grid().maxHeightM());
    }

    glm::vec3 skyAmbient() const { return skyRadiance(scene_, {0.0, 0.0, 1.0}); }

    // The sun's disc, seen directly or in a mirror: its irradiance spread over the disc's solid angle.
    glm::vec3 sunDisc(const glm::dvec3& dir) const {
        glm::vec3 l{0.0f};
        for (const SceneLight& light : scene_.lights()) {
            if (light.kind != LightKind::Sun || light.cosAngularRadius >= 1.0) continue;
            if (glm::dot(dir, light.direction) >= light.cosAngularRadius)
                l += light.radiance / float(2.0 * kPi * (1.0 - light.cosAngularRadius));
        }
        return l;
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

    const Scene& scene_;
    const SceneRenderSettings& s_;
    Counters& counters_;
    std::vector<RayRecord>* tree_;
};

// The film position of sample k of pixel (x, y): the centre for one sample, otherwise a jittered stratum of
// a sqrt(n) x sqrt(n) grid (samples beyond the largest square are uniform).
glm::dvec2 samplePosition(int x, int y, int k, int n, uint64_t seed) {
    if (n <= 1) return {x + 0.5, y + 0.5};
    const int side = int(std::sqrt(double(n)));
    const double jx = hashUniform(uint64_t(x), uint64_t(y), uint64_t(k), seed * 4 + 0);
    const double jy = hashUniform(uint64_t(x), uint64_t(y), uint64_t(k), seed * 4 + 1);
    if (k < side * side) return {x + (k % side + jx) / side, y + (k / side + jy) / side};
    return {x + jx, y + jy};
}

glm::vec3 pixelValue(const Scene& scene, const SceneCamera& camera, const SceneRenderSettings& s, int x, int y,
                     Counters& counters, std::vector<RayRecord>* tree) {
    Tracer tracer(scene, s, counters, tree);
    glm::vec3 sum{0.0f};
    const int n = std::max(1, s.samples);
    for (int k = 0; k < n; ++k) {
        const glm::dvec2 p = samplePosition(x, y, k, n, s.seed);
        const glm::dvec2 lens{hashUniform(uint64_t(x), uint64_t(y), uint64_t(k), s.seed * 4 + 2),
                              hashUniform(uint64_t(x), uint64_t(y), uint64_t(k), s.seed * 4 + 3)};
        const auto ray = camera.generate(p.x / s.width, p.y / s.height, n > 1 ? lens : glm::dvec2(0.5), 0.0);
        if (!ray) continue;  // outside a fisheye's circle: black
        sum += tracer.trace(*ray, RayKind::Primary, 0, glm::vec3(1.0f), glm::vec3(0.0f));
    }
    return sum * (s.exposure / float(n));
}

}  // namespace

const char* rayKindName(RayKind kind) {
    switch (kind) {
    case RayKind::Primary: return "primary";
    case RayKind::Shadow: return "shadow";
    case RayKind::Reflection: return "reflection";
    case RayKind::Refraction: return "refraction";
    }
    return "ray";
}

glm::vec3 skyRadiance(const Scene& scene, const glm::dvec3& dir) {
    switch (scene.sky().kind) {
    case SkyKind::None: return glm::vec3(0.0f);
    case SkyKind::Flat: return scene.sky().colour;
    case SkyKind::Gradient:
    case SkyKind::Physical: return gradientSky(dir);
    }
    return glm::vec3(0.0f);
}

SceneCamera makeSceneCamera(const Scene& scene, const CameraDescription& d, double aspect) {
    glm::dvec3 eye, look;
    if (d.eye && d.lookAt) {
        eye = *d.eye;
        look = *d.lookAt;
    } else {
        // Frame the terrain (or every bounded object) from the south-west, 30 degrees down, as `render` does.
        Bounds3 box = scene.bounds();
        if (!box.finite()) box = {glm::dvec3(-1.0), glm::dvec3(1.0)};
        const glm::dvec3 centre = box.centre();
        const double pitch = 30.0 * kPi / 180.0, azimuth = 45.0 * kPi / 180.0;
        glm::dvec3 forward{std::sin(azimuth) * std::cos(pitch), std::cos(azimuth) * std::cos(pitch), -std::sin(pitch)};
        if (d.lookAt && !d.eye) forward = glm::normalize(*d.lookAt - centre + forward * 1e-9);
        const double tanV = std::tan(d.fovDeg * kPi / 360.0), tanH = tanV * aspect;
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
    return SceneCamera(desc, eye, look, aspect);
}

glm::vec3 tracePixel(const Scene& scene, const SceneCamera& camera, const SceneRenderSettings& s, int x, int y,
                     std::vector<RayRecord>* tree, SceneRayStats* stats) {
    Counters counters;
    const glm::vec3 value = pixelValue(scene, camera, s, x, y, counters, tree);
    if (stats) counters.addTo(*stats);
    return value;
}

Film renderScene(const Scene& scene, const SceneCamera& camera, const SceneRenderSettings& s, SceneRayStats* stats) {
    const auto start = std::chrono::steady_clock::now();
    Film film(s.width, s.height);
    std::mutex mutex;
    SceneRayStats total;
    int64_t pixelsDone = 0;
    const int64_t pixels = int64_t(s.width) * s.height;
    parallelForTiles(s.width, s.height, s.tileSize, s.threads, [&](int x0, int y0, int x1, int y1) {
        Counters counters;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) film.set(x, y, pixelValue(scene, camera, s, x, y, counters, nullptr));
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
