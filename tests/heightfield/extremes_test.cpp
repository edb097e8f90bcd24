// The intersector at the extremes real terrain and real cameras produce. Each case runs many seeded rays
// where it applies and compares every bilinear method with a brute-force long-double root search.
#include "heightfield/traversal.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace terracast;
using namespace terracast::testing;

namespace {

const CellMethod kBilinearMethods[] = {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Reference};

struct Agreement {
    int rays = 0, ambiguous = 0, verdictMismatch = 0, tMismatch = 0, hits = 0;
    double worstRel = 0.0;
    std::string firstFailure;
};

// Compares one method with the brute-force search on one ray. Rays that pass within `tolM` of the surface
// without crossing it are ambiguous for any arithmetic and are only counted. The search samples about 400 times
// a cell and can step over a dip of a few millimetres; where the method disagrees with it, the search is run
// again a thousand times denser (up to 2 million samples) and that answer is the reference. (Which rays a test
// draws depends on the compiler: the order in which a call's arguments draw their random numbers is unspecified.)
void compare(const HeightGrid& g, const Ray& ray, CellMethod method, Agreement& a, double relTol = 1e-5) {
    ++a.rays;
    const auto range = footprintRange(g, ray, {0.0, kInfinity});
    std::optional<long double> ref;
    long double minG = INFINITY;
    int samples = 0;
    const auto search = [&](int count) {
        const auto bf = bruteForceHit(g, ray, range->first, range->second, count);
        ref = bf.t;
        minG = bf.minAbsGNoCross;
    };
    if (range) {
        const double cellsCrossed = (range->second - range->first) *
                                    (std::abs(ray.dir.x) / g.cellSizeXM() + std::abs(ray.dir.y) / g.cellSizeYM());
        samples = int(std::min(200000.0, 400.0 * (cellsCrossed + 1.0) + 100.0));
        search(samples);
    }
    const double tolM = 1e-7 * (1.0 + std::max(std::abs(g.minHeightM()), std::abs(g.maxHeightM())));
    const auto hit = intersect(g, ray, {0.0, kInfinity}, method);
    const double scale = std::min(g.cellSizeXM(), g.cellSizeYM());
    const auto relativeError = [&] {
        return double(std::abs((long double)hit->t - *ref) / std::max<long double>(*ref, scale));
    };
    if (range && minG >= tolM && (hit.has_value() != ref.has_value() || (hit && relativeError() > relTol)))
        search(std::min(2000000, 1000 * samples));
    if (minG < tolM) {
        ++a.ambiguous;
        return;
    }
    if (hit.has_value() != ref.has_value()) {
        ++a.verdictMismatch;
        if (a.firstFailure.empty())
            a.firstFailure = std::string(cellMethodName(method)) + (hit ? " hit, reference missed" : " missed, reference hit") + " (origin " + std::to_string(ray.origin.x) + "," + std::to_string(ray.origin.y) + "," + std::to_string(ray.origin.z) + " dir " + std::to_string(ray.dir.x) + "," + std::to_string(ray.dir.y) + "," + std::to_string(ray.dir.z) + ")";
        return;
    }
    if (!hit) return;
    ++a.hits;
    const double rel = relativeError();
    a.worstRel = std::max(a.worstRel, rel);
    if (rel > relTol) {
        ++a.tMismatch;
        if (a.firstFailure.empty())
            a.firstFailure = std::string(cellMethodName(method)) + " t error " + std::to_string(rel);
    }
}

void requireAgreement(const Agreement& a, int minHits) {
    INFO("rays " << a.rays << ", hits " << a.hits << ", ambiguous " << a.ambiguous << ", worst relative t error "
                 << a.worstRel << "; " << a.firstFailure);
    CHECK(a.verdictMismatch == 0);
    CHECK(a.tMismatch == 0);
    CHECK(a.hits >= minHits);
    CHECK(a.ambiguous * 100 <= a.rays);
}

HeightGrid rough(int64_t w, int64_t h, uint64_t seed, double cell = 30.0) {
    return randomGrid(w, h, cell, cell * 1.3, 100.0f, 400.0f, seed);
}

glm::dvec3 randomPointAbove(const HeightGrid& g, std::mt19937_64& rng, double above) {
    std::uniform_real_distribution<double> U(0.0, 1.0);
    return {g.extentXM() * U(rng), g.extentYM() * U(rng), g.maxHeightM() + above * U(rng)};
}

}  // namespace

