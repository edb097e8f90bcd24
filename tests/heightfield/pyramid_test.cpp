// The maximum and minimum pyramids: their levels bound the cells, and traversal through them returns exactly
// the hits of the flat DDA walk.
#include "heightfield/fractal_terrain.h"
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

struct HitPair {
    std::optional<HeightFieldHit> pyramid, flat;
};

// Requires the pyramid walk to find the flat walk's nearest hit of `ray` (same t, cell and normal: the cell is
// entered through the same side, so a wall hit of `nearest` has the same normal) and its occlusion verdict.
HitPair requirePyramidAsFlat(const HeightGrid& g, const Ray& ray, CellMethod m) {
    HitPair h{intersect(g, ray, {0, kInfinity}, m, nullptr, Traversal::Pyramid),
              intersect(g, ray, {0, kInfinity}, m, nullptr, Traversal::Flat)};
    REQUIRE(h.pyramid.has_value() == h.flat.has_value());
    if (h.pyramid) {
        REQUIRE(h.pyramid->t == h.flat->t);
        REQUIRE(h.pyramid->cellX == h.flat->cellX);
        REQUIRE(h.pyramid->cellY == h.flat->cellY);
        REQUIRE(h.pyramid->normal == h.flat->normal);
    }
    REQUIRE(occluded(g, ray, {0, kInfinity}, m, nullptr, Traversal::Pyramid) ==
            occluded(g, ray, {0, kInfinity}, m, nullptr, Traversal::Flat));
    return h;
}

// Checks pyramid against flat traversal on `n` seeded rays of mixed kinds.
void requireSameHits(const HeightGrid& g, int n, uint64_t seed, bool expectSkips = false) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    int64_t skipped = 0, hits = 0;
    for (int k = 0; k < n; ++k) {
        glm::dvec3 o, d;
        const double az = 2.0 * M_PI * U(rng);
        if (k % 3 == 0) {  // from above, steep to shallow
            const double el = (1.0 + 88.0 * U(rng)) * M_PI / 180.0;
            d = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el)};
            o = glm::dvec3(g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM()) -
                ((g.maxHeightM() - g.minHeightM() + 50.0) / std::sin(el)) * d;
        } else if (k % 3 == 1) {  // nearly horizontal, across the whole grid; every other one exactly horizontal
            const double dz = 0.02 * (U(rng) - 0.5);
            d = {std::cos(az), std::sin(az), k % 6 == 1 ? 0.0 : dz};
            o = {g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + (g.maxHeightM() - g.minHeightM()) * U(rng)};
        } else {  // upward, from inside the box
            d = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng)));
            o = {g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + (g.maxHeightM() - g.minHeightM()) * U(rng)};
        }
        const Ray ray{o, d};
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
            // Without counters, as the renderers trace; the counters (which widen the skip margin) only count.
            const auto b = intersect(g, ray, {0, kInfinity}, m, nullptr, Traversal::Flat);
            TraceCounters counters;
            const auto c = intersect(g, ray, {0, kInfinity}, m, &counters, Traversal::Pyramid);
            skipped += counters.blocksSkipped;
            REQUIRE(c.has_value() == b.has_value());
            if (c) REQUIRE(c->t == b->t);
            INFO("ray " << k << " method " << cellMethodName(m));
            hits += requirePyramidAsFlat(g, ray, m).pyramid.has_value();
        }
    }
    CHECK(hits > n / 2);
    if (expectSkips) CHECK(skipped > n);  // on real terrain the pyramid does skip
}

LoadedDem sample(const std::string& name, DemLoadOptions o = {}) {
    return loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name, o);
}

}  // namespace

