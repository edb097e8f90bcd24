// The tracer's own cell walk (traversal.cpp: the DDA of Amanatides & Woo interleaved with the pyramid) against a
// brute-force reference. The walk is observed through occlusion: in a grid of holes (nodata vertices) only one
// cell has four valid corners, flat at height 1, and the terrain counts as solid: a horizontal ray at z = 0.6 is
// blocked exactly when the walk reaches that cell. The verdict is compared with dense sampling of the ray's
// footprint in double precision, for both traversals (flat, and through the pyramid), with the default cell
// method.
#include "heightfield/traversal.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <tuple>
#include <vector>

using namespace terracast;

namespace {

constexpr double kTol = 1e-7;  // footprints this close to a cell's boundary may be credited to either side
constexpr double kRayZ = 0.6;

// A cx x cy cell grid (unit cells, cx >= 2) of holes but for cell (ti, tj), flat at height 1. One more valid
// vertex, at height 0 and in no valid cell, brings the grid's height range down to 0, so that the ray at 0.6 lies
// within the terrain's bounding box.
HeightGrid raisedCell(int64_t cx, int64_t cy, int64_t ti, int64_t tj) {
    std::vector<float> z(size_t((cx + 1) * (cy + 1)), 1.0f);
    std::vector<uint8_t> valid(z.size(), 0);
    for (int64_t dj = 0; dj <= 1; ++dj)
        for (int64_t di = 0; di <= 1; ++di) valid[size_t((tj + dj) * (cx + 1) + ti + di)] = 1;
    const size_t low = ti == 0 ? size_t(cx) : 0;  // vertex (cx, 0) or (0, 0): not a corner of the cell
    valid[low] = 1;
    z[low] = 0.0f;
    return HeightGrid(cx + 1, cy + 1, 1.0, 1.0, z, valid);
}

enum class Crossing { Yes, No, Unsure };

// Whether o + t d, t in [t0, t1], passes through the open cell (ti, tj): the stretch of the parameter inside the
// cell's square, found per axis; Unsure when the answer hangs on less than kTol.
Crossing crosses(glm::dvec2 o, glm::dvec2 d, double t0, double t1, int64_t ti, int64_t tj) {
    double a = t0, b = t1;
    bool near = false;
    for (int axis = 0; axis < 2; ++axis) {
        const double oo = axis == 0 ? o.x : o.y, dd = axis == 0 ? d.x : d.y, lo = double(axis == 0 ? ti : tj);
        if (dd == 0.0) {
            if (oo <= lo - kTol || oo >= lo + 1 + kTol) return Crossing::No;
            if (oo < lo + kTol || oo > lo + 1 - kTol) near = true;
            continue;
        }
        double ta = (lo - oo) / dd, tb = (lo + 1 - oo) / dd;
        if (ta > tb) std::swap(ta, tb);
        a = std::max(a, ta);
        b = std::min(b, tb);
    }
    const double length = (b - a) * std::hypot(d.x, d.y);
    if (length > kTol) return near ? Crossing::Unsure : Crossing::Yes;
    return length < -kTol ? Crossing::No : Crossing::Unsure;
}

struct Probe {
    int64_t cx, cy, ti, tj;
    glm::dvec2 o, d;
    double t0, t1;
};

bool blockedBy(const Probe& p, Traversal traversal) {
    const HeightGrid g = raisedCell(p.cx, p.cy, p.ti, p.tj);
    return occluded(g, Ray{{p.o.x, p.o.y, kRayZ}, {p.d.x, p.d.y, 0.0}}, {p.t0, p.t1}, CellMethod::Bilinear, nullptr,
                    traversal);
}

// Runs `count` random horizontal rays over random grids; returns the first disagreement, or "".
enum class Rays { Random, OnGridLines, FromGridLines };

std::string sweep(int count, uint64_t seed, Rays kind, Traversal traversal, int& checked) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(-4.0, 24.0), D(-1.0, 1.0);
    std::uniform_int_distribution<int> L(-1, 20), S(-3, 3);
    for (int k = 0; k < count; ++k) {
        Probe p;
        p.cx = 2 + k % 16;
        p.cy = 1 + (k / 17) % 13;
        p.ti = int64_t(rng() % uint64_t(p.cx));
        p.tj = int64_t(rng() % uint64_t(p.cy));
        p.o = {U(rng), U(rng)};
        p.d = {D(rng), D(rng)};
        if (kind == Rays::OnGridLines) {
            // Along a grid line, or through grid vertices with rational slopes.
            if (k % 2 == 0) {
                p.o = k % 4 == 0 ? glm::dvec2{U(rng), double(L(rng))} : glm::dvec2{double(L(rng)), U(rng)};
                p.d = k % 4 == 0 ? glm::dvec2{D(rng) < 0 ? -0.7 : 0.7, 0.0} : glm::dvec2{0.0, D(rng) < 0 ? -1.3 : 1.3};
            } else {
                p.d = {double(S(rng)), double(S(rng))};
                if (p.d == glm::dvec2(0.0)) p.d = {1.0, 2.0};
                p.o = glm::dvec2{double(L(rng)), double(L(rng))} - 5.0 * p.d;
            }
        }
        if (p.d == glm::dvec2(0.0)) continue;
        p.t0 = std::abs(D(rng)) * 3.0;
        p.t1 = p.t0 + std::abs(D(rng)) * 60.0;
        if (kind == Rays::FromGridLines) {
            // Starting exactly on a grid line (or at a vertex) inside the grid, and crossing it.
            p.o = {k % 3 == 1 ? U(rng) * 0.5 : double(1 + int64_t(rng() % uint64_t(p.cx))),
                   k % 3 == 0 ? U(rng) * 0.5 : double(1 + int64_t(rng() % uint64_t(p.cy)))};
            p.t0 = 0.0;
        }
        const Crossing expected = crosses(p.o, p.d, p.t0, p.t1, p.ti, p.tj);
        if (expected == Crossing::Unsure) continue;
        const bool blocked = blockedBy(p, traversal);
        ++checked;
        if (blocked != (expected == Crossing::Yes))
            return "ray " + std::to_string(k) + ": grid " + std::to_string(p.cx) + "x" + std::to_string(p.cy) +
                   ", cell (" + std::to_string(p.ti) + "," + std::to_string(p.tj) + "), o (" + std::to_string(p.o.x) +
                   ", " + std::to_string(p.o.y) + "), d (" + std::to_string(p.d.x) + ", " + std::to_string(p.d.y) +
                   "), t " + std::to_string(p.t0) + " .. " + std::to_string(p.t1) + ": " +
                   (blocked ? "blocked but not crossed" : "crossed but not blocked");
    }
    return "";
}

}  // namespace

