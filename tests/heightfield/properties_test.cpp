// Properties over many seeded rays on a real DEM: watertightness, no self-intersection of spawned rays, and
// the gap between the bilinear patch and its two triangles.
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

const HeightGrid& stHelens() {
    static const LoadedDem dem =
        loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    return dem.grid;
}

// Height of the two-triangle surface (diagonal (i+1, j)-(i, j+1)) at local metres, in double.
double triangleHeightAt(const HeightGrid& g, double xM, double yM) {
    const double gx = xM / g.cellSizeXM(), gy = yM / g.cellSizeYM();
    const int64_t i = std::min<int64_t>(int64_t(gx), g.cellsX() - 1), j = std::min<int64_t>(int64_t(gy), g.cellsY() - 1);
    const double u = gx - double(i), v = gy - double(j);
    const double h00 = g.at(i, j), h10 = g.at(i + 1, j), h01 = g.at(i, j + 1), h11 = g.at(i + 1, j + 1);
    if (u + v <= 1.0) return h00 + (h10 - h00) * u + (h01 - h00) * v;
    return h11 + (h01 - h11) * (1.0 - u) + (h10 - h11) * (1.0 - v);
}

// Largest slope (rise over run) of any cell edge or diagonal of the grid's valid cells.
double maxSlope(const HeightGrid& g) {
    double m = 0.0;
    const double diag = std::hypot(g.cellSizeXM(), g.cellSizeYM());
    for (int64_t j = 0; j < g.cellsY(); ++j)
        for (int64_t i = 0; i < g.cellsX(); ++i) {
            if (!g.cellValid(i, j)) continue;
            m = std::max(m, std::abs(g.at(i + 1, j) - g.at(i, j)) / g.cellSizeXM());
            m = std::max(m, std::abs(g.at(i, j + 1) - g.at(i, j)) / g.cellSizeYM());
            m = std::max(m, std::abs(g.at(i + 1, j + 1) - g.at(i, j)) / diag);
            m = std::max(m, std::abs(g.at(i, j + 1) - g.at(i + 1, j)) / diag);
        }
    return m;
}

// True when the 3 x 3 block of cells around the cell holding a point is inside the grid and valid.
bool surroundedByValidCells(const HeightGrid& g, glm::dvec2 pM) {
    const auto i = int64_t(std::floor(pM.x / g.cellSizeXM())), j = int64_t(std::floor(pM.y / g.cellSizeYM()));
    for (int64_t b = j - 1; b <= j + 1; ++b)
        for (int64_t a = i - 1; a <= i + 1; ++a)
            if (a < 0 || b < 0 || a >= g.cellsX() || b >= g.cellsY() || !g.cellValid(a, b)) return false;
    return true;
}

// A random point of a valid cell: a third exactly on vertices, a third exactly on cell edges.
glm::dvec2 randomValidPoint(const HeightGrid& g, std::mt19937_64& rng) {
    std::uniform_int_distribution<int64_t> I(0, g.cellsX() - 1), J(0, g.cellsY() - 1);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (;;) {
        const int64_t i = I(rng), j = J(rng);
        if (!g.cellValid(i, j)) continue;
        double u = U(rng), v = U(rng);
        const int kind = int(rng() % 3);
        if (kind == 0) {
            u = double(rng() % 2);
            v = double(rng() % 2);
        } else if (kind == 1) {
            (rng() % 2 ? u : v) = double(rng() % 2);
        }
        return {(double(i) + u) * g.cellSizeXM(), (double(j) + v) * g.cellSizeYM()};
    }
}

}  // namespace

