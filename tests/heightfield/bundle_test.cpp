// Bundles of rays from one origin (a camera's tile of pixels): intersectBundle returns exactly the hits of
// tracing each ray on its own, and the free stretch it proves for the bundle spares work.
#include "heightfield/fractal_terrain.h"
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <optional>
#include <random>
#include <vector>

using namespace terracast;
using namespace terracast::testing;

namespace {

constexpr int kSide = 8;  // rays per bundle side

struct Work {
    TraceCounters single;  // summed over the rays traced one by one
    TraceCounters bundle;  // summed over the same rays traced as bundles
    int64_t rays = 0;
    int64_t hits = 0;
    int64_t ambiguous = 0;  // bundles with a ray flagged ambiguous
};

// An 8 x 8 fan of unit directions around `centre`, `spreadDeg` across (a tile of a pinhole camera's pixels).
std::array<Ray, kSide * kSide> fan(const glm::dvec3& origin, const glm::dvec3& centre, double spreadDeg) {
    const glm::dvec3 f = glm::normalize(centre);
    const glm::dvec3 side = std::abs(f.z) < 0.999 ? glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1)))
                                                   : glm::dvec3(1, 0, 0);
    const glm::dvec3 up = glm::cross(side, f);
    const double half = std::tan(0.5 * spreadDeg * M_PI / 180.0);
    std::array<Ray, kSide * kSide> rays;
    for (int y = 0; y < kSide; ++y)
        for (int x = 0; x < kSide; ++x) {
            const double sx = half * (2.0 * (x + 0.5) / kSide - 1.0), sy = half * (2.0 * (y + 0.5) / kSide - 1.0);
            rays[size_t(y * kSide + x)] = Ray{origin, glm::normalize(f + sx * side + sy * up)};
        }
    return rays;
}

// Traces `rays` as one bundle (with and without counters) and one by one, with every direct method, and
// requires the same hit, bit for bit, from all of them.
void requireSameAsSingle(const HeightGrid& g, std::span<const Ray> rays, Interval interval, Work& work) {
    std::vector<std::optional<HeightFieldHit>> bundle(rays.size()), counted(rays.size());
    for (CellMethod m : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Triangles, CellMethod::Nearest,
                         CellMethod::Reference}) {
        intersectBundle(g, rays, interval, m, bundle);
        TraceCounters bundleCounters;
        intersectBundle(g, rays, interval, m, counted, &bundleCounters);
        bool anyAmbiguous = false;
        for (size_t k = 0; k < rays.size(); ++k) {
            TraceCounters singleCounters;
            const auto single = intersect(g, rays[k], interval, m);
            const auto singleCounted = intersect(g, rays[k], interval, m, &singleCounters);
            anyAmbiguous = anyAmbiguous || singleCounters.ambiguous;
            if (m == CellMethod::Bilinear) {
                work.single.blocksSkipped += singleCounters.blocksSkipped;
                work.single.cellsVisited += singleCounters.cellsVisited;
                ++work.rays;
                work.hits += single.has_value();
            }
            INFO("ray " << k << " of the bundle, method " << cellMethodName(m));
            REQUIRE(bundle[k].has_value() == single.has_value());
            REQUIRE(counted[k].has_value() == singleCounted.has_value());
            if (single) {
                REQUIRE(bundle[k]->t == single->t);
                REQUIRE(bundle[k]->cellX == single->cellX);
                REQUIRE(bundle[k]->cellY == single->cellY);
                REQUIRE(bundle[k]->u == single->u);
                REQUIRE(bundle[k]->v == single->v);
                REQUIRE(bundle[k]->normal == single->normal);
                REQUIRE(counted[k]->t == singleCounted->t);
            }
        }
        // A graze the single rays flag lies outside the proved stretch, so the bundle flags it too.
        REQUIRE(bundleCounters.ambiguous == anyAmbiguous);
        if (m == CellMethod::Bilinear) {
            work.ambiguous += anyAmbiguous;
            work.bundle.blocksSkipped += bundleCounters.blocksSkipped;
            work.bundle.cellsVisited += bundleCounters.cellsVisited;
        }
    }
}

