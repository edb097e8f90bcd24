// The Whitted scene tracer against analytic answers: sphere silhouettes and distances, Fresnel, total internal
// reflection, Beer-Lambert through a slab, a mirror image, the rays each scene pays for, shadows through glass
// under either Fresnel model, and dispersion by Snell's law per colour channel.
#include "support/scene_builders.h"
#include "tracer/scene/optics.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

int countKind(const std::vector<RayRecord>& tree, RayKind kind) {
    return int(std::count_if(tree.begin(), tree.end(), [&](const RayRecord& r) { return r.kind == kind; }));
}

}  // namespace

TEST_CASE("Camera rays meet a sphere exactly inside its analytic silhouette, at the analytic distance", "[scene]") {
    const double distance = 10.0, radius = 2.0;
    SceneDescription d;
    d.objects.push_back(sphere({0, distance, 0}, radius));
    d.camera = lookingAt({0, 0, 0}, {0, 1, 0}, 40.0);
    Scene scene(d, {});
    const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
    const double sinEdge = radius / distance;
    int hits = 0, checked = 0;
    for (int y = 0; y < 200; ++y) {
        for (int x = 0; x < 200; ++x) {
            const Ray ray = *cam.generate((x + 0.5) / 200, (y + 0.5) / 200);
            // theta: angle between the ray and the direction to the centre.
            const double cosTheta = ray.dir.y;
            const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
            if (std::abs(sinTheta - sinEdge) < 1e-9) continue;
            ++checked;
            SurfaceHit hit;
            const bool got = scene.intersect(ray, {0.0, kInfinity}, hit);
            REQUIRE(got == (sinTheta < sinEdge));
            if (!got) continue;
            ++hits;
            const double expected = distance * cosTheta - std::sqrt(radius * radius - std::pow(distance * sinTheta, 2));
            REQUIRE(hit.t == Approx(expected).epsilon(1e-12));
            REQUIRE(glm::length(hit.point - glm::dvec3(0, distance, 0)) == Approx(radius).epsilon(1e-12));
        }
    }
    CHECK(checked > 39000);
    CHECK(hits > 1000);
}

TEST_CASE("A sphere far from the origin is still hit to within a micrometre", "[scene]") {
    // UTM-sized coordinates: the precision-preserving discriminant keeps the hit on the surface.
    const glm::dvec3 c{5.0e5, 5.2e6, 1500.0};
    SpherePrimitive s(c, 3.0);
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 eye = c + glm::dvec3(-4000.0, -3000.0, 500.0);
        const glm::dvec3 target = c + 2.9 * glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)));
        const Ray ray{eye, glm::normalize(target - eye)};
        SurfaceHit hit;
        REQUIRE(s.intersect(ray, {0.0, kInfinity}, hit));
        REQUIRE(std::abs(glm::length(hit.point - c) - 3.0) < 1e-6);
    }
}

TEST_CASE("Fresnel reflectance is 0.04 at normal incidence for n = 1.5 and rises to 1 at grazing", "[scene]") {
    for (auto fresnel : {fresnelSchlick, fresnelDielectric}) {
        CHECK(fresnel(1.0, 1.0, 1.5) == Approx(0.04).margin(1e-12));
        CHECK(fresnel(1e-9, 1.0, 1.5) == Approx(1.0).margin(1e-6));
        double previous = 0.0;
        for (int k = 0; k <= 90; ++k) {  // monotone in the angle of incidence
            const double f = fresnel(std::cos(k * M_PI / 180.0), 1.0, 1.5);
            CHECK(f >= previous - 1e-12);
            previous = f;
        }
    }
    // Schlick's curve stays within a few hundredths of the exact one below 80 degrees.
    for (int k = 0; k <= 80; k += 5) {
        const double c = std::cos(k * M_PI / 180.0);
        CHECK(std::abs(fresnelSchlick(c, 1.0, 1.5) - fresnelDielectric(c, 1.0, 1.5)) < 0.03);
    }
}

