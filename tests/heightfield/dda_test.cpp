// The DDA walk against a brute-force reference: dense sampling of the segment in double precision.
#include "heightfield/dda.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <set>
#include <vector>

using namespace terracast;

namespace {

constexpr double kTol = 1e-9;  // points this close to a cell boundary may be credited to either side

struct Walk {
    std::vector<CellVisit> visits;
};

Walk walk(int64_t cx, int64_t cy, glm::dvec2 o, glm::dvec2 d, double t0, double t1) {
    Walk w;
    walkCells(cx, cy, o, d, t0, t1, [&](const CellVisit& v) {
        w.visits.push_back(v);
        return false;
    });
    return w;
}

// Checks one walk against the brute-force reference; returns an empty string or a failure description.
std::string checkWalk(int64_t cx, int64_t cy, glm::dvec2 o, glm::dvec2 d, double t0, double t1) {
    const Walk w = walk(cx, cy, o, d, t0, t1);
    // Clip the segment to the footprint, exactly as a reference would (independent code).
    double a = t0, b = t1;
    auto clip = [&](double oo, double dd, double hi) {
        if (dd == 0) return -kTol <= oo && oo <= hi + kTol;
        double ta = (0 - oo) / dd, tb = (hi - oo) / dd;
        if (ta > tb) std::swap(ta, tb);
        a = std::max(a, ta);
        b = std::min(b, tb);
        return a <= b;
    };
    const bool overlaps = clip(o.x, d.x, double(cx)) && clip(o.y, d.y, double(cy));

    std::set<std::pair<int64_t, int64_t>> visited;
    for (size_t k = 0; k < w.visits.size(); ++k) {
        const auto& v = w.visits[k];
        if (!visited.insert({v.i, v.j}).second) return "cell visited twice";
        if (v.i < 0 || v.j < 0 || v.i >= cx || v.j >= cy) return "cell outside the grid";
        if (v.tExit < v.tEnter) return "segment runs backwards";
        if (k > 0) {
            const auto& p = w.visits[k - 1];
            const auto step = std::abs(v.i - p.i) + std::abs(v.j - p.j);
            if (step != 1) return "consecutive cells are not neighbours";
            if (v.tEnter != p.tExit) return "segments are not contiguous";
        }
        // The segment must touch the visited cell (within the tolerance).
        double ca = v.tEnter, cb = v.tExit;
        const double mid = 0.5 * (ca + cb);
        const glm::dvec2 pm = o + mid * d;
        if (pm.x < v.i - kTol * 10 - 1e-12 * std::abs(pm.x) || pm.x > v.i + 1 + kTol * 10 ||
            pm.y < v.j - kTol * 10 || pm.y > v.j + 1 + kTol * 10)
            return "visited cell does not contain its segment";
    }
    if (!overlaps) return w.visits.empty() ? "" : "walk of a ray that misses the grid";
    if (w.visits.empty()) {
        // Acceptable only when the ray merely grazes the footprint's border.
        const glm::dvec2 p = o + 0.5 * (a + b) * d;
        const bool onBorder = std::abs(p.x) < kTol || std::abs(p.y) < kTol || std::abs(p.x - cx) < kTol ||
                              std::abs(p.y - cy) < kTol;
        return onBorder ? "" : "no cell visited for a ray crossing the grid";
    }
    // Every sample strictly inside a cell must lie in a visited cell.
    const int samples = 64 * int(cx + cy) + 16;
    for (int s = 0; s <= samples; ++s) {
        const double t = a + (b - a) * s / samples;
        const glm::dvec2 p = o + t * d;
        const double fx = std::floor(p.x), fy = std::floor(p.y);
        if (p.x - fx < kTol || fx + 1 - p.x < kTol || p.y - fy < kTol || fy + 1 - p.y < kTol) continue;
        const auto i = int64_t(fx), j = int64_t(fy);
        if (i < 0 || j < 0 || i >= cx || j >= cy) continue;
        if (!visited.count({i, j})) return "sampled cell (" + std::to_string(i) + "," + std::to_string(j) + ") missed";
    }
    return "";
}

}  // namespace