TEST_CASE("Extremes: axis-parallel rays (d.x = 0 and d.y = 0)", "[heightfield][extremes]") {
    const HeightGrid g = rough(9, 7, 1);
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : kBilinearMethods) {
        Agreement a;
        for (int k = 0; k < 2000; ++k) {
            glm::dvec3 o = randomPointAbove(g, rng, 200.0);
            glm::dvec3 d = k % 2 ? glm::dvec3{0.0, U(rng), -std::abs(U(rng))} : glm::dvec3{U(rng), 0.0, -std::abs(U(rng))};
            if (k % 4 < 2) o.z -= 150.0;  // also start inside the box
            compare(g, Ray{o, d}, m, a);
        }
        requireAgreement(a, 600);
    }
}

TEST_CASE("Extremes: direction components too small to step across a cell act as zero", "[heightfield][extremes]") {
    // A component of 1e-305 is a normal double, but the boundary parameters it gives overflow; the walk must then
    // treat the axis as parallel (and not form inf - inf), so the ray hits exactly where the axis-parallel one does.
    const HeightGrid g = rough(65, 49, 7);
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    int hits = 0;
    for (int k = 0; k < 2000; ++k) {
        const glm::dvec3 o = randomPointAbove(g, rng, 300.0);
        const double along = U(rng), down = -0.05 - std::abs(U(rng));
        const double tiny = (k % 2 ? 1.0 : -1.0) * 1e-305;
        const glm::dvec3 d0 = k % 4 < 2 ? glm::dvec3(along, 0.0, down) : glm::dvec3(0.0, along, down);
        const glm::dvec3 d1 = k % 4 < 2 ? glm::dvec3(along, tiny, down) : glm::dvec3(tiny, along, down);
        for (CellMethod m : kBilinearMethods) {
            const auto a = intersect(g, Ray{o, d0}, {0.0, kInfinity}, m);
            const auto b = intersect(g, Ray{o, d1}, {0.0, kInfinity}, m);
            INFO("ray " << k << ", " << cellMethodName(m));
            REQUIRE(a.has_value() == b.has_value());
            if (!a) continue;
            ++hits;
            CHECK(b->t == a->t);
            CHECK(b->cellX == a->cellX);
            CHECK(b->cellY == a->cellY);
            CHECK(occluded(g, Ray{o, d1}, {0.0, kInfinity}, m));
        }
    }
    CHECK(hits > 1500);
}

TEST_CASE("Extremes: vertical rays up and down, and horizontal rays", "[heightfield][extremes]") {
    const HeightGrid g = rough(9, 7, 2);
    std::mt19937_64 rng(12);
    std::uniform_real_distribution<double> U(-1.0, 1.0), Z(50.0, 450.0);
    for (CellMethod m : kBilinearMethods) {
        Agreement down, up, horizontal;
        for (int k = 0; k < 2000; ++k) {
            const glm::dvec3 p = randomPointAbove(g, rng, 0.0);
            // Straight down from above: always a hit, at exactly the bilinear height.
            compare(g, Ray{{p.x, p.y, 1000.0}, {0, 0, -1}}, m, down);
            // Straight up from below the surface: hits the surface from beneath.
            compare(g, Ray{{p.x, p.y, 0.0}, {0, 0, 2.5}}, m, up);
            // Horizontal at a random height, from outside the footprint.
            glm::dvec3 d{U(rng), U(rng), 0.0};
            compare(g, Ray{glm::dvec3(p.x, p.y, Z(rng)) - 1000.0 * d, d}, m, horizontal);
        }
        requireAgreement(down, 1900);
        requireAgreement(up, 1900);
        requireAgreement(horizontal, 500);
    }
    // A vertical ray's hit is the bilinear height under it, to float precision.
    const auto hit = intersect(g, Ray{{45.0, 39.0, 1000.0}, {0, 0, -1}}, {0, kInfinity}, CellMethod::Bilinear);
    REQUIRE(hit);
    CHECK(hit->pointM.z == Approx(double(bilinearHeightAt(g, 45.0, 39.0))).epsilon(1e-6));
}