TEST_CASE("Total internal reflection begins at the critical angle of 41.8 degrees for n = 1.5", "[scene]") {
    CHECK(criticalAngle(1.5, 1.0) * 180.0 / M_PI == Approx(41.81).margin(0.01));
    const glm::dvec3 n{0, 0, -1};  // facing a ray going up inside glass
    for (double deg : {41.7, 41.9}) {
        const double a = deg * M_PI / 180.0;
        const glm::dvec3 d{std::sin(a), 0.0, std::cos(a)};
        const auto t = refract(d, n, 1.5, 1.0);
        CHECK(t.has_value() == (deg < 41.81));
        CHECK((fresnelDielectric(std::cos(a), 1.5, 1.0) == 1.0) == (deg > 41.81));
        CHECK((fresnelSchlick(std::cos(a), 1.5, 1.0) == 1.0) == (deg > 41.81));
        if (t) CHECK(1.5 * std::sin(a) == Approx(std::sqrt(t->x * t->x + t->y * t->y)).epsilon(1e-12));
    }

    // In a scene: a ray inside a glass block meeting its top face beyond the critical angle spawns no refraction.
    SceneDescription d;
    d.materials.push_back(clearGlass());
    d.objects.push_back(box({-100, -100, -1}, {100, 100, 0}, "glass"));
    d.sky.kind = SkyKind::Flat;
    d.render.maxDepth = 1;
    for (double deg : {30.0, 50.0}) {
        const double a = deg * M_PI / 180.0;
        d.camera = lookingAt({0, 0, -0.5}, glm::dvec3(0, 0, -0.5) + glm::dvec3(std::sin(a), 0, std::cos(a)));
        d.render.width = d.render.height = 1;
        Scene scene(d, {});
        const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
        std::vector<RayRecord> tree;
        tracePixel(scene, cam, settingsFor(d), 0, 0, &tree);
        CHECK(countKind(tree, RayKind::Refraction) == (deg < 41.81 ? 1 : 0));
        CHECK(countKind(tree, RayKind::Reflection) == 1);
    }
}

TEST_CASE("Light through an absorbing slab keeps exp(-sigma s) of its radiance", "[scene]") {
    // Index 1: no Fresnel reflection and no bending, so only Beer-Lambert acts on the flat white sky.
    const glm::vec3 sigma{0.5f, 1.0f, 2.0f};
    const double thickness = 0.7;
    SceneDescription d;
    MaterialDescription ink;
    ink.name = "ink";
    ink.kd = 0.0f;
    ink.dielectric = true;
    ink.ior = glm::vec3(1.0f);
    ink.absorptionPerM = sigma;
    d.materials.push_back(ink);
    d.objects.push_back(box({-50, -50, 1.0}, {50, 50, 1.0 + thickness}, "ink"));
    d.sky.kind = SkyKind::Flat;
    d.sky.colour = glm::vec3(1.0f);
    d.lights.push_back(LightDescription{});
    d.lights.back().intensity = 0.0f;
    for (double tilt : {0.0, 30.0}) {
        const double a = tilt * M_PI / 180.0;
        d.camera = lookingAt({0, 0, 0}, {std::sin(a), 0, std::cos(a)}, 1.0);
        d.camera.up = {0, 1, 0};
        d.render.width = d.render.height = 1;
        Scene scene(d, {});
        const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
        const glm::vec3 v = tracePixel(scene, cam, settingsFor(d), 0, 0, nullptr);
        const double path = thickness / std::cos(a);
        for (int c = 0; c < 3; ++c) CHECK(v[c] == Approx(std::exp(-sigma[c] * path)).epsilon(1e-5));
    }
}

