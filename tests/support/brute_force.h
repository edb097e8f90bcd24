// Independent references for the height-field tests: brute-force cell coverage and root search.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"

#include <cmath>
#include <optional>
#include <random>
#include <vector>

namespace terracast::testing {

// Bilinear height of the grid at local metres (x, y), in long double; NaN outside the footprint or in a hole.
inline long double bilinearHeightAt(const HeightGrid& g, long double xM, long double yM) {
    long double gx = xM / g.cellSizeXM(), gy = yM / g.cellSizeYM();
    // Points a rounding error outside the footprint are pulled onto its border.
    const long double slack = 1e-9L * (1 + g.cellsX() + g.cellsY());
    if (gx < -slack || gy < -slack || gx > g.cellsX() + slack || gy > g.cellsY() + slack) return NAN;
    gx = std::clamp<long double>(gx, 0, g.cellsX());
    gy = std::clamp<long double>(gy, 0, g.cellsY());
    auto i = static_cast<int64_t>(std::floor(gx));
    auto j = static_cast<int64_t>(std::floor(gy));
    i = std::min<int64_t>(i, g.cellsX() - 1);
    j = std::min<int64_t>(j, g.cellsY() - 1);
    // A point on a cell boundary belongs to every cell that shares it: take a valid one if there is one.
    if (!g.cellValid(i, j) && gx == std::floor(gx) && i > 0 && g.cellValid(i - 1, j)) --i;
    else if (!g.cellValid(i, j) && gy == std::floor(gy) && j > 0 && g.cellValid(i, j - 1)) --j;
    else if (!g.cellValid(i, j) && gx == std::floor(gx) && gy == std::floor(gy) && i > 0 && j > 0 &&
             g.cellValid(i - 1, j - 1)) {
        --i;
        --j;
    }
    if (!g.cellValid(i, j)) return NAN;
    const long double u = gx - i, v = gy - j;
    const long double h00 = g.at(i, j), h10 = g.at(i + 1, j), h01 = g.at(i, j + 1), h11 = g.at(i + 1, j + 1);
    return h00 * (1 - u) * (1 - v) + h10 * u * (1 - v) + h01 * (1 - u) * v + h11 * u * v;
}

// Result of a brute-force root search of G(t) = h(x(t), y(t)) - z(t) along a ray.
struct BruteForceResult {
    std::optional<long double> t;  // first crossing
    long double minAbsGNoCross;    // smallest |G| at samples before the one preceding the crossing (grazing measure)
};

// The surface at grid coordinates (u, v) (vertex indices), in double, for either surface (bilinearHeightAt
// above is the bilinear patch alone, in long double): the bilinear patch, or with `triangles` the two
// triangles split by the diagonal from (1, 0) to (0, 1); NaN over holes. On a grid line or a vertex, any valid
// cell touching the point gives it.
inline double surfaceAt(const HeightGrid& g, double u, double v, bool triangles = false) {
    const int64_t iu = int64_t(std::floor(u)), iv = int64_t(std::floor(v));
    for (int64_t cj : {iv, iv - 1})
        for (int64_t ci : {iu, iu - 1}) {
            if (ci < 0 || cj < 0 || ci >= g.cellsX() || cj >= g.cellsY() || !g.cellValid(ci, cj)) continue;
            const double fu = u - double(ci), fv = v - double(cj);
            if (fu < 0.0 || fu > 1.0 || fv < 0.0 || fv > 1.0) continue;
            const double h00 = g.at(ci, cj), h10 = g.at(ci + 1, cj), h01 = g.at(ci, cj + 1), h11 = g.at(ci + 1, cj + 1);
            if (!triangles)
                return (1 - fu) * (1 - fv) * h00 + fu * (1 - fv) * h10 + (1 - fu) * fv * h01 + fu * fv * h11;
            if (fu + fv <= 1.0) return h00 + (h10 - h00) * fu + (h01 - h00) * fv;
            return h11 + (h11 - h01) * (fu - 1.0) + (h11 - h10) * (fv - 1.0);
        }
    return std::nan("");
}

// Dense sampling of G over [t0, t1] (`samples` steps) and bisection of the first sign change, in long double.
// Samples in holes or outside the grid are skipped (a hole interrupts the surface).
inline BruteForceResult bruteForceHit(const HeightGrid& g, const Ray& ray, long double t0, long double t1,
                                      int samples) {
    BruteForceResult r{std::nullopt, INFINITY};
    auto G = [&](long double t) {
        const long double x = (long double)ray.origin.x + t * (long double)ray.dir.x;
        const long double y = (long double)ray.origin.y + t * (long double)ray.dir.y;
        const long double z = (long double)ray.origin.z + t * (long double)ray.dir.z;
        return bilinearHeightAt(g, x, y) - z;
    };
    long double tPrev = t0, gPrev = G(t0);
    if (gPrev == 0) {
        r.t = t0;
        return r;
    }
    for (int k = 1; k <= samples; ++k) {
        const long double t = t0 + (t1 - t0) * k / samples;
        const long double gt = G(t);
        if (!std::isnan(gPrev) && !std::isnan(gt)) {
            if (gt == 0 || (gt < 0) != (gPrev < 0)) {
                long double lo = tPrev, hi = t, glo = gPrev;
                for (int it = 0; it < 200 && lo < hi; ++it) {
                    const long double mid = 0.5L * (lo + hi);
                    if (mid <= lo || mid >= hi) break;
                    const long double gm = G(mid);
                    if (gm == 0) { lo = hi = mid; break; }
                    if ((gm < 0) == (glo < 0)) { lo = mid; glo = gm; } else hi = mid;
                }
                r.t = gt == 0 && (gPrev < 0) == (gt < 0) ? t : 0.5L * (lo + hi);
                return r;
            }
        }
        // The previous sample is folded in only now that no crossing follows it: a sample next to the
        // crossing is close to zero without saying anything about grazing.
        if (!std::isnan(gPrev)) r.minAbsGNoCross = std::min(r.minAbsGNoCross, std::abs(gPrev));
        tPrev = t;
        gPrev = gt;
    }
    return r;
}

// Parameter range where the ray is over the grid's footprint (in metres), or none.
inline std::optional<std::pair<double, double>> footprintRange(const HeightGrid& g, const Ray& ray, Interval iv) {
    double t0 = iv.lo, t1 = iv.hi;
    auto clip = [&](double o, double d, double hi) {
        if (d == 0) return 0 <= o && o <= hi;
        double a = (0 - o) / d, b = (hi - o) / d;
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        return t0 <= t1;
    };
    if (!clip(ray.origin.x, ray.dir.x, g.extentXM()) || !clip(ray.origin.y, ray.dir.y, g.extentYM()))
        return std::nullopt;
    // Also bound by the height range (padded), so vertical rays get a finite range.
    const double zLo = g.minHeightM() - 1.0, zHi = g.maxHeightM() + 1.0;
    if (ray.dir.z == 0) {
        if (ray.origin.z < zLo || ray.origin.z > zHi) return std::nullopt;
    } else {
        double a = (zLo - ray.origin.z) / ray.dir.z, b = (zHi - ray.origin.z) / ray.dir.z;
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return std::nullopt;
    }
    return std::make_pair(t0, t1);
}

// A grid of random heights in [lo, hi] (seeded).
inline HeightGrid randomGrid(int64_t w, int64_t h, double cellX, double cellY, float lo, float hi, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> U(lo, hi);
    std::vector<float> z(static_cast<size_t>(w * h));
    for (auto& v : z) v = U(rng);
    return HeightGrid(w, h, cellX, cellY, std::move(z));
}

// The extreme grids the traversal tests share, in this order: flat; planar; strongly twisted (alternating
// +-200 m); tall with centimetre relief (8000 m); strips 2 cells wide along x and along y; 100 x 100 random
// heights with 600 nodata holes.
inline std::vector<HeightGrid> extremeGrids() {
    std::vector<HeightGrid> grids;
    grids.emplace_back(33, 33, 10.0, 10.0, std::vector<float>(33 * 33, 250.0f));
    std::vector<float> plane(64 * 48), twist(64 * 48);
    for (int j = 0; j < 48; ++j)
        for (int i = 0; i < 64; ++i) {
            plane[size_t(j * 64 + i)] = float(300.0 + 5.0 * i - 2.5 * j);
            twist[size_t(j * 64 + i)] = float((i + j) % 2 ? 200.0 : -200.0);
        }
    grids.emplace_back(64, 48, 10.0, 10.0, plane);
    grids.emplace_back(64, 48, 10.0, 10.0, twist);
    grids.push_back(randomGrid(65, 65, 30.0, 30.0, 8000.0f, 8000.01f, 9));
    grids.push_back(randomGrid(2, 300, 5.0, 5.0, 0.0f, 100.0f, 10));
    grids.push_back(randomGrid(300, 2, 5.0, 5.0, 0.0f, 100.0f, 11));
    std::vector<float> z(100 * 100);
    std::vector<uint8_t> valid(100 * 100, 1);
    std::mt19937_64 rng(12);
    for (auto& v : z) v = float(rng() % 1000);
    for (int k = 0; k < 600; ++k) valid[size_t(rng() % valid.size())] = 0;
    grids.emplace_back(100, 100, 20.0, 20.0, z, valid);
    return grids;
}

}  // namespace terracast::testing