// Bundles from seeded cameras of six kinds over `g`: high above looking down at any pitch, outside an edge
// looking in, grazing just above the highest point (some rays rising), far away (1000 grid widths) looking
// along the surface, inside the relief (some bundles starting below the surface), and a million metres up
// looking straight down through a tiny cone.
Work requireSameBundleHits(const HeightGrid& g, int bundles, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double relief = double(g.maxHeightM()) - g.minHeightM();
    const double ex = g.extentXM(), ey = g.extentYM(), span = std::max(ex, ey);
    // The highest valid vertex, for cameras that graze it.
    glm::dvec2 peak{0.0};
    for (int64_t j = 0; j < g.height(); ++j)
        for (int64_t i = 0; i < g.width(); ++i)
            if (g.vertexValid(i, j) && g.at(i, j) == g.maxHeightM())
                peak = {double(i) * g.cellSizeXM(), double(j) * g.cellSizeYM()};
    Work work;
    for (int b = 0; b < bundles; ++b) {
        const double az = 2.0 * M_PI * U(rng);
        const glm::dvec3 inside{ex * U(rng), ey * U(rng), g.minHeightM() + relief * U(rng)};
        glm::dvec3 origin, centre;
        double spread = 0.2 + 3.0 * U(rng);
        switch (b % 6) {
        case 0: {  // above, looking down
            const double el = (5.0 + 84.0 * U(rng)) * M_PI / 180.0;
            origin = {inside.x, inside.y, g.maxHeightM() + (0.05 + U(rng)) * (relief + 50.0)};
            centre = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el)};
            break;
        }
        case 1: {  // outside, looking at a point of the grid
            origin = {ex * 0.5 - span * std::cos(az), ey * 0.5 - span * std::sin(az), g.maxHeightM() + relief * U(rng)};
            centre = glm::dvec3(ex * U(rng), ey * U(rng), g.minHeightM()) - origin;
            break;
        }
        case 2: {  // grazing: just above the highest level, every other one over the peak by half the graze
                   // tolerance (the single rays flag those as ambiguous)
            const double el = (U(rng) - 0.7) * 4.0 * M_PI / 180.0;
            if (b % 10 == 2)
                origin = {peak.x, peak.y, g.maxHeightM() + 0.5 * grazingToleranceM(g)};
            else
                origin = {inside.x, inside.y, g.maxHeightM() + 1e-3 * (relief + 1.0)};
            centre = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)};
            spread = 0.05 + 0.5 * U(rng);
            break;
        }
        case 3: {  // far away, along the surface towards the grid
            origin = {ex * 0.5 - 1000.0 * span * std::cos(az), ey * 0.5 - 1000.0 * span * std::sin(az),
                      g.maxHeightM() + relief * U(rng)};
            centre = glm::dvec3(ex * U(rng), ey * U(rng), g.minHeightM() + relief * U(rng)) - origin;
            spread = 0.01 * U(rng);
            break;
        }
        case 4: {  // inside the relief, any direction
            origin = inside;
            centre = glm::dvec3(U(rng) - 0.5, U(rng) - 0.5, U(rng) - 0.7);
            break;
        }
        default: {  // very high above, looking almost straight down
            origin = {inside.x, inside.y, g.maxHeightM() + 1e6 * (1.0 + U(rng))};
            centre = glm::dvec3(ex * U(rng), ey * U(rng), g.minHeightM()) - origin;
            spread = 1e-4 * U(rng);
            break;
        }
        }
        const auto rays = fan(origin, centre, spread);
        requireSameAsSingle(g, rays, {0.0, kInfinity}, work);
    }
    return work;
}

LoadedDem sample(const std::string& name, DemLoadOptions o = {}) {
    return loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name, o);
}

}  // namespace

TEST_CASE("Ray bundles get exactly the hits of single rays on real DEMs, with less work", "[heightfield][bundle]") {
    DemLoadOptions png;
    png.imageCellSizeM = 160.0;
    png.imageHeightScale = 0.1;
    for (const auto& [name, options] : std::vector<std::pair<std::string, DemLoadOptions>>{
             {"usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", {}},
             {"srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif", {}},
             {"puget-sound-usgs-1025x1025-16bit-heightmap.png", png},
             {"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", {}},
             {"N44W072.srtm3-white-mountains-nh.hgt", {}}}) {
        INFO(name);
        const HeightGrid g = sample(name, options).grid;
        const Work w = requireSameBundleHits(g, 150, 21);
        CHECK(w.hits > w.rays / 4);
        CHECK(w.ambiguous > 0);  // the near-peak grazing bundles did meet the tolerance
        // The bundle's free stretch replaces the blocks each ray would skip on its way down to the relief.
        CHECK(w.bundle.blocksSkipped < w.single.blocksSkipped * 3 / 4);
    }
}