TEST_CASE("Extremes: rays through vertices, along cell edges and out through a corner", "[heightfield][extremes]") {
    const HeightGrid g = rough(9, 9, 3, 10.0);
    std::mt19937_64 rng(13);
    std::uniform_int_distribution<int> V(0, 8);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : kBilinearMethods) {
        Agreement vertices, edges, corners;
        for (int k = 0; k < 2000; ++k) {
            // Through an interior vertex, arriving from a random direction. (At a border vertex a ray may
            // enter the footprint exactly at the surface's edge and pass under it: a graze.)
            const int i = 1 + V(rng) % 7, j = 1 + V(rng) % 7;
            // Along a grid line x = i * cell (an edge shared by two cells), descending.
            const glm::dvec3 e{i * g.cellSizeXM(), -5.0, 420.0};
            compare(g, Ray{e, {0.0, 1.0, -0.3 * std::abs(U(rng))}}, m, edges);
            // Diagonal rays through the vertices (k, k), leaving the grid exactly through its corner (8, 8).
            const glm::dvec3 c0{i * g.cellSizeXM(), i * g.cellSizeYM(), 350.0 + 100.0 * U(rng)};
            const glm::dvec3 dc{g.cellSizeXM(), g.cellSizeYM(), -5.0 * std::abs(U(rng))};
            compare(g, Ray{c0, dc}, m, corners);
            const glm::dvec3 vtx{i * g.cellSizeXM(), j * g.cellSizeYM(), double(g.at(i, j))};
            const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.2 - std::abs(U(rng))});
            // The ray reaches the surface at the vertex (t = 300) unless it crossed it earlier: it must hit
            // no later than there, and where the brute force finds an earlier crossing, at that crossing.
            const Ray ray{vtx - 300.0 * d, d};
            // Only rays that are above the surface just before the vertex and below it just after must hit;
            // a ray that only touches the surface at the vertex is a graze.
            const glm::dvec3 past = vtx + 0.1 * d, before = vtx - 0.1 * d;
            const long double hPast = bilinearHeightAt(g, past.x, past.y);
            const long double hBefore = bilinearHeightAt(g, before.x, before.y);
            if (std::isnan(hPast) || hPast - past.z < 1e-4 || std::isnan(hBefore) || hBefore - before.z > -1e-4)
                continue;
            const auto hit = intersect(g, ray, {0, kInfinity}, m);
            ++vertices.rays;
            if (!hit || hit->t > 300.0 + 1e-4) {
                ++vertices.verdictMismatch;
                continue;
            }
            ++vertices.hits;
            const auto range = footprintRange(g, ray, {0.0, 300.0 - 1e-3});
            if (range) {
                const auto bf = bruteForceHit(g, ray, range->first, range->second, 20000);
                if (bf.t && bf.minAbsGNoCross > 1e-4 && std::abs(hit->t - double(*bf.t)) > 1e-5 * 300.0)
                    ++vertices.tMismatch;
                if (!bf.t && hit->t < 300.0 - 1e-2) ++vertices.tMismatch;
            }
        }
        requireAgreement(vertices, 300);
        requireAgreement(edges, 30);
        requireAgreement(corners, 100);
    }
}

