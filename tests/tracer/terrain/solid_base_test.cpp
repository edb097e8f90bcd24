// The default look of `render`: the solid base's walls (where rays meet them, against the edge profile and the
// floor written out here), how a rendered slab stands on them, and the backdrops.
#include "tracer/terrain/solid_base.h"
#include "tracer/terrain/terrain_renderer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace terracast;

namespace {

// 11 x 11 vertices on 10 m cells; the heights rise eastward, 10 m + 2 m per column, the same on every row.
HeightGrid eastwardRamp(std::vector<uint8_t> valid = {}) {
    std::vector<float> z(121);
    for (int j = 0; j < 11; ++j)
        for (int i = 0; i < 11; ++i) z[size_t(j * 11 + i)] = 10.0f + 2.0f * float(i);
    return HeightGrid(11, 11, 10.0, 10.0, z, std::move(valid));
}

}  // namespace

TEST_CASE("The solid base's south wall runs from the floor up to the edge profile", "[tracer][base]") {
    const HeightGrid g = eastwardRamp();
    // Heights 10 .. 30 m: the floor lies a tenth of the 20 m relief below, or a hundredth of the 100 m side,
    // whichever is more: 10 - 2 = 8 m.
    const double floor = solidBaseFloorM(g);
    CHECK(floor == Approx(8.0));
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> across(-20.0, 120.0), up(0.0, 40.0);
    int hits = 0, misses = 0;
    for (int k = 0; k < 4000; ++k) {
        // From the south, aimed at a point of the plane y = 0.
        const glm::dvec3 target{across(rng), 0.0, up(rng)};
        const glm::dvec3 origin{target.x + across(rng) - 50.0, -300.0, up(rng)};
        const Ray ray{origin, glm::normalize(target - origin)};
        const auto wall = intersectSolidBase(g, floor, ray, kInfinity);
        // The edge profile along y = 0 is 10 + 0.2 x over 0 <= x <= 100.
        const bool expected = target.x >= 0.0 && target.x <= 100.0 && target.z >= 8.0 && target.z <= 10.0 + 0.2 * target.x;
        const double nearEdge = std::min({std::abs(target.x), std::abs(target.x - 100.0), std::abs(target.z - 8.0),
                                          std::abs(target.z - 10.0 - 0.2 * target.x)});
        if (nearEdge < 1e-6) continue;
        INFO("target " << target.x << ", " << target.z);
        // A slanted ray that passes the south wall's plane beside the wall may meet the east or west wall.
        const bool south = wall && wall->normal == glm::dvec3(0.0, -1.0, 0.0);
        REQUIRE(south == expected);
        if (!south) {
            ++misses;
            continue;
        }
        ++hits;
        CHECK(wall->t == Approx(glm::length(target - origin)).epsilon(1e-12));
        CHECK(wall->normal == glm::dvec3(0.0, -1.0, 0.0));
        // Nearer than the wall: nothing.
        CHECK_FALSE(intersectSolidBase(g, floor, ray, wall->t * 0.999));
    }
    CHECK(hits > 500);
    CHECK(misses > 500);
}

TEST_CASE("The solid base has a gap under a nodata edge vertex and no inside faces", "[tracer][base]") {
    std::vector<uint8_t> valid(121, 1);
    valid[5] = 0;  // vertex (5, 0) on the south edge
    const HeightGrid g = eastwardRamp(valid);
    const double floor = solidBaseFloorM(g);
    const auto aimAt = [&](double x) {
        const glm::dvec3 target{x, 0.0, 12.0}, origin{x, -100.0, 12.0};
        return intersectSolidBase(g, floor, Ray{origin, glm::normalize(target - origin)}, kInfinity);
    };
    CHECK(aimAt(35.0));
    CHECK_FALSE(aimAt(45.0));  // the cells on either side of the hole
    CHECK_FALSE(aimAt(55.0));
    CHECK(aimAt(65.0));
    // From inside the block, heading out through the south wall.
    const glm::dvec3 inside{30.0, 50.0, 12.0};
    CHECK_FALSE(intersectSolidBase(g, floor, Ray{inside, {0.0, -1.0, 0.0}}, kInfinity));
    // The east wall from the east, under the profile's 30 m top.
    const auto east = intersectSolidBase(g, floor, Ray{{200.0, 50.0, 25.0}, {-1.0, 0.0, 0.0}}, kInfinity);
    REQUIRE(east);
    CHECK(east->t == Approx(100.0));
    CHECK(east->normal == glm::dvec3(1.0, 0.0, 0.0));
}

namespace {

// A flat slab 50 m high, seen level from the south at 40 m: the south wall fills the rows between the floor
// and the slab's top, the backdrop the rest.
TerrainRenderSettings levelView(bool base) {
    TerrainRenderSettings s;
    s.width = 60;
    s.height = 60;
    s.threads = 2;
    s.camera.eyeM = {50.0, -200.0, 40.0};
    s.camera.lookAtM = {50.0, 0.0, 40.0};
    s.camera.fovYDeg = 20.0;
    s.sky.kind = SkyKind::Flat;
    s.sky.samples = 0;
    s.sun = Sun{180.0, 30.0};  // from the south: the wall faces it
    s.look.solidBase = base;
    s.look.backdrop = Backdrop::Neutral;
    return s;
}

}  // namespace

