// Sunlight on a lake bed against its analytic value: light from a sun at any elevation above the horizon crosses
// a flat water surface along Snell's refracted direction, keeps the surface's Fresnel transmittance and loses
// Beer-Lambert's share over its slanted path in the water, and lights a horizontal bed with the irradiance of
// the beam that entered the surface above it.
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

using namespace terracast;

namespace {

// The Fresnel reflectance of unpolarised light entering index n2 from n1 at incidence cosine cosI (Born and
// Wolf, "Principles of Optics", section 1.5), written out here as the test's own reference.
double fresnelReference(double cosI, double n1, double n2) {
    const double sinT = n1 / n2 * std::sqrt(1.0 - cosI * cosI);
    const double cosT = std::sqrt(1.0 - sinT * sinT);
    const double rs = (n1 * cosI - n2 * cosT) / (n1 * cosI + n2 * cosT);
    const double rp = (n2 * cosI - n1 * cosT) / (n2 * cosI + n1 * cosT);
    return 0.5 * (rs * rs + rp * rp);
}

// A white material named `name` that colours terrain plainly.
MaterialDescription whiteGround(const std::string& name) {
    MaterialDescription m;
    m.name = name;
    m.colour = glm::vec3(1.0f);
    m.terrain = TerrainColouring::Plain;
    return m;
}

// Water named "water" of index `n` absorbing `sigma` per metre, with the exact Fresnel reflectance.
MaterialDescription water(double n, const glm::dvec3& sigma) {
    MaterialDescription m;
    m.name = "water";
    m.kd = 0.0f;
    m.dielectric = true;
    m.ior = glm::vec3(float(n));
    m.absorptionPerM = glm::vec3(sigma);
    m.fresnel = FresnelModel::Exact;
    return m;
}

}  // namespace

TEST_CASE("A lake bed receives the sun through the water at any elevation, as Fresnel, Snell and Beer-Lambert say",
          "[scene][water]") {
    const double depth = 2.0, n = 1.333;
    const glm::dvec3 sigma{0.3, 0.1, 0.05};
    for (const double elevationDeg : {10.0, 30.0, 45.0, 70.0}) {
        INFO("sun elevation " << elevationDeg << " degrees");
        SceneDescription d;
        d.materials.push_back(whiteGround("bed"));
        d.materials.push_back(water(n, sigma));
        // A flat bed 41 m square at z = 0, under water 2 m deep.
        const int size = 41;
        SceneAssets assets;
        assets.grids.push_back(
            std::make_shared<const HeightGrid>(size, size, 1.0, 1.0, std::vector<float>(size_t(size) * size, 0.0f)));
        ObjectDescription field;
        field.kind = ObjectKind::HeightField;
        field.offsetM = {-20.0, -20.0, 0.0};
        field.material = "bed";
        d.objects.push_back(field);
        ObjectDescription lake;
        lake.kind = ObjectKind::Water;
        lake.levelM = depth;
        lake.material = "water";
        d.objects.push_back(lake);
        LightDescription sun;
        sun.azimuthDeg = 200.0;
        sun.elevationDeg = elevationDeg;
        d.lights.push_back(sun);
        d.sky.kind = SkyKind::None;  // the sun alone, not reddened by air
        // Looking straight down at the bed's centre.
        d.camera.eye = glm::dvec3(0.0, 0.0, 10.0);
        d.camera.lookAt = glm::dvec3(0.0, 0.0, 0.0);
        d.camera.up = glm::dvec3(0.0, 1.0, 0.0);
        d.camera.fovDeg = 1.0;
        const Scene scene(d, assets);
        SceneRenderSettings s;
        s.width = s.height = 1;
        const glm::vec3 pixel = tracePixel(scene, makeSceneCamera(scene, d.camera, 1.0), s, 0, 0, nullptr);

        // The bed's irradiance: the sun's unit irradiance on the horizontal surface (sin e), the share that
        // crosses the surface, and what is left after the slanted path of depth / cos(under) in the water.
        const double e = elevationDeg * M_PI / 180.0;
        const double cosAbove = std::sin(e);
        const double sinUnder = std::cos(e) / n, cosUnder = std::sqrt(1.0 - sinUnder * sinUnder);
        const double camera = 1.0 - fresnelReference(1.0, 1.0, n);  // the camera's ray enters at normal incidence
        for (int c = 0; c < 3; ++c) {
            const double bedIrradiance =
                cosAbove * (1.0 - fresnelReference(cosAbove, 1.0, n)) * std::exp(-sigma[c] * depth / cosUnder);
            // The white bed sends it back; the camera's ray crosses the surface and the 2 m of water above it.
            const double expected = bedIrradiance * camera * std::exp(-sigma[c] * depth);
            CHECK(pixel[c] == Approx(expected).epsilon(1e-4));
        }
    }
}