TEST_CASE("A mirror shows a point at the pixel where its mirror image projects", "[scene]") {
    SceneDescription d;
    MaterialDescription mirror;
    mirror.name = "mirror";
    mirror.kd = 0.0f;
    mirror.mirror = glm::vec3(0.9f);
    d.materials.push_back(mirror);
    d.objects.push_back(plane({0, 0, 0}, {0, 0, 1}, "mirror"));
    const glm::dvec3 p{3.0, 20.0, 2.0};
    d.objects.push_back(sphere(p, 0.05));
    d.objects.back().name = "marker";
    d.sky.kind = SkyKind::Flat;
    d.camera = lookingAt({0, 0, 5}, {0, 20, 0}, 40.0);
    d.render.width = d.render.height = 401;
    Scene scene(d, {});
    const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
    // Project the mirror image (3, 20, -2) into the film.
    const glm::dvec3 image{p.x, p.y, -p.z};
    const glm::dvec3 f = cam.forward(), r = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1))), u = glm::cross(r, f);
    const glm::dvec3 q = image - cam.eye();
    const double tanV = std::tan(20.0 * M_PI / 180.0);
    const double fx = 0.5 * (1.0 + glm::dot(q, r) / glm::dot(q, f) / tanV);
    const double fy = 0.5 * (1.0 - glm::dot(q, u) / glm::dot(q, f) / tanV);
    const int px = int(fx * 401), py = int(fy * 401);
    std::vector<RayRecord> tree;
    tracePixel(scene, cam, settingsFor(d), px, py, &tree);
    REQUIRE(tree.size() >= 2);
    CHECK(tree[0].hit == "plane 1");
    bool sawMarker = false;
    for (const auto& rec : tree) sawMarker = sawMarker || (rec.kind == RayKind::Reflection && rec.hit == "marker");
    CHECK(sawMarker);
    // Ten pixels away the reflection misses the marker.
    tree.clear();
    tracePixel(scene, cam, settingsFor(d), px + 10, py, &tree);
    for (const auto& rec : tree) CHECK(rec.hit != "marker");
}

TEST_CASE("A scene traces only the ray kinds its materials and lights call for", "[scene]") {
    SceneDescription d;
    d.objects.push_back(plane({0, 0, 0}, {0, 0, 1}));
    d.objects.push_back(sphere({0, 10, 1}, 1.0));
    d.camera = lookingAt({0, 0, 3}, {0, 10, 0});
    d.render.width = 64;
    d.render.height = 48;
    SECTION("opaque Phong only: no reflection or refraction rays") {
        Scene scene(d, {});
        SceneRayStats stats;
        renderScene(scene, makeSceneCamera(scene, d.camera, 4.0 / 3.0), settingsFor(d), &stats);
        CHECK(stats.primary == 64 * 48);
        CHECK(stats.shadow > 0);
        CHECK(stats.reflection == 0);
        CHECK(stats.refraction == 0);
        CHECK_FALSE(scene.usesBvh());
    }
    SECTION("a sun below the horizon: no shadow rays from the ground") {
        d.objects.pop_back();
        d.lights.push_back(LightDescription{});
        d.lights.back().elevationDeg = -10.0;
        Scene scene(d, {});
        SceneRayStats stats;
        renderScene(scene, makeSceneCamera(scene, d.camera, 4.0 / 3.0), settingsFor(d), &stats);
        CHECK(stats.primary == 64 * 48);
        CHECK(stats.shadow == 0);
    }
    SECTION("a mirror adds reflection rays but still no refraction") {
        MaterialDescription m;
        m.name = "chrome";
        m.mirror = glm::vec3(0.8f);
        d.materials.push_back(m);
        d.objects[1].material = "chrome";
        Scene scene(d, {});
        SceneRayStats stats;
        renderScene(scene, makeSceneCamera(scene, d.camera, 4.0 / 3.0), settingsFor(d), &stats);
        CHECK(stats.reflection > 0);
        CHECK(stats.refraction == 0);
    }
    SECTION("glass adds refraction rays") {
        MaterialDescription m;
        m.name = "glass";
        m.kd = 0.0f;
        m.dielectric = true;
        d.materials.push_back(m);
        d.objects[1].material = "glass";
        Scene scene(d, {});
        SceneRayStats stats;
        renderScene(scene, makeSceneCamera(scene, d.camera, 4.0 / 3.0), settingsFor(d), &stats);
        CHECK(stats.refraction > 0);
        CHECK(stats.reflection > 0);
    }
}

TEST_CASE("The scene hierarchy finds the same nearest hits as testing every object", "[scene]") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-20.0, 20.0), r(0.2, 2.0);
    SceneDescription d;
    for (int k = 0; k < 200; ++k) {
        if (k % 3 == 0)
            d.objects.push_back(box({u(rng), u(rng), u(rng)}, glm::dvec3(0.0)));
        else
            d.objects.push_back(sphere({u(rng), u(rng), u(rng)}, r(rng)));
        if (k % 3 == 0) d.objects.back().boxMax = d.objects.back().boxMin + glm::dvec3(r(rng), r(rng), r(rng));
    }
    Scene scene(d, {});
    REQUIRE(scene.usesBvh());
    for (int k = 0; k < 20000; ++k) {
        const Ray ray{{u(rng), u(rng), u(rng)}, glm::normalize(glm::dvec3(u(rng), u(rng), u(rng)))};
        SurfaceHit viaBvh;
        const bool got = scene.intersect(ray, {0.0, kInfinity}, viaBvh);
        double best = kInfinity;
        for (const auto& obj : scene.objects()) {
            SurfaceHit h;
            if (obj.primitive->intersect(ray, {0.0, best}, h)) best = h.t;
        }
        REQUIRE(got == std::isfinite(best));
        if (got) REQUIRE(viaBvh.t == best);
    }
}

