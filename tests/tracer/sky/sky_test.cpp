// The render's sky: sunlight through the air, sky light through the open part of the hemisphere, aerial
// perspective, and the rays each sky setting costs.
#include "tracer/core/angles.h"
#include "tracer/scene/scene_renderer.h"
#include "tracer/sky/sky.h"
#include "tracer/terrain/terrain_renderer.h"

#include "tracer/scene/scene.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

namespace {


// A unit direction by compass azimuth and elevation, degrees.
glm::dvec3 fromAngles(double azimuthDeg, double elevationDeg) { return directionFromDegrees(azimuthDeg, elevationDeg); }

SkyDescription physical() {
    SkyDescription d;
    d.kind = SkyKind::Physical;
    return d;
}

}  // namespace

TEST_CASE("Physical sunlight is white at the zenith over sea level and reddens as the sun sinks", "[tracer][sky]") {
    const Sky sky(physical(), SkySun{{0, 0, 1}, glm::vec3(2.0f)}, 100.0);
    const glm::vec3 noon = sky.sunlight(glm::vec3(2.0f), {0, 0, 1}, 0.0);
    for (int c = 0; c < 3; ++c) CHECK(noon[c] == Approx(2.0f).epsilon(1e-3));
    // Higher up, less air in front of the sun: brighter than at sea level, bluest channel gaining most.
    const glm::vec3 summit = sky.sunlight(glm::vec3(1.0f), {0, 0, 1}, 4000.0);
    CHECK(summit.b > summit.r);
    CHECK(summit.r > 1.0f);
    const glm::vec3 evening = sky.sunlight(glm::vec3(1.0f), fromAngles(270.0, 3.0), 0.0);
    CHECK(evening.r > evening.g);
    CHECK(evening.g > evening.b);
    // The simple skies leave the sun alone.
    SkyDescription flat;
    flat.kind = SkyKind::Flat;
    const Sky plain(flat, SkySun{{0, 0, 1}, glm::vec3(1.0f)}, 0.0);
    CHECK(plain.sunlight(glm::vec3(0.7f), fromAngles(270.0, 3.0), 0.0) == glm::vec3(0.7f));
}

TEST_CASE("Aerial perspective fades distant surfaces towards the horizon sky", "[tracer][sky]") {
    const Sky sky(physical(), SkySun{fromAngles(200.0, 30.0), glm::vec3(1.0f)}, 500.0);
    const glm::dvec3 dir = fromAngles(20.0, -0.3);
    const glm::vec3 surface{0.05f, 0.08f, 0.03f};
    const glm::vec3 horizon = sky.radiance(fromAngles(20.0, 0.5));
    const glm::vec3 near = sky.throughAir(surface, dir, 10.0);
    for (int c = 0; c < 3; ++c) CHECK(near[c] == Approx(surface[c]).epsilon(0.01));
    float previous = glm::length(surface - horizon);
    for (const double d : {2000.0, 10000.0, 40000.0, 120000.0}) {
        const float gap = glm::length(sky.throughAir(surface, dir, d) - horizon);
        INFO("distance " << d);
        CHECK(gap < previous);
        previous = gap;
    }
    CHECK(previous < 0.5f * glm::length(surface - horizon));
    SkyDescription off = physical();
    off.aerialPerspective = false;
    const Sky clear(off, SkySun{fromAngles(200.0, 30.0), glm::vec3(1.0f)}, 500.0);
    CHECK(clear.throughAir(surface, dir, 120000.0) == surface);
}