TEST_CASE("A rendered slab stands on its base: the wall fills the rows from the floor to the top edge",
          "[tracer][base]") {
    const HeightGrid g(11, 11, 10.0, 10.0, std::vector<float>(121, 50.0f));
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    const double floor = solidBaseFloorM(g);  // 50 - max(0, 1) = 49 m
    CHECK(floor == Approx(49.0));
    // A deeper base to see: the north-east corner vertex at 0 m makes the relief 50 m (and it lies out of the
    // sight of the middle column, which looks along x = 50 m).
    std::vector<float> z(121, 50.0f);
    z[120] = 0.0f;
    const HeightGrid slab(11, 11, 10.0, 10.0, z);
    const TerrainSurface slabSurface(slab, SurfaceMethod::Bilinear);
    const double slabFloor = solidBaseFloorM(slab);  // 0 - 5 = -5 m
    CHECK(slabFloor == Approx(-5.0));
    const Film with = renderTerrain(slab, slabSurface, levelView(true));
    const Film without = renderTerrain(slab, slabSurface, levelView(false));
    // Row of height z on the wall at distance 200 m: tan of its angle over tan(10 degrees), on 60 rows.
    const double tanHalf = std::tan(10.0 * 3.14159265358979 / 180.0);
    const auto rowOf = [&](double z) { return (1.0 - (z - 40.0) / 200.0 / tanHalf) * 30.0; };
    const glm::vec3 backdrop = TerrainShader(slab, slabSurface, levelView(true).sun, levelView(true).sky, 40.0, 0,
                                             true, levelView(true).look)
                                   .miss(glm::dvec3(0.0, 1.0, 0.0));
    int wallRows = 0;
    for (int y = 0; y < 60; ++y) {
        const double centre = y + 0.5;
        const bool onWall = centre > rowOf(50.0) + 0.5 && centre < rowOf(-5.0) - 0.5;
        const bool offWall = centre < rowOf(50.0) - 0.5 || centre > rowOf(-5.0) + 0.5;
        const glm::vec3 a = with.get(30, y), b = without.get(30, y);
        INFO("row " << y);
        if (onWall) {
            ++wallRows;
            // The base's albedo under the sun at 30 degrees on a south-facing wall, plus sky light, where the
            // same ray without a base shows the backdrop or the slab's underside.
            CHECK(std::abs(a.r / a.b - kSolidBaseAlbedo.r / kSolidBaseAlbedo.b) < 0.25f);
            CHECK(std::abs(a.r - backdrop.r) > 0.05f);
            CHECK(glm::length(a - b) > 0.02f);
        } else if (offWall) {
            CHECK(a == b);
        }
    }
    // From row 30 (1 - 10 / 35.27) = 21.5 down past the bottom of the picture (the floor's row is 68.3).
    CHECK(wallRows >= 36);
}

TEST_CASE("Backdrops: neutral grey, the sky's horizon colour below the horizon, or the Earth's ground",
          "[tracer][base]") {
    const HeightGrid g(3, 3, 10.0, 10.0, std::vector<float>(9, 0.0f));
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    SkyDescription sky;  // physical
    const Sun sun{135.0, 25.0};
    TerrainLook look;
    const glm::dvec3 down = glm::normalize(glm::dvec3(0.3, 0.8, -0.5)), level = glm::normalize(glm::dvec3(0.3, 0.8, 0.0));
    const glm::dvec3 up = glm::normalize(glm::dvec3(0.3, 0.8, 0.4));
    look.backdrop = Backdrop::Ground;
    const TerrainShader ground(g, surface, sun, sky, 100.0, 0, true, look);
    look.backdrop = Backdrop::Sky;
    const TerrainShader skyOnly(g, surface, sun, sky, 100.0, 0, true, look);
    look.backdrop = Backdrop::Neutral;
    const TerrainShader neutral(g, surface, sun, sky, 100.0, 0, true, look);
    // Above the horizon, the sky and ground backdrops are the sky model.
    CHECK(skyOnly.miss(up) == ground.miss(up));
    // Below it, the ground backdrop shows the Earth's grey ground, the sky backdrop the horizon's colour.
    CHECK(skyOnly.miss(down) == ground.miss(level));
    CHECK(glm::length(ground.miss(down) - ground.miss(level)) > 0.01f);
    // Neutral: grey, 0.6 at the horizon and above, darkening downward to 0.3 straight down.
    CHECK(neutral.miss(up) == glm::vec3(0.6f));
    CHECK(neutral.miss(down).r == Approx(0.6 - 0.3 * 0.5 / std::sqrt(0.09 + 0.64 + 0.25)).epsilon(1e-6));
    CHECK(neutral.miss({0.0, 0.0, -1.0}) == glm::vec3(0.3f));
}