TEST_CASE("A non-convex polygon contains exactly the points of its even-odd interior", "[scene]") {
    // An L shape in the plane z = 1: the unit square [0,2]x[0,2] without [1,2]x[1,2].
    PolygonPrimitive poly({{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {1, 1, 1}, {1, 2, 1}, {0, 2, 1}});
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-0.5, 2.5);
    for (int k = 0; k < 20000; ++k) {
        const double x = u(rng), y = u(rng);
        const bool inside = x > 0 && x < 2 && y > 0 && y < 2 && !(x > 1 && y > 1);
        if (std::min({std::abs(x), std::abs(y), std::abs(x - 1), std::abs(y - 1), std::abs(x - 2), std::abs(y - 2)}) < 1e-9)
            continue;
        SurfaceHit hit;
        REQUIRE(poly.intersect({{x, y, 5.0}, {0, 0, -1}}, {0.0, kInfinity}, hit) == inside);
        if (inside) REQUIRE(hit.t == Approx(4.0));
    }
}

TEST_CASE("A box is hit on the face the ray enters, and from inside on the face it leaves", "[scene]") {
    BoxPrimitive b({0, 0, 0}, {1, 2, 3});
    SurfaceHit hit;
    REQUIRE(b.intersect({{-1, 1, 1}, {1, 0, 0}}, {0.0, kInfinity}, hit));
    CHECK(hit.t == Approx(1.0));
    CHECK(hit.normal == glm::dvec3(-1, 0, 0));
    REQUIRE(b.intersect({{0.5, 1, 1}, {0, 0, 1}}, {0.0, kInfinity}, hit));
    CHECK(hit.t == Approx(2.0));
    CHECK(hit.normal == glm::dvec3(0, 0, 1));
    CHECK_FALSE(b.intersect({{-1, 3, 1}, {1, 0, 0}}, {0.0, kInfinity}, hit));
}

TEST_CASE("Panorama and fisheye cameras map the picture to the expected directions", "[scene]") {
    SceneDescription d;
    d.objects.push_back(sphere({0, 0, 0}, 1.0));
    d.camera = lookingAt({0, 0, 0}, {0, 1, 0});
    d.camera.kind = CameraKind::Panorama;
    Scene scene(d, {});
    const ViewCamera pano = makeSceneCamera(scene, d.camera, 2.0);
    CHECK(glm::length(pano.generate(0.5, 0.5)->dir - glm::dvec3(0, 1, 0)) < 1e-12);   // centre: ahead
    CHECK(glm::length(pano.generate(0.75, 0.5)->dir - glm::dvec3(1, 0, 0)) < 1e-12);  // right: east
    CHECK(glm::length(pano.generate(0.5, 0.0)->dir - glm::dvec3(0, 0, 1)) < 1e-12);   // top: zenith
    CHECK(glm::length(pano.generate(0.0, 0.5)->dir - glm::dvec3(0, -1, 0)) < 1e-12);  // left edge: behind
    d.camera.kind = CameraKind::Fisheye;
    d.camera.fovDeg = 180.0;
    const ViewCamera fish = makeSceneCamera(scene, d.camera, 1.0);
    CHECK(glm::length(fish.generate(0.5, 0.5)->dir - glm::dvec3(0, 1, 0)) < 1e-12);
    CHECK(glm::length(fish.generate(1.0, 0.5)->dir - glm::dvec3(1, 0, 0)) < 1e-12);  // the rim is 90 degrees off
    CHECK_FALSE(fish.generate(0.99, 0.99).has_value());                              // outside the circle
}

