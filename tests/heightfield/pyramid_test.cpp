// The maximum pyramid: its levels bound the cells, and traversal through it returns exactly the hits of the
// flat DDA walk.
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

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
        } else if (k % 3 == 1) {  // nearly horizontal, across the whole grid
            d = {std::cos(az), std::sin(az), 0.02 * (U(rng) - 0.5)};
            o = {g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + (g.maxHeightM() - g.minHeightM()) * U(rng)};
        } else {  // upward, from inside the box
            d = glm::normalize(glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng)));
            o = {g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + (g.maxHeightM() - g.minHeightM()) * U(rng)};
        }
        const Ray ray{o, d};
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
            // Without counters, as the renderers trace; the counters (which widen the skip margin) only count.
            const auto a = intersect(g, ray, {0, kInfinity}, m, nullptr, Traversal::Pyramid);
            const auto b = intersect(g, ray, {0, kInfinity}, m, nullptr, Traversal::Flat);
            TraceCounters counters;
            const auto c = intersect(g, ray, {0, kInfinity}, m, &counters, Traversal::Pyramid);
            skipped += counters.blocksSkipped;
            REQUIRE(c.has_value() == b.has_value());
            if (c) REQUIRE(c->t == b->t);
            INFO("ray " << k << " method " << cellMethodName(m));
            REQUIRE(a.has_value() == b.has_value());
            if (a) {
                ++hits;
                REQUIRE(a->t == b->t);
                REQUIRE(a->cellX == b->cellX);
                REQUIRE(a->cellY == b->cellY);
                // The cell is entered through the same side, so a wall hit of `nearest` has the same normal.
                REQUIRE(a->normal == b->normal);
            }
            REQUIRE(occluded(g, ray, {0, kInfinity}, m, nullptr, Traversal::Pyramid) ==
                    occluded(g, ray, {0, kInfinity}, m, nullptr, Traversal::Flat));
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
}

TEST_CASE("Pyramid traversal gives exactly the flat walk's hits on real DEMs", "[heightfield][pyramid]") {
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