TEST_CASE("Extremes: grazing rays tangent to a ridge, and rays that dip into a cell and leave it", "[heightfield][extremes]") {
    std::mt19937_64 rng(14);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    int tangentFlagged = 0, tangentCases = 0;
    for (int k = 0; k < 5000; ++k) {
        // A one-cell patch with random corners; pick an interior point and a horizontal direction along which
        // the patch is concave (d du dv < 0), and the tangent line there.
        std::vector<float> hc(4);
        for (auto& v : hc) v = float(100.0 + 50.0 * U(rng));
        const HeightGrid g(2, 2, 20.0, 20.0, hc);
        const double a = g.at(0, 0), b = g.at(1, 0) - a, c = g.at(0, 1) - a, d = a - g.at(1, 0) - g.at(0, 1) + g.at(1, 1);
        if (std::abs(d) < 1.0) continue;
        const double u0 = 0.3 + 0.4 * U(rng), v0 = 0.3 + 0.4 * U(rng);
        double du = 0.3 + U(rng), dv = 0.3 + U(rng);
        if (d > 0) dv = -dv;  // d du dv < 0: concave along the ray
        const double h0 = a + b * u0 + c * v0 + d * u0 * v0;
        const double slope = (b + d * v0) * du + (c + d * u0) * dv;  // dh/ds at s = 0 (grid units)
        const glm::dvec3 dir{du * 20.0, dv * 20.0, slope};
        const glm::dvec3 touch{u0 * 20.0, v0 * 20.0, h0};
        const double depth = 1e-2;  // metres
        // Tangent line raised by `depth`: passes above the ridge, a miss for every method.
        const Ray above{touch + glm::dvec3(0, 0, depth) - 0.25 * dir, dir};
        // Lowered by `depth`: dips under the surface and comes back out within the cell.
        const Ray below{touch - glm::dvec3(0, 0, depth) - 0.25 * dir, dir};
        const double curvature = d * du * dv;  // h(s) = h0 + slope s + curvature s^2 along the ray
        const double halfWidth = std::sqrt(depth / -curvature);
        const double firstRoot = 0.25 - halfWidth;
        // Keep cases whose dip lies inside the cell and after the ray's origin.
        const double uRoot = u0 - halfWidth * du, vRoot = v0 - halfWidth * dv;
        if (halfWidth > 0.2 || uRoot < 0.0 || uRoot > 1.0 || vRoot < 0.0 || vRoot > 1.0) continue;
        // Float rounds G by a few ulps of the heights (~5e-5 m here); near a tangent the root moves by that
        // over the slope of G at the root, 2 sqrt(depth |curvature|).
        const double floatMargin = 5e-5 / (2.0 * std::sqrt(depth * -curvature));
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Reference}) {
            INFO("case " << k << " " << cellMethodName(m));
            CHECK_FALSE(intersect(g, above, {0, kInfinity}, m));
            const auto hit = intersect(g, below, {0, kInfinity}, m);
            REQUIRE(hit);
            if (m == CellMethod::Bilinear) CHECK(hit->t == Approx(firstRoot).margin(floatMargin));
            else CHECK(hit->t == Approx(firstRoot).epsilon(1e-9));
        }
        // The exact tangent is the ambiguous case the reference flags.
        ++tangentCases;
        TraceCounters counters;
        intersect(g, Ray{touch - 0.25 * dir, dir}, {0, kInfinity}, CellMethod::Reference, &counters);
        tangentFlagged += counters.ambiguous;
    }
    CHECK(tangentCases > 1000);
    CHECK(tangentFlagged == tangentCases);
}