TEST_CASE("A thin lens keeps the focus plane sharp and blurs nearer points over the circle of confusion", "[scene]") {
    CameraDescription c = lookingAt({0, 0, 0}, {0, 10, 0}, 30.0);
    c.kind = CameraKind::ThinLens;
    c.apertureRadiusM = 0.1;
    c.focusDistanceM = 10.0;
    SceneDescription d;
    Scene scene(d, {});
    const ViewCamera cam = makeSceneCamera(scene, c, 1.0);
    // Rays through one film point from different lens positions meet at the focus plane...
    const Ray a = *cam.generate(0.6, 0.4, {0.1, 0.2}), b = *cam.generate(0.6, 0.4, {0.9, 0.7});
    const glm::dvec3 pa = a.at((10.0 - a.origin.y) / a.dir.y), pb = b.at((10.0 - b.origin.y) / b.dir.y);
    CHECK(glm::length(pa - pb) < 1e-9);
    // ...and spread at distance 5 over a disc of diameter 2 a |5 - 10| / 10 = 0.1 m (similar triangles).
    double widest = 0.0;
    for (int k = 0; k < 64; ++k) {
        const double ang = k * 2.0 * M_PI / 64.0;
        const glm::dvec2 lens{0.5 + 0.5 * std::cos(ang) * 0.999999, 0.5 + 0.5 * std::sin(ang) * 0.999999};
        const Ray r1 = *cam.generate(0.5, 0.5, lens);
        const glm::dvec3 p = r1.at((5.0 - r1.origin.y) / r1.dir.y);
        widest = std::max(widest, 2.0 * std::hypot(p.x, p.z));
    }
    CHECK(widest == Approx(0.1).epsilon(1e-3));
}