TEST_CASE("Watertight: 10^7 rays aimed from above at a real DEM's valid footprint all hit", "[heightfield][properties]") {
    const HeightGrid& g = stHelens();
    // Rays steeper than any slope of the terrain reach their target from above and go under the surface
    // right after it, so each must hit at or before the target; a crack between cells would let one through.
    const double steep = 1.2 * maxSlope(g);
    std::mt19937_64 rng(314159);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles}) {
        int64_t misses = 0, late = 0;
        const int64_t n = 5000000 / kSweepDivisor;  // per method: 10^7 in all (a tenth under sanitizers)
        for (int64_t k = 0; k < n; ++k) {
            const glm::dvec2 p = randomValidPoint(g, rng);
            glm::dvec3 d{U(rng), U(rng), 0.0};
            const double len = std::hypot(d.x, d.y);
            d.z = -std::max(steep * len, 1e-3);
            // The surface must go on all around the target: on the edge of a hole or of the footprint the
            // surface ends, and a ray reaching that edge exactly (or clipping the hole's corner next to it)
            // grazes the border; that is not a test of cracks between cells.
            if (!surroundedByValidCells(g, p)) {
                --k;
                continue;
            }
            const double h = m == CellMethod::Triangles ? triangleHeightAt(g, p.x, p.y)
                                                        : double(bilinearHeightAt(g, p.x, p.y));
            const glm::dvec3 target{p.x, p.y, h};
            const double back = (g.maxHeightM() + 10.0 - h) / -d.z;
            const auto hit = intersect(g, Ray{target - back * d, d}, {0, kInfinity}, m);
            if (!hit) {
                if (misses++ < 3)
                    std::printf("miss %s target %.17g %.17g %.17g dir %.17g %.17g %.17g\n", cellMethodName(m), target.x,
                                target.y, target.z, d.x, d.y, d.z);
            } else if ((hit->t - back) * glm::length(d) > hit->errorM) {
                ++late;
            }
        }
        std::printf("watertightness %s: %lld rays, %lld misses, %lld hits past the target\n", cellMethodName(m),
                    (long long)n, (long long)misses, (long long)late);
        INFO(cellMethodName(m));
        CHECK(misses == 0);
        CHECK(late == 0);
    }
}

TEST_CASE("Spawned rays never re-hit the surface they leave (10^5 hit points)", "[heightfield][properties]") {
    // pbrt-v4's re-intersection property: a ray leaving a hit point into the hemisphere above the geometric
    // normal, from the offset origin, must not hit the surface it starts on. A curved bilinear patch can be
    // hit again legitimately a little further on, so a near re-hit counts as a failure only when the
    // long-double reference, traced from the same origin, does not see it; for planar triangles, any re-hit
    // of the same triangle is a failure. (The nearest method's steps make a hit on a block's rim lie inside
    // the next block; it has no such guarantee.)
    const HeightGrid& g = stHelens();
    std::mt19937_64 rng(271828);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Triangles}) {
        int hits = 0, selfHits = 0, nearRehits = 0;
        while (hits < 100000) {
            const glm::dvec2 p = randomValidPoint(g, rng);
            const glm::dvec3 d = glm::normalize(glm::dvec3(U(rng), U(rng), -0.3 - std::abs(U(rng))));
            const auto hit = intersect(g, Ray{glm::dvec3(p, g.maxHeightM() + 5.0) - 3000.0 * d, d}, {0, kInfinity}, m);
            if (!hit) continue;
            glm::dvec3 w = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)));
            if (glm::dot(w, hit->normal) < 0.0) w = -w;
            if (glm::dot(w, hit->normal) < 1e-3) continue;
            ++hits;
            const Ray spawned{spawnOrigin(*hit, w), w};
            const auto again = intersect(g, spawned, {0, kInfinity}, m);
            if (!again || again->t > 0.1 * g.cellSizeXM()) continue;
            ++nearRehits;
            if (m == CellMethod::Triangles) {
                const bool sameTriangle = again->cellX == hit->cellX && again->cellY == hit->cellY &&
                                          (again->u + again->v > 1.0) == (hit->u + hit->v > 1.0) &&
                                          glm::length(again->normal - hit->normal) < 1e-9;
                selfHits += sameTriangle;
            } else {
                const auto truth = intersect(g, spawned, {0, kInfinity}, CellMethod::Reference);
                selfHits += !truth || truth->t > 0.2 * g.cellSizeXM();
            }
        }
        INFO(cellMethodName(m) << ": " << nearRehits << " legitimate re-hits within a tenth of a cell");
        CHECK(selfHits == 0);
    }
}