TEST_CASE("Cell walk: a ray is stopped by exactly the cells exact clipping finds, 10^5 random rays", "[heightfield][dda]") {
    for (const Traversal traversal : {Traversal::Flat, Traversal::Pyramid}) {
        int checked = 0;
        const std::string first = sweep(100000, 12345, Rays::Random, traversal, checked);
        INFO((traversal == Traversal::Flat ? "flat: " : "pyramid: ") << first);
        CHECK(first.empty());
        CHECK(checked > 95000);
    }
}

TEST_CASE("Cell walk: rays along grid lines and through grid vertices", "[heightfield][dda]") {
    for (const Traversal traversal : {Traversal::Flat, Traversal::Pyramid}) {
        int checked = 0;
        const std::string first = sweep(40000, 7, Rays::OnGridLines, traversal, checked);
        INFO((traversal == Traversal::Flat ? "flat: " : "pyramid: ") << first);
        CHECK(first.empty());
        CHECK(checked > 10000);
    }
}

TEST_CASE("Cell walk: rays that start on a grid line or at a vertex", "[heightfield][dda]") {
    for (const Traversal traversal : {Traversal::Flat, Traversal::Pyramid}) {
        int checked = 0;
        const std::string first = sweep(40000, 99, Rays::FromGridLines, traversal, checked);
        INFO((traversal == Traversal::Flat ? "flat: " : "pyramid: ") << first);
        CHECK(first.empty());
        CHECK(checked > 30000);
    }
}

TEST_CASE("Cell walk: a shallow ray over 65536 cells changes row where it should", "[heightfield][dda]") {
    // Boundaries come from integer indices, not accumulated steps: the walk neither drifts into the next row
    // nor stops short over a long run. The ray rises 1/70000 per cell from y = 0.3 and crosses into row 1 at
    // x = 0.1 + 0.7 * 70000 = 49000.1.
    const int64_t n = 65536;
    const glm::dvec2 o{0.1, 0.3}, d{1.0, 1.0 / 70000.0};
    for (const auto& [cell, row, expected] : {std::tuple{int64_t(48999), int64_t(0), true}, {int64_t(49001), int64_t(0), false},
                                              {int64_t(49000), int64_t(1), true}, {int64_t(48999), int64_t(1), false},
                                              {n - 1, int64_t(1), true}}) {
        for (const Traversal traversal : {Traversal::Flat, Traversal::Pyramid}) {
            INFO("cell " << cell << ", row " << row << (traversal == Traversal::Flat ? ", flat" : ", pyramid"));
            CHECK(blockedBy(Probe{n, 2, cell, row, o, d, 0.0, 1e9}, traversal) == expected);
        }
    }
}