TEST_CASE("Pyramid levels bound every cell's valid heights", "[heightfield][pyramid]") {
    const HeightGrid g = randomGrid(37, 23, 10.0, 10.0, -50.0f, 900.0f, 3);
    REQUIRE(g.pyramidLevels() >= 5);
    CHECK(g.pyramidBlocksX(g.pyramidLevels()) == 1);
    CHECK(g.pyramidBlocksY(g.pyramidLevels()) == 1);
    // Float heights: the int16 pyramid rounds up, by less than a 65000th of the height range.
    REQUIRE(g.storage() == HeightStorage::Float32);
    const double step = (double(g.maxHeightM()) - g.minHeightM()) / 65000.0;
    CHECK(g.blockMaxM(g.pyramidLevels(), 0, 0) >= g.maxHeightM());
    CHECK(g.blockMaxM(g.pyramidLevels(), 0, 0) <= g.maxHeightM() + step);
    for (int k = 1; k <= g.pyramidLevels(); ++k)
        for (int64_t j = 0; j < g.cellsY(); ++j)
            for (int64_t i = 0; i < g.cellsX(); ++i) {
                const float m = std::max({g.at(i, j), g.at(i + 1, j), g.at(i, j + 1), g.at(i + 1, j + 1)});
                REQUIRE(g.blockMaxM(k, i >> k, j >> k) >= m);
            }
    // Nearly tight at level 1: the block's max is one of its vertices, rounded up to the next code.
    const float m = std::max({g.at(0, 0), g.at(1, 0), g.at(2, 0), g.at(0, 1), g.at(1, 1), g.at(2, 1), g.at(0, 2),
                              g.at(1, 2), g.at(2, 2)});
    CHECK(g.blockMaxM(1, 0, 0) >= m);
    CHECK(g.blockMaxM(1, 0, 0) <= m + step);

    // The minimum pyramid, from level 2: below every cell it covers, and nearly tight.
    CHECK(g.blockMinM(g.pyramidLevels(), 0, 0) <= g.minHeightM());
    CHECK(g.blockMinM(g.pyramidLevels(), 0, 0) >= g.minHeightM() - step);
    for (int k = 2; k <= g.pyramidLevels(); ++k)
        for (int64_t j = 0; j < g.cellsY(); ++j)
            for (int64_t i = 0; i < g.cellsX(); ++i) {
                const float lo = std::min({g.at(i, j), g.at(i + 1, j), g.at(i, j + 1), g.at(i + 1, j + 1)});
                REQUIRE(g.blockMinM(k, i >> k, j >> k) <= lo);
            }
    float lo = INFINITY;
    for (int64_t j = 0; j <= 4; ++j)
        for (int64_t i = 0; i <= 4; ++i) lo = std::min(lo, g.at(i, j));
    CHECK(g.blockMinM(2, 0, 0) >= lo - step);
}