TEST_CASE("Extremes: planar cells (the linear case), strongly twisted cells and flat terrain", "[heightfield][extremes]") {
    std::mt19937_64 rng(15);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    // Planar: h = 3 + 0.5 x - 0.25 y everywhere, so d = 0 in every cell.
    std::vector<float> plane(64);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) plane[size_t(j * 8 + i)] = float(300.0 + 5.0 * i - 2.5 * j);
    const HeightGrid planar(8, 8, 10.0, 10.0, plane);
    // Twisted: alternating corners +-200 m, so |d| is 800 m per cell.
    std::vector<float> twist(64);
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) twist[size_t(j * 8 + i)] = float((i + j) % 2 ? 200.0 : -200.0);
    const HeightGrid twisted(8, 8, 10.0, 10.0, twist);
    const HeightGrid flat(8, 8, 10.0, 10.0, std::vector<float>(64, 250.0f));
    for (CellMethod m : kBilinearMethods) {
        Agreement p, t, f;
        for (int k = 0; k < 2000; ++k) {
            const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.05 - std::abs(U(rng))});
            const glm::dvec3 target{35.0 + 30.0 * U(rng), 35.0 + 30.0 * U(rng), 0.0};
            compare(planar, Ray{target + glm::dvec3(0, 0, 300) - 500.0 * d, d}, m, p);
            compare(twisted, Ray{target - 500.0 * d, d}, m, t);
            compare(flat, Ray{target + glm::dvec3(0, 0, 250) - 500.0 * d, d}, m, f);
        }
        requireAgreement(p, 1000);
        requireAgreement(t, 1000);
        requireAgreement(f, 1000);
    }
    // Flat terrain: every ray aimed from above at the footprint hits at exactly z = 250.
    for (int k = 0; k < 10000; ++k) {
        const glm::dvec3 target{70.0 * (0.5 + 0.5 * U(rng)), 70.0 * (0.5 + 0.5 * U(rng)), 250.0};
        const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.01 - std::abs(U(rng))});
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
            const auto hit = intersect(flat, Ray{target - 100.0 * d, d}, {0, kInfinity}, m);
            REQUIRE(hit);
            REQUIRE(hit->pointM.z == Approx(250.0).margin(1e-3));
        }
    }
}

TEST_CASE("Extremes: tall terrain with tiny relief, and a grid at UTM-sized coordinates", "[heightfield][extremes]") {
    // Heights near 8000 m that vary by 0.01 m.
    const HeightGrid tall = randomGrid(9, 9, 30.0, 30.0, 8000.0f, 8000.01f, 16);
    std::mt19937_64 rng(16);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : kBilinearMethods) {
        Agreement a;
        for (int k = 0; k < 2000; ++k) {
            const glm::dvec3 target{120.0 + 100.0 * U(rng), 120.0 + 100.0 * U(rng), 8000.0};
            const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.1 - std::abs(U(rng))});
            // Float holds 8000 m to 5e-4 m, so its relative error here is bounded by the 1e-4 maximum goal.
            compare(tall, Ray{target - 1000.0 * d, d}, m, a, m == CellMethod::Bilinear ? 1e-4 : 1e-9);
        }
        requireAgreement(a, 1900);
    }
    // The same rays expressed in UTM coordinates (origin 500000 E, 4500000 N) and brought into the local
    // frame in double precision hit the same points as rays built in the local frame directly.
    const HeightGrid g = rough(17, 17, 17);
    const glm::dvec3 utmOrigin{500000.0, 4500000.0, 0.0};
    int compared = 0;
    for (int k = 0; k < 5000; ++k) {
        const glm::dvec3 targetUtm = utmOrigin + glm::dvec3{240.0 + 200.0 * U(rng), 300.0 + 250.0 * U(rng), 0.0};
        const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.2 - std::abs(U(rng))});
        const glm::dvec3 eyeUtm = targetUtm - 2000.0 * d + glm::dvec3(0, 0, 400);
        const Ray local{eyeUtm - utmOrigin, d};
        const Ray direct{(targetUtm - utmOrigin) - 2000.0 * d + glm::dvec3(0, 0, 400), d};
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles}) {
            const auto a = intersect(g, local, {0, kInfinity}, m), b = intersect(g, direct, {0, kInfinity}, m);
            REQUIRE(a.has_value() == b.has_value());
            if (a) {
                // Equal within the hits' own error bounds (the two origins differ by UTM rounding, ~1e-9 m).
                CHECK(glm::length(a->pointM - b->pointM) <= a->errorM + b->errorM);
                ++compared;
            }
        }
    }
    CHECK(compared > 5000);
    // Float coordinates at a UTM northing are 0.5 m apart: the reason the local frame exists.
    CHECK(std::nextafter(4500000.0f, 5e6f) - 4500000.0f == 0.5f);
}