TEST_CASE("Ray bundles get exactly the hits of single rays at the extremes", "[heightfield][bundle]") {
    // The shared extreme grids (flat, planar, twisted, tall with centimetre relief, strips, holes), then
    // centimetre cells and float fractal terrain.
    uint64_t seed = 31;
    for (const HeightGrid& g : extremeGrids()) requireSameBundleHits(g, 60, seed++);
    const Work tiny = requireSameBundleHits(randomGrid(65, 65, 0.01, 0.013, 0.0f, 0.05f, 12), 60, 39);
    CHECK(tiny.bundle.blocksSkipped < tiny.single.blocksSkipped);
    FractalTerrainOptions fractal;
    fractal.size = 257;
    const HeightGrid terrain = fractalTerrain(fractal);
    REQUIRE(terrain.storage() == HeightStorage::Float32);
    const Work w = requireSameBundleHits(terrain, 200, 38);
    CHECK(w.bundle.blocksSkipped < w.single.blocksSkipped * 3 / 4);
}

TEST_CASE("Ray bundles entering through a side face resume past the first cell only", "[heightfield][bundle]") {
    // Flat ground with the rays entering through the high-x (and high-y) face, steeply down, so the free
    // stretch ends inside the first column (row) and the hit lies in it. The face's boundary parameter from the
    // walk's formula can round a few ulps past the entry parameter from the clip; the walk must not restart
    // the first cell from it.
    std::vector<float> ground(33 * 33, 0.0f);
    ground[0] = 100.0f;  // one far peak lifts the grid's box above the rays' entry points
    const HeightGrid g(33, 33, 10.0, 10.0, ground);
    std::mt19937_64 rng(50);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    Work work;
    for (int b = 0; b < 400; ++b) {
        const bool alongX = b % 2 == 0;
        const double outside = g.extentXM() + 0.5 + 4.0 * U(rng), across = 40.0 + 240.0 * U(rng);
        const glm::dvec3 origin = alongX ? glm::dvec3(outside, across, 10.0 + 30.0 * U(rng))
                                         : glm::dvec3(across, outside, 10.0 + 30.0 * U(rng));
        const double el = (60.0 + 25.0 * U(rng)) * M_PI / 180.0;
        const glm::dvec3 centre = alongX ? glm::dvec3(-std::cos(el), 0.1 * (U(rng) - 0.5), -std::sin(el))
                                         : glm::dvec3(0.1 * (U(rng) - 0.5), -std::cos(el), -std::sin(el));
        requireSameAsSingle(g, fan(origin, centre, 0.5 + 2.0 * U(rng)), {0.0, kInfinity}, work);
    }
    CHECK(work.hits > work.rays * 9 / 10);
}