TEST_CASE("Triangles versus bilinear: the vertical gap never exceeds |d|/4 of the cell", "[heightfield][properties]") {
    const HeightGrid& g = stHelens();
    std::mt19937_64 rng(1618);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int checked = 0;
    double worstExcess = -kInfinity;
    for (int k = 0; k < 200000; ++k) {
        const glm::dvec2 p = randomValidPoint(g, rng);
        const glm::dvec3 d = glm::normalize(glm::dvec3(U(rng), U(rng), -0.2 - std::abs(U(rng))));
        const Ray ray{glm::dvec3(p, g.maxHeightM() + 5.0) - 3000.0 * d, d};
        const auto b = intersect(g, ray, {0, kInfinity}, CellMethod::Bilinear);
        const auto t = intersect(g, ray, {0, kInfinity}, CellMethod::Triangles);
        if (!b || !t) continue;
        const int64_t i = b->cellX, j = b->cellY;
        const double dTwist = double(g.at(i, j)) - g.at(i + 1, j) - g.at(i, j + 1) + g.at(i + 1, j + 1);
        const double tol = 1e-3;  // float rounding of heights near 2500 m, with margin
        const double gap = std::abs(b->pointM.z - triangleHeightAt(g, b->pointM.x, b->pointM.y));
        worstExcess = std::max(worstExcess, gap - std::abs(dTwist) / 4.0);
        CHECK(gap <= std::abs(dTwist) / 4.0 + tol);
        // And the triangles method's own hit lies on the triangles.
        CHECK(std::abs(t->pointM.z - triangleHeightAt(g, t->pointM.x, t->pointM.y)) <= tol);
        ++checked;
    }
    INFO("worst gap minus |d|/4: " << worstExcess << " m");
    CHECK(checked > 150000);
}

TEST_CASE("firstBlock blocks exactly the rays occluded blocks: at the nearest hit for rays that come down on the "
          "surface, at the entry for rays that come in under it from a hole", "[heightfield][properties]") {
    const HeightGrid& g = stHelens();
    for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
        INFO(cellMethodName(m));
        // Rays from high above towards random points of the valid footprint, steep and shallow.
        std::mt19937_64 rng(2718);
        std::uniform_real_distribution<double> U(-1.0, 1.0), S(0.0, 0.4);
        int64_t blocked = 0, atFirstHit = 0;
        const int64_t n = 30000 / kSweepDivisor;
        for (int64_t k = 0; k < n; ++k) {
            const glm::dvec2 p = randomValidPoint(g, rng);
            glm::dvec3 d{U(rng), U(rng), 0.0};
            d.z = -S(rng) * std::hypot(d.x, d.y) - 1e-3;
            const double top = double(g.maxHeightM()) + 5.0, back = (top - double(g.minHeightM())) / -d.z;
            const Ray ray{glm::dvec3(p, top) - back * d, d};
            const Interval span{0.0, 2.0 * back};
            const auto block = firstBlock(g, ray, span, m);
            INFO("ray " << k);
            REQUIRE(block.has_value() == occluded(g, ray, span, m));
            if (!block) continue;
            ++blocked;
            // Blocked at the first crossing, or earlier: where the ray came in under the surface (over a hole,
            // or at a nearest square's wall), with no crossing at all or a later one.
            const auto hit = intersect(g, ray, span, m);
            if (hit && block->t == hit->t) ++atFirstHit;
            else REQUIRE((!hit || block->t < hit->t));
        }
        CHECK(blocked > n / 10);
        CHECK(atFirstHit > blocked * 9 / 10);
        // Horizontal rays from the middle of a hole cell, a metre under the lowest corner of the valid cell east
        // of it, heading east: they come in under that cell, where occlusion (the terrain solid) blocks them at
        // once, while a search for a crossing from above finds none there (but the nearest squares' wall).
        int64_t fromHoles = 0;
        for (int64_t j = 0; j < g.cellsY() && fromHoles < 200; ++j)
            for (int64_t i = 0; i + 1 < g.cellsX() && fromHoles < 200; ++i) {
                if (g.cellValid(i, j) || !g.cellValid(i + 1, j)) continue;
                const double low = std::min({g.at(i + 1, j), g.at(i + 2, j), g.at(i + 1, j + 1), g.at(i + 2, j + 1)});
                const Ray ray{{(double(i) + 0.5) * g.cellSizeXM(), (double(j) + 0.5) * g.cellSizeYM(), low - 1.0},
                              {1.0, 0.0, 0.0}};
                const double entry = 0.5 * g.cellSizeXM();
                const auto block = firstBlock(g, ray, {0.0, kInfinity}, m);
                INFO("hole cell " << i << ", " << j);
                REQUIRE(block);
                CHECK(block->t == Approx(entry).margin(1e-6));
                // (The nearest squares' wall there is a crossing too.)
                const auto hit = intersect(g, ray, {0.0, kInfinity}, m);
                if (m == CellMethod::Nearest) CHECK((hit && hit->t == block->t));
                else if (hit) CHECK(hit->t > entry);
                ++fromHoles;
            }
        CHECK(fromHoles == 200);
    }
}