TEST_CASE("Extremes: 1x1-cell, 1xN, Nx1 and 65537 x 3 grids", "[heightfield][extremes]") {
    std::mt19937_64 rng(18);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    struct Shape {
        int64_t w, h;
    };
    for (Shape s : {Shape{2, 2}, Shape{2, 40}, Shape{40, 2}}) {
        const HeightGrid g = rough(s.w, s.h, 19 + uint64_t(s.w));
        for (CellMethod m : kBilinearMethods) {
            Agreement a;
            for (int k = 0; k < 1000; ++k) {
                const glm::dvec3 p = randomPointAbove(g, rng, 0.0);
                const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), -0.1 - std::abs(U(rng))});
                compare(g, Ray{glm::dvec3(p.x, p.y, 250.0) - 800.0 * d, d}, m, a);
            }
            INFO(s.w << " x " << s.h);
            requireAgreement(a, 300);
        }
    }
    // 65537 x 3 vertices: cell indices beyond 65535 along x; a long shallow ray walks the whole grid.
    const int64_t w = 65537;
    std::vector<float> z(size_t(w * 3));
    for (int64_t j = 0; j < 3; ++j)
        for (int64_t i = 0; i < w; ++i) z[size_t(j * w + i)] = float(100.0 + 10.0 * std::sin(double(i) * 0.001));
    // A peak near the far end.
    z[size_t(1 * w + 65530)] = 5000.0f;
    const HeightGrid big(w, 3, 1.0, 1.0, z);
    const Ray ray{{0.0, 1.0, 400.0}, {1.0, 0.0, 0.0}};
    TraceCounters counters;
    const auto hit = intersect(big, ray, {0, kInfinity}, CellMethod::Bilinear, &counters, Traversal::Flat);
    REQUIRE(hit);
    CHECK(hit->cellX == 65529);
    CHECK(hit->pointM.x > 65529.0);
    CHECK(hit->pointM.x < 65530.0);
    CHECK(counters.cellsVisited == 65530);
    // Through the pyramid: the same hit, walking a handful of cells.
    TraceCounters fast;
    const auto same = intersect(big, ray, {0, kInfinity}, CellMethod::Bilinear, &fast);
    REQUIRE(same);
    CHECK(same->t == hit->t);
    CHECK(fast.cellsVisited < 100);
    // At the last cell, index 65535: a vertical ray.
    const auto last = intersect(big, Ray{{65535.5, 0.5, 1000.0}, {0, 0, -1}}, {0, kInfinity}, CellMethod::Bilinear);
    REQUIRE(last);
    CHECK(last->cellX == 65535);
}