TEST_CASE("Ray bundles that only just reach the grid get the hits of single rays", "[heightfield][bundle]") {
    // Flat ground with one 100 m vertex in the middle. Bundles from one origin high above and outside a side
    // aim at ground points a billionth to half a cell inside (and as far outside) that side; level bundles from far
    // off aim at the peak's vertical, a millionth of a metre to two centimetres under its top. A bundle first sets aside the rays
    // that miss the grid's box: none of these may be set aside wrongly, and most of them hit.
    constexpr int64_t kSize = 17;
    constexpr double kCell = 10.0;
    std::vector<float> ground(kSize * kSize, 0.0f);
    ground[(kSize / 2) * kSize + kSize / 2] = 100.0f;
    const HeightGrid g(kSize, kSize, kCell, kCell, ground);
    const double ex = g.extentXM(), ey = g.extentYM();
    Work edges;
    for (double inside : {1e-9, 1e-6, 1e-3, 0.1, 0.5}) {
        for (double sign : {1.0, -1.0}) {
            const double d = sign * inside * kCell;  // metres inside the side (outside when negative)
            // Per side: an origin 20 cells out and a kilometre up, and the ground points along that side. Such a
            // ray enters the grid's box only within d of the side.
            const std::array<std::pair<glm::dvec3, glm::dvec2>, 4> sides{{
                {{-20.0 * kCell, 0.5 * ey, 1000.0}, {d, 0.0}},
                {{ex + 20.0 * kCell, 0.5 * ey, 1000.0}, {ex - d, 0.0}},
                {{0.5 * ex, -20.0 * kCell, 1000.0}, {0.0, d}},
                {{0.5 * ex, ey + 20.0 * kCell, 1000.0}, {0.0, ey - d}},
            }};
            for (const auto& [origin, fixed] : sides) {
                std::vector<Ray> rays;
                for (int k = 0; k < 16; ++k) {
                    const double along = (k + 0.5) / 16.0;
                    const glm::dvec2 p = fixed.y == 0.0 ? glm::dvec2(fixed.x, along * ey) : glm::dvec2(along * ex, fixed.y);
                    rays.push_back(Ray{origin, glm::normalize(glm::dvec3(p.x, p.y, 0.0) - origin)});
                }
                Work work;
                requireSameAsSingle(g, rays, {0.0, kInfinity}, work);
                if (sign > 0) CHECK(work.hits == work.rays);
                edges.rays += work.rays;
                edges.hits += work.hits;
            }
        }
    }
    CHECK(edges.hits < edges.rays);  // some aimed outside do miss
    const glm::dvec3 peak{0.5 * ex, 0.5 * ey, 100.0};
    Work level;
    for (double under : {1e-6, 1e-4, 1e-2}) {
        const glm::dvec3 origin{-3.0 * ex, 0.3 * ey, 100.0 - under};
        std::vector<Ray> rays;
        for (int k = 0; k < 16; ++k) {
            const glm::dvec3 target = peak - glm::dvec3(0.0, 0.0, under * (1.0 + k / 16.0));
            rays.push_back(Ray{origin, glm::normalize(target - origin)});
        }
        requireSameAsSingle(g, rays, {0.0, kInfinity}, level);
    }
    CHECK(level.hits == level.rays);
}

TEST_CASE("Ray bundles whose interval reaches behind the origin get the hits of single rays", "[heightfield][bundle]") {
    // Rays pointing up and away from above the terrain, with an interval that starts far behind the origin: their
    // hits lie behind it, where the bundle's proof (ahead of the origin only) says nothing.
    FractalTerrainOptions fractal;
    fractal.size = 65;
    const HeightGrid g = fractalTerrain(fractal);
    std::mt19937_64 rng(60);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    Work work;
    for (int b = 0; b < 20; ++b) {
        const glm::dvec3 origin{g.extentXM() * (0.3 + 0.4 * U(rng)), g.extentYM() * (0.3 + 0.4 * U(rng)),
                                g.maxHeightM() + 20.0 + 200.0 * U(rng)};
        const double az = 2.0 * M_PI * U(rng), el = (20.0 + 60.0 * U(rng)) * M_PI / 180.0;
        const glm::dvec3 up{std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)};
        const auto rays = fan(origin, up, 1.0 + 5.0 * U(rng));
        requireSameAsSingle(g, rays, {-1e7, kInfinity}, work);
        requireSameAsSingle(g, rays, {-1e7, 1e7}, work);
    }
    CHECK(work.hits > work.rays / 2);
}

