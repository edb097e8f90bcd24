// A surface under a level of detail: a level that never takes over changes no hit; rays wholly in a coarser
// level's range hit where that coarser grid, traced on its own, is hit; a ray that passes onto a coarser level
// under its surface meets it there; occlusion rays are traced on the level where they start.
#include "heightfield/coarser_grid.h"
#include "heightfield/fractal_terrain.h"
#include "heightfield/shading_normals.h"
#include "heightfield/traversal.h"
#include "support/cut_tiles.h"
#include "tracer/terrain/surface.h"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <random>
#include <vector>

using namespace terracast;
using terracast::testing::CutTiles;

namespace {

// Rays from `eye` towards random points of the grid's area (a little beyond it too).
std::vector<Ray> raysAt(const HeightGrid& g, const glm::dvec3& eye, int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> ux(-0.05 * g.extentXM(), 1.05 * g.extentXM()),
        uy(-0.05 * g.extentYM(), 1.05 * g.extentYM()), uz(g.minHeightM(), g.maxHeightM());
    std::vector<Ray> rays;
    for (int k = 0; k < n; ++k) rays.push_back(Ray{eye, glm::normalize(glm::dvec3(ux(rng), uy(rng), uz(rng)) - eye)});
    return rays;
}

bool sameHit(const std::optional<HeightFieldHit>& a, const std::optional<HeightFieldHit>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || (std::bit_cast<uint64_t>(a->t) == std::bit_cast<uint64_t>(b->t) && a->cellX == b->cellX &&
                  a->cellY == b->cellY);
}

}  // namespace

TEST_CASE("Level of detail: a level that never takes over changes no hit, bundle or not", "[terrain][lod]") {
    FractalTerrainOptions o;
    o.size = 129;
    const HeightGrid g = fractalTerrain(o);
    const glm::dvec3 eye{-800.0, -600.0, 2500.0};
    const TerrainSurface exact(g, SurfaceMethod::Bilinear);
    TerrainSurface lod(g, SurfaceMethod::Bilinear);
    // Cells span one pixel only beyond 1000 km: the coarse levels exist but nothing reaches them.
    lod.setLevelOfDetail({eye, 30.0 / 1e6, 1.0});
    REQUIRE(lod.detailLevels() >= 6);
    CHECK(lod.detailDistancesM().front() == Approx(1e6));
    const std::vector<Ray> rays = raysAt(g, eye, 2000, 7);
    int differ = 0, hits = 0, single = 0, bundled = 0, occ = 0;
    std::vector<std::optional<HeightFieldHit>> bundle(rays.size()), exactBundle(rays.size());
    lod.intersectBundle(rays, {0.0, kInfinity}, bundle);
    exact.intersectBundle(rays, {0.0, kInfinity}, exactBundle);
    for (size_t k = 0; k < rays.size(); ++k) {
        const auto e = exact.intersect(rays[k], {0.0, kInfinity});
        hits += e.has_value();
        single += !sameHit(lod.intersect(rays[k], {0.0, kInfinity}), e);
        bundled += !sameHit(bundle[k], exactBundle[k]);
        occ += lod.occluded(rays[k], {0.0, kInfinity}) != exact.occluded(rays[k], {0.0, kInfinity});
    }
    differ = single + bundled + occ;
    INFO(single << " single, " << bundled << " bundled, " << occ << " occlusion");
    CHECK(hits > 1000);
    CHECK(differ == 0);
}