TEST_CASE("Extremes: nodata holes let rays through to what lies behind", "[heightfield][extremes]") {
    // 9 x 9 vertices at 100 m on flat ground (100 m), with two north-south ridges 1000 m high at x = 400 m
    // and x = 700 m. A nodata vertex in the first ridge at (400, 400) opens a gap of four hole cells.
    auto build = [](bool withHole) {
        std::vector<float> z(81, 100.0f);
        std::vector<uint8_t> valid(81, 1);
        for (int j = 0; j < 9; ++j) z[size_t(j * 9 + 4)] = z[size_t(j * 9 + 7)] = 1000.0f;
        if (withHole) {
            valid[size_t(4 * 9 + 4)] = 0;
            z[size_t(4 * 9 + 4)] = -32767.0f;  // the nodata value itself must never be traced
        }
        return HeightGrid(9, 9, 100.0, 100.0, z, valid);
    };
    const HeightGrid holed = build(true), solid = build(false);
    CHECK(holed.nodataVertexCount() == 1);
    CHECK(holed.validCellCount() == 64 - 4);
    const Ray level{{50.0, 400.0, 500.0}, {1.0, 0.0, 0.0}};  // through the gap, at half the ridge height
    for (CellMethod m : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Triangles, CellMethod::Nearest,
                         CellMethod::Reference}) {
        INFO(cellMethodName(m));
        // Without the hole the first ridge stops the ray (its west slope spans x = 300..400 m).
        const auto blocked = intersect(solid, level, {0, kInfinity}, m);
        REQUIRE(blocked);
        CHECK(blocked->pointM.x >= 300.0);
        CHECK(blocked->pointM.x <= 400.0);
        // With it, the ray passes through the gap and hits the second ridge's west slope (x = 600..700 m).
        const auto behind = intersect(holed, level, {0, kInfinity}, m);
        REQUIRE(behind);
        CHECK(behind->pointM.x >= 600.0);
        CHECK(behind->pointM.x <= 700.0);
        // Straight down into a hole: nothing below.
        CHECK_FALSE(intersect(holed, Ray{{350.0, 350.0, 2000.0}, {0, 0, -1}}, {0, kInfinity}, m));
        // Next to the gap: the ground.
        const auto ground = intersect(holed, Ray{{150.0, 450.0, 2000.0}, {0, 0, -1}}, {0, kInfinity}, m);
        REQUIRE(ground);
        CHECK(ground->pointM.z == Approx(100.0));
    }
}

TEST_CASE("Extremes: non-finite heights are refused when the grid is built", "[heightfield][extremes]") {
    std::vector<float> z(9, 1.0f);
    z[4] = std::numeric_limits<float>::quiet_NaN();
    CHECK_THROWS_AS(HeightGrid(3, 3, 1.0, 1.0, z), GridError);
    z[4] = std::numeric_limits<float>::infinity();
    CHECK_THROWS_WITH(HeightGrid(3, 3, 1.0, 1.0, z), Catch::Contains("not finite") && Catch::Contains("(1, 1)"));
    // The same vertex marked nodata is accepted.
    std::vector<uint8_t> valid(9, 1);
    valid[4] = 0;
    CHECK_NOTHROW(HeightGrid(3, 3, 1.0, 1.0, z, valid));
}

TEST_CASE("Extremes: rays starting inside the box, below the surface and exactly on it", "[heightfield][extremes]") {
    const HeightGrid g = rough(9, 9, 20);
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> U(-1.0, 1.0);
    for (CellMethod m : kBilinearMethods) {
        Agreement inside, below;
        for (int k = 0; k < 2000; ++k) {
            const glm::dvec3 p = randomPointAbove(g, rng, 0.0);
            const double h = double(bilinearHeightAt(g, p.x, p.y));
            const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), U(rng)});
            // Inside the box above the surface, any direction.
            compare(g, Ray{{p.x, p.y, h + 0.5 * (g.maxHeightM() - h) + 1.0}, d}, m, inside);
            // Below the surface: the first crossing is where the ray comes out.
            compare(g, Ray{{p.x, p.y, h - 5.0}, d}, m, below);
        }
        requireAgreement(inside, 500);
        requireAgreement(below, 1200);
    }
    // Exactly on the surface (a vertex, where the height is exact): the hit is at t = 0, whatever the direction.
    for (int k = 0; k < 1000; ++k) {
        const int i = 1 + k % 7, j = 1 + (k / 7) % 7;
        const glm::dvec3 p{i * g.cellSizeXM(), j * g.cellSizeYM(), double(g.at(i, j))};
        const glm::dvec3 d = glm::normalize(glm::dvec3{U(rng), U(rng), U(rng)});
        for (CellMethod m : kBilinearMethods) {
            const auto hit = intersect(g, Ray{p, d}, {0, kInfinity}, m);
            REQUIRE(hit);
            CHECK(hit->t == 0.0);
        }
    }
}