TEST_CASE("Ray bundles that cannot share a proof are traced ray by ray", "[heightfield][bundle]") {
    FractalTerrainOptions fractal;
    fractal.size = 129;
    const HeightGrid g = fractalTerrain(fractal);
    Work work;
    const double relief = double(g.maxHeightM()) - g.minHeightM();
    const glm::dvec3 eye{-0.2 * g.extentXM(), -0.2 * g.extentYM(), g.maxHeightM() + 0.5 * relief};
    auto rays = fan(eye, glm::dvec3(0.5 * g.extentXM(), 0.5 * g.extentYM(), g.minHeightM()) - eye, 2.0);
    // One origin moved by a metre (no shared origin), or a vertical ray among them (no horizontal distance to
    // bound): each ray walks exactly as alone, so the bundle's counts are the single rays' counts.
    auto moved = rays;
    moved[17].origin.x += 1.0;
    auto vertical = rays;
    vertical[5].dir = {0.0, 0.0, -1.0};
    for (const auto& fallback : {moved, vertical}) {
        Work alone;
        requireSameAsSingle(g, fallback, {0.0, kInfinity}, alone);
        CHECK(alone.bundle.blocksSkipped == alone.single.blocksSkipped);
        CHECK(alone.bundle.cellsVisited == alone.single.cellsVisited);
        CHECK(alone.hits > 0);
    }
    // The same rays with one origin do take the shortcut.
    Work shared;
    requireSameAsSingle(g, rays, {0.0, kInfinity}, shared);
    CHECK(shared.bundle.blocksSkipped < shared.single.blocksSkipped);
    // From a grid vertex along directions through vertices (1:1, 1:2, 2:1 steps): x and y boundaries tie
    // all along, so the walk resumes after a corner.
    std::array<Ray, 9> diagonal;
    for (int k = 0; k < 9; ++k) {
        const glm::dvec3 d{1.0 + k % 3 / 2 + (k == 4), 1.0 + (k % 3 == 1), -0.05 * (1 + k / 3)};
        diagonal[size_t(k)] = Ray{{g.cellSizeXM() * 3, g.cellSizeYM() * 5, g.maxHeightM() + 20.0}, d};
    }
    requireSameAsSingle(g, diagonal, {0.0, kInfinity}, work);
    // A bounded interval that starts and ends inside the relief, and one ray alone.
    const double toCentre = glm::length(glm::dvec3(0.5 * g.extentXM(), 0.5 * g.extentYM(), g.minHeightM()) - eye);
    requireSameAsSingle(g, rays, {0.6 * toCentre, 1.1 * toCentre}, work);
    requireSameAsSingle(g, std::span<const Ray>(rays.data(), 1), {0.0, kInfinity}, work);
    CHECK(work.hits > 0);
    // The flat walk never takes the bundle's shortcut: it is the reference the pyramid is compared with.
    std::vector<std::optional<HeightFieldHit>> flat(rays.size());
    TraceCounters flatCounters, singleCounters;
    intersectBundle(g, rays, {0.0, kInfinity}, CellMethod::Bilinear, flat, &flatCounters, Traversal::Flat);
    for (size_t k = 0; k < rays.size(); ++k) {
        const auto single = intersect(g, rays[k], {0.0, kInfinity}, CellMethod::Bilinear, &singleCounters,
                                      Traversal::Flat);
        REQUIRE(flat[k].has_value() == single.has_value());
        if (single) REQUIRE(flat[k]->t == single->t);
    }
    CHECK(flatCounters.cellsVisited == singleCounters.cellsVisited);
    CHECK(flatCounters.blocksSkipped == 0);
}

TEST_CASE("A bundle traced with a value that names no cell method gets no hits, as a single ray does",
          "[heightfield][bundle]") {
    FractalTerrainOptions fractal;
    fractal.size = 33;
    const HeightGrid g = fractalTerrain(fractal);
    const double relief = double(g.maxHeightM()) - g.minHeightM();
    const glm::dvec3 eye{-0.2 * g.extentXM(), -0.2 * g.extentYM(), g.maxHeightM() + 0.5 * relief};
    const auto rays = fan(eye, glm::dvec3(0.5 * g.extentXM(), 0.5 * g.extentYM(), g.minHeightM()) - eye, 2.0);
    // The slots first hold the hits of a real method, so a bundle that wrote nothing would keep them.
    std::vector<std::optional<HeightFieldHit>> hits(rays.size());
    intersectBundle(g, rays, {0.0, kInfinity}, CellMethod::Bilinear, hits);
    REQUIRE(std::count_if(hits.begin(), hits.end(), [](const auto& h) { return h.has_value(); }) > 0);
    const auto notAMethod = static_cast<CellMethod>(99);
    intersectBundle(g, rays, {0.0, kInfinity}, notAMethod, hits);
    for (const auto& h : hits) CHECK_FALSE(h.has_value());
    CHECK_FALSE(intersect(g, rays.front(), {0.0, kInfinity}, notAMethod).has_value());
}