TEST_CASE("DDA visits exactly the cells a dense sampling finds, for 10^5 random rays", "[heightfield][dda]") {
    std::mt19937_64 rng(12345);
    std::uniform_real_distribution<double> U(-4.0, 24.0);
    std::uniform_real_distribution<double> D(-1.0, 1.0);
    int failures = 0;
    std::string first;
    for (int k = 0; k < 100000; ++k) {
        const int64_t cx = 1 + k % 17, cy = 1 + (k / 17) % 13;
        const glm::dvec2 o{U(rng), U(rng)};
        glm::dvec2 d{D(rng), D(rng)};
        const double t0 = D(rng) * 5.0, t1 = t0 + std::abs(D(rng)) * 60.0;
        const std::string r = checkWalk(cx, cy, o, d, t0, t1);
        if (!r.empty() && failures++ == 0) first = r;
    }
    INFO(first);
    CHECK(failures == 0);
}

TEST_CASE("DDA handles axis-parallel and vertical rays, and rays along edges", "[heightfield][dda]") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> U(-2.0, 12.0);
    std::uniform_int_distribution<int> I(-1, 11);
    for (int k = 0; k < 20000; ++k) {
        const bool onLine = k % 2 == 0;  // origin exactly on a grid line
        const double across = onLine ? double(I(rng)) : U(rng);
        const double along = U(rng);
        const double s = (k % 4 < 2) ? 1.0 : -1.0;
        INFO("ray " << k);
        REQUIRE(checkWalk(10, 10, {along, across}, {s * 0.7, 0.0}, -30.0, 30.0).empty());  // d.y = 0
        REQUIRE(checkWalk(10, 10, {across, along}, {0.0, s * 1.3}, -30.0, 30.0).empty());  // d.x = 0
    }
    // Vertical rays: one cell, the whole interval.
    const Walk w = walk(10, 10, {3.5, 4.25}, {0.0, 0.0}, -1.0, 2.0);
    REQUIRE(w.visits.size() == 1);
    CHECK(w.visits[0].i == 3);
    CHECK(w.visits[0].j == 4);
    CHECK(w.visits[0].tEnter == -1.0);
    CHECK(w.visits[0].tExit == 2.0);
    // A vertical ray outside the footprint visits nothing.
    CHECK(walk(10, 10, {-0.5, 4.0}, {0.0, 0.0}, 0.0, 1.0).visits.empty());
}

TEST_CASE("DDA through grid vertices and out through a corner", "[heightfield][dda]") {
    // The diagonal of a square grid passes through every vertex (i, i).
    const Walk diag = walk(8, 8, {0.0, 0.0}, {1.0, 1.0}, 0.0, 100.0);
    REQUIRE(checkWalk(8, 8, {0.0, 0.0}, {1.0, 1.0}, 0.0, 100.0).empty());
    // It crosses the 8 diagonal cells plus one zero-length corner cell between each pair.
    CHECK(diag.visits.size() == 8 + 7);
    CHECK(diag.visits.front().i == 0);
    CHECK(diag.visits.back().i == 7);
    CHECK(diag.visits.back().j == 7);
    CHECK(diag.visits.back().tExit == Approx(8.0));
    // Reverse direction, leaving through the corner (0, 0).
    const Walk back = walk(8, 8, {8.0, 8.0}, {-1.0, -1.0}, 0.0, 100.0);
    CHECK(back.visits.front().i == 7);
    CHECK(back.visits.back().i == 0);
    CHECK(back.visits.back().j == 0);
    // Random rays through random vertices with rational slopes.
    std::mt19937_64 rng(99);
    std::uniform_int_distribution<int> V(0, 12), S(-3, 3);
    for (int k = 0; k < 20000; ++k) {
        const glm::dvec2 vtx{double(V(rng)), double(V(rng))};
        glm::dvec2 d{double(S(rng)), double(S(rng))};
        if (d == glm::dvec2(0.0)) d = {1.0, 2.0};
        const glm::dvec2 o = vtx - 5.0 * d;
        INFO("ray " << k);
        REQUIRE(checkWalk(12, 12, o, d, -10.0, 10.0).empty());
    }
}

TEST_CASE("DDA boundaries come from integer indices: no drift over a long walk", "[heightfield][dda]") {
    // A shallow ray over 65536 cells: every boundary crossing t must match (k - o) / d exactly.
    const int64_t n = 65536;
    const glm::dvec2 o{0.1, 0.3};
    const glm::dvec2 d{1.0, 1.0 / 70000.0};
    int64_t checked = 0;
    bool exact = true;
    walkCells(n, 2, o, d, 0.0, 1e9, [&](const CellVisit& v) {
        if (v.entry == CellSide::XLow) {
            exact = exact && v.tEnter == (double(v.i) - o.x) / d.x;
            ++checked;
        }
        return false;
    });
    CHECK(exact);
    CHECK(checked == n - 1);
}