namespace {

// The Fresnel equations for unpolarised light, written out here as the reference: the mean of the s- and
// p-polarised reflectances, 1 under total internal reflection.
double fresnelReference(double cosI, double n1, double n2) {
    const double sinT = n1 / n2 * std::sqrt(1.0 - cosI * cosI);
    if (sinT >= 1.0) return 1.0;
    const double cosT = std::sqrt(1.0 - sinT * sinT);
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// Schlick's approximation as published: R0 + (1 - R0)(1 - cos)^5, with the cosine on the less dense side.
double schlickReference(double cosI, double n1, double n2) {
    double c = cosI;
    if (n1 > n2) c = std::sqrt(1.0 - (n1 / n2) * (n1 / n2) * (1.0 - cosI * cosI));
    const double r0 = (n1 - n2) * (n1 - n2) / ((n1 + n2) * (n1 + n2));
    return r0 + (1.0 - r0) * std::pow(1.0 - c, 5.0);
}

}  // namespace

TEST_CASE("Shadow rays through glass use the material's Fresnel model", "[scene]") {
    // A white floor under a 0.5 m glass slab (n = 1.5) at z = 2; the sun at elevation 60, so its shadow ray
    // crosses both faces at 30 degrees from the normal without bending. The floor point under the camera gets
    // the sun's irradiance times cos 30 times the transmission (1 - F_in)(1 - F_out) of the two faces.
    SceneDescription d;
    MaterialDescription white;
    white.name = "white";
    white.colour = glm::vec3(1.0f);
    d.materials.push_back(white);
    d.materials.push_back(clearGlass());
    d.objects.push_back(plane({0, 0, 0}, {0, 0, 1}, "white"));
    d.objects.push_back(box({-100, -100, 2.0}, {100, 100, 2.5}, "glass"));
    d.sky.kind = SkyKind::None;
    LightDescription sun;
    sun.azimuthDeg = 0.0;
    sun.elevationDeg = 60.0;
    d.lights.push_back(sun);
    d.camera = lookingAt({0, 0, 1}, {0, 0, 0}, 1.0);
    d.camera.up = {0, 1, 0};
    d.render.width = d.render.height = 1;
    const double cosI = std::cos(M_PI / 6.0);
    for (const FresnelModel model : {FresnelModel::Schlick, FresnelModel::Exact}) {
        d.materials[1].fresnel = model;
        const bool exact = model == FresnelModel::Exact;
        INFO((exact ? "exact" : "Schlick"));
        const auto f = exact ? fresnelReference : schlickReference;
        const double through = (1.0 - f(cosI, 1.0, 1.5)) * (1.0 - f(cosI, 1.5, 1.0));
        const double other = exact ? (1.0 - schlickReference(cosI, 1.0, 1.5)) * (1.0 - schlickReference(cosI, 1.5, 1.0))
                                   : (1.0 - fresnelReference(cosI, 1.0, 1.5)) * (1.0 - fresnelReference(cosI, 1.5, 1.0));
        REQUIRE(std::abs(through - other) > 0.005);  // the two models are told apart below
        Scene scene(d, {});
        const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
        std::vector<RayRecord> tree;
        const glm::vec3 v = tracePixel(scene, cam, settingsFor(d), 0, 0, &tree);
        for (int c = 0; c < 3; ++c) CHECK(v[c] == Approx(through * cosI).epsilon(1e-5));
        REQUIRE(countKind(tree, RayKind::Shadow) == 1);
        for (const RayRecord& r : tree)
            if (r.kind == RayKind::Shadow) CHECK(r.contribution.r == Approx(through).epsilon(1e-5));
    }
}

TEST_CASE("A dispersive dielectric refracts each colour channel by its own index, as Snell's law says", "[scene]") {
    // A camera ray meets the flat top of a glass block at 40 degrees from the normal; the block's indices are
    // 1.50, 1.60 and 1.70 for red, green and blue. Each channel's refracted ray makes the angle asin(sin 40 / n)
    // with the inward normal, in the plane of incidence, and carries only its own channel, weighted by Schlick's
    // transmission.
    SceneDescription d;
    MaterialDescription flint;
    flint.name = "flint";
    flint.kd = 0.0f;
    flint.dielectric = true;
    flint.dispersive = true;
    flint.ior = {1.5f, 1.6f, 1.7f};
    d.materials.push_back(flint);
    d.objects.push_back(box({-100, -100, -1}, {100, 100, 0}, "flint"));
    d.sky.kind = SkyKind::Flat;
    d.render.width = d.render.height = 1;
    d.render.maxDepth = 1;
    const double theta = 40.0 * M_PI / 180.0;
    const glm::dvec3 eye{0, 0, 1};
    d.camera = lookingAt(eye, eye + glm::dvec3(std::sin(theta), 0.0, -std::cos(theta)), 1.0);
    Scene scene(d, {});
    const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
    std::vector<RayRecord> tree;
    tracePixel(scene, cam, settingsFor(d), 0, 0, &tree);
    REQUIRE(countKind(tree, RayKind::Refraction) == 3);
    int seen[3] = {0, 0, 0};
    double angles[3] = {0, 0, 0};
    for (const RayRecord& r : tree) {
        if (r.kind != RayKind::Refraction) continue;
        // The one channel this ray carries.
        int channel = -1;
        for (int c = 0; c < 3; ++c)
            if (r.weight[c] > 0.0f) {
                CHECK(channel == -1);
                channel = c;
            }
        REQUIRE(channel >= 0);
        ++seen[channel];
        const double n = flint.ior[channel];
        const double sinT = std::sin(theta) / n;
        const glm::dvec3 expected{sinT, 0.0, -std::sqrt(1.0 - sinT * sinT)};
        INFO("channel " << channel);
        CHECK(glm::length(r.dir - expected) < 1e-9);
        CHECK(r.weight[channel] == Approx(1.0 - schlickReference(std::cos(theta), 1.0, n)).epsilon(1e-5));
        angles[channel] = std::atan2(r.dir.x, -r.dir.z);
    }
    CHECK(seen[0] == 1);
    CHECK(seen[1] == 1);
    CHECK(seen[2] == 1);
    // Blue bends most: the spread between red and blue is the difference of the two Snell angles.
    CHECK(angles[0] > angles[1]);
    CHECK(angles[1] > angles[2]);
    CHECK(angles[0] - angles[2] ==
          Approx(std::asin(std::sin(theta) / double(flint.ior[0])) - std::asin(std::sin(theta) / double(flint.ior[2])))
              .epsilon(1e-9));
    // The same block with one index sends a single refraction ray.
    d.materials[0].dispersive = false;
    d.materials[0].ior = glm::vec3(1.6f);
    Scene plain(d, {});
    tree.clear();
    tracePixel(plain, makeSceneCamera(plain, d.camera, 1.0), settingsFor(d), 0, 0, &tree);
    CHECK(countKind(tree, RayKind::Refraction) == 1);
}