TEST_CASE("Level of detail: rays wholly in a coarser level's range hit that grid as traced on its own",
          "[terrain][lod]") {
    FractalTerrainOptions o;
    o.size = 257;
    const HeightGrid g = fractalTerrain(o);  // 7.68 km a side
    // From 40 km away every point of the grid lies between 36 and 48 km from the eye: with level k taking over at
    // 2^(k-1) * 30 m / (radians per pixel * pixels), a pixel angle that puts level 2's start at 30 km and level 3's
    // at 60 km gives level 2 to all of it.
    const glm::dvec3 eye{3840.0 - 40000.0 * std::cos(0.3), 3840.0 - 40000.0 * std::sin(0.3), 9000.0};
    const double anglePixels = 60.0 / 30000.0;
    TerrainSurface lod(g, SurfaceMethod::Bilinear);
    lod.setLevelOfDetail({eye, anglePixels, 1.0});
    REQUIRE(lod.detailDistancesM().size() >= 3);
    CHECK(lod.detailDistancesM()[1] == Approx(30000.0));
    CHECK(lod.detailDistancesM()[2] == Approx(60000.0));
    const HeightGrid level2 = coarserGrid(coarserGrid(g));
    const std::vector<Ray> rays = raysAt(g, eye, 3000, 11);
    int hits = 0, differ = 0, occlusion = 0, shadowed = 0;
    std::vector<std::optional<HeightFieldHit>> bundle(rays.size());
    lod.intersectBundle(rays, {0.0, kInfinity}, bundle);
    for (size_t k = 0; k < rays.size(); ++k) {
        const auto want = intersect(level2, rays[k], {0.0, kInfinity}, CellMethod::Bilinear);
        const auto got = lod.intersect(rays[k], {0.0, kInfinity});
        hits += want.has_value();
        for (const auto& h : {got, bundle[k]}) {
            differ += h.has_value() != want.has_value();
            if (h && want) {
                differ += std::bit_cast<uint64_t>(h->t) != std::bit_cast<uint64_t>(want->t);
                // Located in the fine grid's cells.
                differ += h->cellX != std::min<int64_t>(int64_t(h->pointM.x / 30.0), g.cellsX() - 1);
                differ += h->cellY != std::min<int64_t>(int64_t(h->pointM.y / 30.0), g.cellsY() - 1);
            }
        }
        // An occlusion ray from that hit, on the level where it starts: level 2's.
        if (want) {
            const Ray up{want->pointM + glm::dvec3(0.0, 0.0, 0.01), glm::normalize(glm::dvec3(0.3, 0.4, 0.25 + 0.001 * double(k % 50)))};
            occlusion += lod.occluded(up, {0.0, kInfinity}) != occluded(level2, up, {0.0, kInfinity}, CellMethod::Bilinear);
            shadowed += occluded(level2, up, {0.0, kInfinity}, CellMethod::Bilinear);
        }
    }
    CHECK(shadowed > 100);
    CHECK(hits > 1500);
    CHECK(differ == 0);
    CHECK(occlusion == 0);
    // The fine grid's own hits are not those: the level of detail did take over.
    int fineDiffer = 0;
    for (const Ray& r : rays) fineDiffer += !sameHit(intersect(g, r, {0.0, kInfinity}, CellMethod::Bilinear),
                                                     intersect(level2, r, {0.0, kInfinity}, CellMethod::Bilinear));
    CHECK(fineDiffer > 500);
}

TEST_CASE("Level of detail: a ray that passes onto a coarser level under its surface meets it there",
          "[terrain][lod]") {
    // Ridges of 100 m on even columns, valleys of 0 m on odd ones: the coarse grid keeps only the ridges (100 m
    // everywhere). A level ray at 50 m along an odd column's valley floor meets nothing on the fine grid, and
    // enters the coarse level's range under its surface.
    const int64_t n = 65;
    std::vector<float> z(size_t(n * n));
    for (int64_t j = 0; j < n; ++j)
        for (int64_t i = 0; i < n; ++i) z[size_t(j * n + i)] = i % 2 == 0 ? 100.0f : 0.0f;
    const HeightGrid g(n, n, 10.0, 10.0, std::move(z));
    const Ray ray{{330.0, -50.0, 50.0}, {0.0, 1.0, 0.0}};
    REQUIRE_FALSE(intersect(g, ray, {0.0, kInfinity}, CellMethod::Bilinear));
    TerrainSurface lod(g, SurfaceMethod::Bilinear);
    // Level 1 from 300 m from the eye (the ray's origin) on.
    lod.setLevelOfDetail({ray.origin, 10.0 / 300.0, 1.0});
    REQUIRE(lod.detailDistancesM().front() == Approx(300.0));
    const auto hit = lod.intersect(ray, {0.0, kInfinity});
    REQUIRE(hit);
    CHECK(hit->t == Approx(300.0));
    CHECK(hit->pointM.z == Approx(100.0));
    CHECK(hit->normal.z == Approx(1.0));
    CHECK(hit->cellY == 25);
    // Occlusion rays are traced whole on the level where they start: a ray descending along the valley misses
    // the fine grid (it would reach 0 m past its far edge) and meets the coarse one's 100 m.
    const glm::dvec3 down = glm::normalize(glm::dvec3(0.0, 1.0, -0.2));
    const Ray nearRay{{330.0, 0.0, 150.0}, down}, farRay{{330.0, 350.0, 150.0}, down};
    REQUIRE_FALSE(occluded(g, nearRay, {0.0, kInfinity}, CellMethod::Bilinear));
    REQUIRE_FALSE(occluded(g, farRay, {0.0, kInfinity}, CellMethod::Bilinear));
    CHECK_FALSE(lod.occluded(nearRay, {0.0, kInfinity}));  // starts 112 m from the eye: the fine grid
    CHECK(lod.occluded(farRay, {0.0, kInfinity}));         // starts 412 m from the eye: level 1
}