namespace {

// A ramp 20 m long across x (heights base + 0.5 x; its southern row starts at 0 m) and 4 m wide, water at
// `level`, seen horizontally along its middle (y = 0) from 10 m west of the footprint at height `eyeZ`: the
// centre pixel and its ray tree.
struct RampView {
    glm::vec3 pixel;
    std::vector<RayRecord> tree;
};

RampView rampView(double base, double level, double eyeZ, bool withWater) {
    SceneDescription d;
    d.materials.push_back(whiteGround("ground"));
    d.materials.push_back(water(1.333, glm::dvec3(1.0)));
    const int w = 21, h = 5;
    std::vector<float> heights(size_t(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) heights[size_t(j) * w + size_t(i)] = float((j == 0 ? 0.0 : base) + 0.5 * i);
    SceneAssets assets;
    assets.grids.push_back(std::make_shared<const HeightGrid>(w, h, 1.0, 1.0, heights));
    ObjectDescription ramp;
    ramp.kind = ObjectKind::HeightField;
    ramp.name = "ramp";
    ramp.offsetM = {0.0, -2.0, 0.0};
    ramp.material = "ground";
    d.objects.push_back(ramp);
    if (withWater) {
        ObjectDescription lake;
        lake.kind = ObjectKind::Water;
        lake.name = "lake";
        lake.levelM = level;
        lake.material = "water";
        d.objects.push_back(lake);
    }
    LightDescription sun;
    sun.azimuthDeg = 270.0;
    sun.elevationDeg = 50.0;
    d.lights.push_back(sun);
    d.sky.kind = SkyKind::None;
    d.camera.eye = glm::dvec3(-10.0, 0.0, eyeZ);
    d.camera.lookAt = glm::dvec3(0.0, 0.0, eyeZ);
    d.camera.fovDeg = 1.0;
    const Scene scene(d, assets);
    SceneRenderSettings s;
    s.width = s.height = 1;
    RampView v;
    v.pixel = tracePixel(scene, makeSceneCamera(scene, d.camera, 1.0), s, 0, 0, &v.tree);
    return v;
}

}  // namespace

TEST_CASE("Water is closed at the terrain's edge: terrain under the level is seen through the water's side",
          "[scene][water]") {
    // The ramp's edge is at 0 m, the water at 3 m: a ray at 1 m enters the water through its side and meets the
    // ramp 2 m further on (where it reaches 1 m), under water.
    const RampView dry = rampView(0.0, 3.0, 1.0, false);
    const RampView wet = rampView(0.0, 3.0, 1.0, true);
    REQUIRE(dry.tree.size() >= 1);
    CHECK(dry.tree[0].hit == "ramp");
    CHECK(dry.tree[0].t == Approx(12.0).epsilon(1e-6));
    REQUIRE(wet.tree.size() >= 2);
    CHECK(wet.tree[0].hit == "lake");
    CHECK(wet.tree[0].t == Approx(10.0).epsilon(1e-9));
    bool refractedToRamp = false;
    for (const RayRecord& r : wet.tree)
        refractedToRamp = refractedToRamp || (r.kind == RayKind::Refraction && r.hit == "ramp" &&
                                              r.t == Approx(2.0).epsilon(1e-6));
    CHECK(refractedToRamp);
    // Two metres of water absorbing 1 per metre, both ways for the sun's light: far darker than dry land.
    INFO("dry " << dry.pixel.r << ", through the water " << wet.pixel.r);
    CHECK(wet.pixel.r < 0.2f * dry.pixel.r);
    CHECK(wet.pixel.r > 0.0f);

    // Where the terrain's edge stands above the water (a ramp starting at 1 m, water at 3 m), there is no side
    // below it: a ray at 0.5 m passes under the terrain as it would without water (the water's side does reach
    // down to 0 m at the southern corner).
    const RampView under = rampView(1.0, 3.0, 0.5, true);
    REQUIRE(!under.tree.empty());
    CHECK(under.tree[0].hit != "lake");
}