TEST_CASE("Pyramid traversal gives exactly the flat walk's hits on real DEMs", "[heightfield][pyramid][heavy]") {
    requireSameHits(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif").grid, 20000, 1, true);
    requireSameHits(sample("srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif").grid, 20000, 2, true);
    DemLoadOptions png;
    png.imageCellSizeM = 160.0;
    png.imageHeightScale = 0.1;
    requireSameHits(sample("puget-sound-usgs-1025x1025-16bit-heightmap.png", png).grid, 20000, 3, true);
    requireSameHits(sample("landfire-storm-lake-mt-utm12n-int16-small-nodata.tif").grid, 20000, 4, true);
    requireSameHits(sample("N44W072.srtm3-white-mountains-nh.hgt").grid, 20000, 5, true);
}

TEST_CASE("Pyramid traversal gives exactly the flat walk's hits at the extremes", "[heightfield][pyramid]") {
    // Flat, planar, strongly twisted, tall with tiny relief, thin strips, and a grid with nodata holes.
    uint64_t seed = 6;
    for (const HeightGrid& g : extremeGrids()) requireSameHits(g, 3000, seed++);
}

// Rays that enter the grid through one of its sides below the surface there (as the lowest rays of a camera
// beside the grid do) run under the terrain, where only the minimum pyramid can skip anything. They must find
// exactly the flat walk's hits (those rising come up through the surface from below) while visiting a
// fraction of its cells.
TEST_CASE("Rays under the surface skip blocks of the minimum pyramid and keep the flat walk's hits",
          "[heightfield][pyramid]") {
    std::vector<HeightGrid> grids;
    grids.push_back(sample("N44W072.srtm3-white-mountains-nh.hgt").grid);
    grids.push_back(sample("usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif").grid);
    FractalTerrainOptions fractal;
    fractal.size = 257;
    fractal.seed = 41;
    grids.push_back(fractalTerrain(fractal));
    const size_t terrains = grids.size();  // real and fractal terrain, then the extremes
    for (HeightGrid& g : extremeGrids()) grids.push_back(std::move(g));
    uint64_t seed = 40;
    for (size_t n = 0; n < grids.size(); ++n) {
        const HeightGrid& g = grids[n];
        INFO("grid " << g.width() << " x " << g.height() << ", seed " << seed);
        std::mt19937_64 rng(seed++);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        const double relief = std::max(1.0, double(g.maxHeightM()) - g.minHeightM());
        int64_t hits = 0, rays = 0, pyramidCells = 0, flatCells = 0;
        for (int k = 0; k < 2000; ++k) {
            // A point on one of the four sides, under the edge's surface by up to a third of the relief.
            const int side = k % 4;
            const double f = U(rng);
            glm::dvec3 p;
            glm::dvec2 inward;
            double edgeZ = 0.0;
            auto lerpEdge = [&](int64_t i0, int64_t j0, int64_t i1, int64_t j1, double w) {
                return (1.0 - w) * g.at(i0, j0) + w * g.at(i1, j1);
            };
            if (side < 2) {
                const double y = f * double(g.cellsY());
                const auto j = std::min(int64_t(y), g.cellsY() - 1);
                const int64_t i = side == 0 ? 0 : g.cellsX();
                edgeZ = lerpEdge(i, j, i, j + 1, y - double(j));
                p = {double(i) * g.cellSizeXM(), y * g.cellSizeYM(), 0.0};
                inward = {side == 0 ? 1.0 : -1.0, 0.0};
            } else {
                const double x = f * double(g.cellsX());
                const auto i = std::min(int64_t(x), g.cellsX() - 1);
                const int64_t j = side == 2 ? 0 : g.cellsY();
                edgeZ = lerpEdge(i, j, i + 1, j, x - double(i));
                p = {x * g.cellSizeXM(), double(j) * g.cellSizeYM(), 0.0};
                inward = {0.0, side == 2 ? 1.0 : -1.0};
            }
            p.z = edgeZ - (0.001 + U(rng) / 3.0) * relief;
            // Into the grid within 60 degrees of the side's normal, from 20 degrees down to 10 up.
            const double az = std::atan2(inward.y, inward.x) + (U(rng) - 0.5) * (2.0 * M_PI / 3.0);
            const double el = (-20.0 + 30.0 * U(rng)) * M_PI / 180.0;
            const glm::dvec3 d{std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)};
            const Ray ray{p - 50.0 * d, d};
            for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
                INFO("ray " << k << " method " << cellMethodName(m));
                // Occlusion treats the terrain as solid (no minimum pyramid there); both walks must still agree.
                const HitPair h = requirePyramidAsFlat(g, ray, m);
                if (h.pyramid) {
                    ++hits;
                    REQUIRE(h.pyramid->u == h.flat->u);
                    REQUIRE(h.pyramid->v == h.flat->v);
                }
                TraceCounters pc, fc;
                (void)intersect(g, ray, {0, kInfinity}, m, &pc, Traversal::Pyramid);
                (void)intersect(g, ray, {0, kInfinity}, m, &fc, Traversal::Flat);
                pyramidCells += pc.cellsVisited;
                flatCells += fc.cellsVisited;
                ++rays;
            }
        }
        // On terrain some rays come up through the surface, and the walk under it visits a small share of the
        // flat walk's cells. (The extremes' blocks mostly reach down to their grid's lowest height.)
        if (n < terrains) {
            CHECK(hits > rays / 20);
            CHECK(pyramidCells * 8 < flatCells);
        }
    }
}