TEST_CASE("Level of detail over a grid held as tiles: the levels that fit its cache, the tiles nearer",
          "[terrain][lod][tiles]") {
    FractalTerrainOptions o;
    o.size = 1025;  // 30 m cells, 30.7 km a side: 4 x 4 tiles
    const HeightGrid whole = fractalTerrain(o);
    const glm::dvec3 eye{-3000.0, -2000.0, 4000.0};
    // Level k takes over at 2^(k-1) * 30 m / (radians per pixel): level 1 from 3 km, level 2 from 6 km, level 3
    // from 12 km.
    const double anglePixels = 30.0 / 3000.0;
    TerrainSurface wholeLod(whole, SurfaceMethod::Bilinear);
    wholeLod.setLevelOfDetail({eye, anglePixels, 1.0});
    REQUIRE(wholeLod.firstDetailLevel() == 1);
    const std::vector<Ray> rays = raysAt(whole, eye, 3000, 17);

    SECTION("a cache that holds every coarser grid: the whole grid's levels, hit for hit") {
        auto tiles = std::make_shared<CutTiles>(whole, size_t(64) << 20);
        const HeightGrid tiled(tiles->summary(), 30.0, 30.0, tiles);
        TerrainSurface lod(tiled, SurfaceMethod::Bilinear, 2);
        lod.setLevelOfDetail({eye, anglePixels, 1.0});
        CHECK(lod.firstDetailLevel() == 1);
        CHECK(lod.detailDistancesM() == wholeLod.detailDistancesM());
        int differ = 0, hits = 0;
        for (const Ray& r : rays) {
            const auto want = wholeLod.intersect(r, {0.0, kInfinity});
            hits += want.has_value();
            differ += !sameHit(lod.intersect(r, {0.0, kInfinity}), want);
            if (want) differ += lod.smoothNormalAt(*want) != wholeLod.smoothNormalAt(*want);
        }
        CHECK(hits > 1500);
        CHECK(differ == 0);
    }
    SECTION("a cache of a few tiles: the first coarse level that fits, from where it takes over") {
        // The budget of level 3's grid and those above: 129 x 129 vertices.
        const size_t budget = size_t(4.0 / 3.0 * coarseGridBytes(129, 129)) + 1024;
        auto tiles = std::make_shared<CutTiles>(whole, budget);
        const HeightGrid tiled(tiles->summary(), 30.0, 30.0, tiles);
        TerrainSurface lod(tiled, SurfaceMethod::Bilinear, 2);
        lod.setLevelOfDetail({eye, anglePixels, 1.0});
        CHECK(lod.firstDetailLevel() == 3);
        REQUIRE(lod.detailDistancesM().size() >= 2);
        // Level 3 from where level 2 would have ended: 12 km.
        CHECK(lod.detailDistancesM()[0] == Approx(12000.0));
        CHECK(lod.detailDistancesM()[1] == Approx(24000.0));
        CHECK(lod.detailBytes() <= budget);
        const TerrainSurface exact(whole, SurfaceMethod::Bilinear);
        const HeightGrid level3 = coarserGrid(coarserGrid(coarserGrid(whole)));
        // Rays that end before 12 km hit the grid itself; a stretch of a ray wholly between 12 and 24 km meets
        // level 3's surface as it is traced on its own.
        int near = 0, nearDiffer = 0, mid = 0, midDiffer = 0;
        for (const Ray& r : rays) {
            const auto e = exact.intersect(r, {0.0, kInfinity});
            if (e && e->t < 11000.0) {
                ++near;
                nearDiffer += !sameHit(lod.intersect(r, {0.0, 11000.0}), exact.intersect(r, {0.0, 11000.0}));
                nearDiffer += lod.smoothNormalAt(*e) != smoothNormal(whole, e->cellX, e->cellY, e->u, e->v);
            }
            const auto m = intersect(level3, r, {12100.0, 23900.0}, CellMethod::Bilinear);
            if (m) {
                ++mid;
                const auto got = lod.intersect(r, {12100.0, 23900.0});
                midDiffer += !got || std::bit_cast<uint64_t>(got->t) != std::bit_cast<uint64_t>(m->t);
                // Shaded with level 3's smooth normal there, not read from the grid's tiles.
                if (got) {
                    const double x = got->pointM.x * level3.cellsPerMetreX(), y = got->pointM.y * level3.cellsPerMetreY();
                    const int64_t i = std::min<int64_t>(int64_t(x), level3.cellsX() - 1),
                                  j = std::min<int64_t>(int64_t(y), level3.cellsY() - 1);
                    midDiffer += lod.smoothNormalAt(*got) != smoothNormal(level3, i, j, x - double(i), y - double(j));
                }
            }
        }
        INFO(near << " near hits, " << mid << " hits between 12 and 24 km");
        CHECK(near > 50);
        CHECK(mid > 200);
        CHECK(nearDiffer == 0);
        CHECK(midDiffer == 0);
    }
}

TEST_CASE("Level of detail: a grid too thin for a coarser level gets none, held whole or as tiles",
          "[terrain][lod][tiles]") {
    const HeightGrid thin(2, 300, 10.0, 10.0, std::vector<float>(600, 5.0f));
    auto tiles = std::make_shared<CutTiles>(thin, size_t(1) << 20);
    const HeightGrid thinTiled(tiles->summary(), 10.0, 10.0, tiles);
    for (const HeightGrid* g : {&thin, &thinTiled}) {
        TerrainSurface lod(*g, SurfaceMethod::Bilinear);
        lod.setLevelOfDetail({{5.0, -100.0, 50.0}, 1e-3, 1.0});
        CHECK(lod.detailLevels() == 0);
        const Ray r{{5.0, -100.0, 50.0}, glm::normalize(glm::dvec3(0.0, 1.0, -0.2))};
        CHECK(sameHit(lod.intersect(r, {0.0, kInfinity}), intersect(*g, r, {0.0, kInfinity}, CellMethod::Bilinear)));
    }
}
