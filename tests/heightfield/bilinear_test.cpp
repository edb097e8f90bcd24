// The bilinear-patch intersection against a brute-force root search, and the cell methods' basic geometry.
#include "heightfield/cell_intersectors.h"
#include "heightfield/traversal.h"
#include "support/brute_force.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

struct PatchRay {
    HeightGrid grid;
    Ray ray;
};

// A one-cell grid with random corners and a ray aimed at a random point near the cell, from a random
// direction: a mix of steep, shallow and upward rays.
PatchRay randomPatchRay(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double cell = 1.0 + 99.0 * U(rng);
    const double relief = cell * (0.05 + 2.0 * U(rng));
    std::vector<float> h(4);
    for (auto& v : h) v = float(relief * U(rng));
    HeightGrid grid(2, 2, cell, cell, h);
    const glm::dvec3 target{cell * (-0.1 + 1.2 * U(rng)), cell * (-0.1 + 1.2 * U(rng)), relief * U(rng)};
    glm::dvec3 dir{U(rng) * 2 - 1, U(rng) * 2 - 1, U(rng) * 2 - 1.3};
    dir = glm::normalize(dir);
    const double back = cell * (0.5 + 4.0 * U(rng));
    return {std::move(grid), Ray{target - back * dir, dir}};
}

}  // namespace

TEST_CASE("Bilinear intersection matches a brute-force root search on 10^5 random patches", "[heightfield][bilinear]") {
    std::mt19937_64 rng(2024);
    struct Tally {
        int verdictMismatch = 0, tMismatch = 0, compared = 0;
        double worstRel = 0.0;
    };
    Tally tallies[3];
    const CellMethod methods[3] = {CellMethod::Reference, CellMethod::BilinearDouble, CellMethod::Bilinear};
    int grazing = 0;
    for (int k = 0; k < 100000 / kSweepDivisor; ++k) {
        const PatchRay pr = randomPatchRay(rng);
        const auto range = footprintRange(pr.grid, pr.ray, {0.0, kInfinity});
        std::optional<long double> ref;
        long double minG = INFINITY;
        if (range) {
            const auto bf = bruteForceHit(pr.grid, pr.ray, range->first, range->second, 4000);
            ref = bf.t;
            minG = bf.minAbsGNoCross;
        }
        // Rays that pass within 1e-6 of the surface without crossing, or cross at a near-tangent, are
        // numerically ambiguous for any method; they are counted and left out.
        const double scale = pr.grid.cellSizeXM();
        if (minG < 1e-6 * scale) {
            ++grazing;
            continue;
        }
        for (int m = 0; m < 3; ++m) {
            const auto hit = intersect(pr.grid, pr.ray, {0.0, kInfinity}, methods[m]);
            auto& t = tallies[m];
            if (hit.has_value() != ref.has_value()) {
                ++t.verdictMismatch;
                continue;
            }
            if (!hit) continue;
            ++t.compared;
            // Relative to the hit distance, or to the cell size for hits closer than one cell (a ray starting
            // next to the surface has t near 0, where a relative error says nothing).
            const double rel = double(std::abs((long double)hit->t - *ref) / std::max<long double>(*ref, scale));
            t.worstRel = std::max(t.worstRel, rel);
            if (rel > 1e-5) ++t.tMismatch;
        }
    }
    INFO("grazing rays left out: " << grazing);
    CHECK(grazing < 1000);
    for (int m = 0; m < 3; ++m) {
        INFO(cellMethodName(methods[m]) << ": compared " << tallies[m].compared << ", worst relative t error "
                                        << tallies[m].worstRel);
        CHECK(tallies[m].compared > 30000 / kSweepDivisor);
        CHECK(tallies[m].verdictMismatch == 0);
        CHECK(tallies[m].tMismatch == 0);
    }
    CHECK(tallies[0].worstRel < 1e-9);
    CHECK(tallies[1].worstRel < 1e-9);
}

TEST_CASE("Bilinear cell solver: hand-computed saddle", "[heightfield][bilinear]") {
    // h = u v on a unit cell (h00 = h10 = h01 = 0, h11 = 1). A ray down the diagonal plane u = v from
    // above, z = 1 - s/2 with u = v = s/2: u v = s^2/4 = 1 - s/2 gives s = -1 + sqrt(5) ... times 2:
    // s^2 + 2 s - 4 = 0, s = -1 + sqrt(5).
    CellCorners<double> h{0, 0, 0, 1};
    CellSegment<double> seg{0, 0, 1, 0.5, 0.5, -0.5, 2.0, 0.0 - 1.0, 1.0 - 0.0};
    const auto s = intersectBilinearCell(h, seg);
    REQUIRE(s);
    CHECK(*s == Approx(-1.0 + std::sqrt(5.0)).epsilon(1e-14));
    // A ray that stays above: z = 1.2 everywhere, h <= 1.
    CellSegment<double> above{0, 0, 1.2, 0.5, 0.5, 0.0, 2.0, -1.2, 1.0 - 1.2};
    CHECK_FALSE(intersectBilinearCell(h, above));
}

TEST_CASE("Analytic normal of the bilinear patch", "[heightfield][bilinear]") {
    // Plane h = 2x + 3y over 10 m cells: normal along (-0.2, -0.3, 1) once cell size is accounted for.
    const std::vector<float> z{0, 20, 30, 50};
    HeightGrid g(2, 2, 10, 10, z);
    const auto hit = intersect(g, Ray{{5, 5, 100}, {0, 0, -1}}, {0, kInfinity}, CellMethod::Bilinear);
    REQUIRE(hit);
    CHECK(hit->t == Approx(100 - 25));
    const glm::dvec3 expected = glm::normalize(glm::dvec3(-2, -3, 1));
    CHECK(hit->normal.x == Approx(expected.x));
    CHECK(hit->normal.y == Approx(expected.y));
    CHECK(hit->normal.z == Approx(expected.z));
}