TEST_CASE("Sky light on a trench floor is the open fraction of the hemisphere", "[tracer][sky]") {
    // A trench 20 m wide and 20 m deep, 2 km long north-south (cells 0.25 m across it, 1 m along it), under a
    // uniform (flat) sky and a sun straight overhead, so floor and plain get the same sunlight. From the middle of
    // the floor the sky shows through the slot; the cosine-weighted share of a long slot seen from its centre
    // line is sin(atan(w / 2d)) (the walls slope over one 0.25 m cell: w = 20.25 m, at mid-slope).
    const int64_t nx = 241, ny = 2001;
    std::vector<float> z(size_t(nx * ny), 20.0f);
    for (int64_t j = 0; j < ny; ++j)
        for (int64_t i = 80; i <= 160; ++i) z[size_t(j * nx + i)] = 0.0f;
    const HeightGrid grid(nx, ny, 0.25, 1.0, z);
    TerrainRenderSettings s;
    s.width = 16;
    s.height = 16;
    s.threads = 2;
    s.camera.eyeM = {30, 1000, 5000};
    s.camera.lookAtM = {30, 1000, 0};
    s.camera.up = {0, 1, 0};
    s.camera.fovYDeg = 0.01;  // every pixel looks at the floor's centre line
    s.sun = Sun{0.0, 90.0};
    s.sky.kind = SkyKind::Flat;
    s.sky.colour = glm::vec3(1.0f);
    s.sky.ambient = 1.0f;
    s.sky.samples = 256;
    const TerrainSurface surface(grid, SurfaceMethod::Bilinear);
    RenderStats stats;
    const Film floor = renderTerrain(grid, surface, s, &stats);
    CHECK(stats.skyVisibilityRays == 16 * 16 * 256);
    s.camera.eyeM = {5, 1000, 5000};
    s.camera.lookAtM = {5, 1000, 0};
    const Film rim = renderTerrain(grid, surface, s);
    const glm::vec3 albedoFloor = elevationAlbedo(0.0, 0.0, 20.0), albedoRim = elevationAlbedo(20.0, 0.0, 20.0);
    // Light = sun (1 for a surface facing a zenith sun; the flat sky's sun keeps its pale colour) + sky share.
    const glm::vec3 sunColour{1.0f, 0.96f, 0.90f};
    double floorShare = 0.0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) floorShare += (floor.get(x, y).g / albedoFloor.g - sunColour.g) / 256.0;
    const glm::vec3 rimLight = rim.get(8, 8) / albedoRim - sunColour;
    CHECK(rimLight.g == Approx(1.0).epsilon(1e-4));  // the open plain sees the whole sky
    const double expected = std::sin(std::atan(10.125 / 20.0));
    INFO("floor sky share " << floorShare << ", slot view factor " << expected);
    CHECK(floorShare == Approx(expected).margin(0.01));
    // Without visibility rays the floor would get the full sky: the rays are what darkens it.
    s.sky.samples = 0;
    s.camera.eyeM = {30, 1000, 5000};
    s.camera.lookAtM = {30, 1000, 0};
    RenderStats none;
    const Film unoccluded = renderTerrain(grid, surface, s, &none);
    CHECK(none.skyVisibilityRays == 0);
    CHECK(unoccluded.get(8, 8).g / albedoFloor.g - sunColour.g == Approx(1.0).epsilon(1e-3));
}

TEST_CASE("Sky-visibility rays are traced only when the sky has light to give", "[tracer][sky][scene]") {
    SceneDescription d;
    ObjectDescription ground;
    ground.kind = ObjectKind::Plane;
    ground.normal = {0, 0, 1};
    d.objects.push_back(ground);
    d.camera.eye = glm::dvec3(0, 0, 3);
    d.camera.lookAt = glm::dvec3(0, 10, 0);
    SceneRenderSettings s;
    s.width = 32;
    s.height = 24;
    s.threads = 2;
    auto render = [&](const SceneDescription& desc) {
        const Scene scene(desc, {});
        SceneRayStats stats;
        renderScene(scene, makeSceneCamera(scene, desc.camera, 32.0 / 24.0), s, &stats);
        return stats;
    };
    const SceneRayStats on = render(d);
    CHECK(on.skyVisibility == 4 * (on.primary - on.skyRays));
    d.sky.samples = 0;
    CHECK(render(d).skyVisibility == 0);
    d.sky.samples = 4;
    d.sky.kind = SkyKind::None;
    CHECK(render(d).skyVisibility == 0);
    d.sky.kind = SkyKind::Gradient;
    d.sky.ambient = 0.0f;
    CHECK(render(d).skyVisibility == 0);
}

TEST_CASE("Skies for another sun, viewer altitude or haze get their own tables, however often they are made",
          "[tracer][sky]") {
    // Each sky against tables built here from scratch, by the ratio of its radiance in several directions (the
    // sky's own scale, its white balance times the sun's irradiance, cancels).
    struct Case {
        glm::dvec3 sun;
        double altitudeM;
        double haze;
    };
    const std::vector<Case> cases{{fromAngles(200.0, 30.0), 500.0, 1.0}, {fromAngles(90.0, 8.0), 500.0, 1.0},
                                  {fromAngles(200.0, 30.0), 3000.0, 1.0}, {fromAngles(200.0, 30.0), 500.0, 4.0}};
    const std::vector<glm::dvec3> dirs{fromAngles(0.0, 60.0), fromAngles(120.0, 5.0), fromAngles(210.0, 25.0),
                                       fromAngles(300.0, 1.0), fromAngles(45.0, -20.0)};
    for (int round = 0; round < 2; ++round)
        for (const Case& c : cases) {
            SkyDescription d = physical();
            d.haze = c.haze;
            const Sky sky(d, SkySun{c.sun, glm::vec3(1.0f)}, c.altitudeM);
            AtmosphereParameters a;
            a.haze = c.haze;
            const SkyTables fresh(std::make_shared<const TransmittanceTable>(a), c.altitudeM, c.sun);
            const glm::vec3 skyBase = sky.radiance(dirs[0]), freshBase = fresh.radiance(dirs[0]);
            for (const glm::dvec3& dir : dirs) {
                INFO("round " << round << ", sun z " << c.sun.z << ", altitude " << c.altitudeM << " m, haze " << c.haze
                              << ", direction z " << dir.z);
                const glm::vec3 got = sky.radiance(dir) / skyBase, want = fresh.radiance(dir) / freshBase;
                for (int k = 0; k < 3; ++k) CHECK(got[k] == Approx(want[k]).epsilon(1e-5));
            }
        }
}
