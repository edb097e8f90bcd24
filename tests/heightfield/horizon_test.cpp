// The horizon walk against answers it does not compute itself: a ridge's geometry, and a dense march over the
// surface (interpolated here, from the four corners) on fractal terrain with holes, for both surfaces, with
// and without a search radius and earth curvature.
#include "heightfield/fractal_terrain.h"
#include "heightfield/horizon.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace terracast;
using terracast::testing::surfaceAt;

namespace {

constexpr double kPiHere = 3.14159265358979323846;

double deg(double tangent) { return std::atan(tangent) * 180.0 / kPiHere; }

// The largest slope from the point (x0, y0) (vertex indices) at height z0 to surface points along (dirX, dirY):
// sampled every 1/4000 of a cell (and from a millionth of a cell on, for the slope at a vertex), and where the
// line crosses the lines u = m, v = m and u + v = m, on which the surfaces have their kinks, and at the search
// radius. A lower bound of the exact supremum.
double marchTangentFrom(const HeightGrid& g, double x0, double y0, double z0, double dirX, double dirY, bool triangles,
                        const HorizonSearch& s) {
    const double n = std::hypot(dirX, dirY);
    const double eu = dirX / n / g.cellSizeXM(), ev = dirY / n / g.cellSizeYM();  // cells per metre
    const double cell = std::min(g.cellSizeXM(), g.cellSizeYM());
    std::vector<double> ts;
    for (double t = 1e-6 * cell; t < 1e-3 * cell; t *= 10.0) ts.push_back(t);
    const double span = std::hypot(g.extentXM(), g.extentYM());
    for (double t = 1e-3 * cell; t <= span; t += cell / 4000.0) ts.push_back(t);
    if (std::isfinite(s.maxDistanceM)) ts.push_back(s.maxDistanceM);  // the search radius ends a stretch too
    for (int64_t m = -100; m <= 100; ++m) {
        if (eu != 0.0) ts.push_back((double(m) - x0) / eu);
        if (ev != 0.0) ts.push_back((double(m) - y0) / ev);
        if (eu + ev != 0.0) ts.push_back((double(m) - x0 - y0) / (eu + ev));
    }
    double best = -std::numeric_limits<double>::infinity();
    for (double t : ts) {
        if (!(t > 0.0) || t > s.maxDistanceM) continue;
        double u = x0 + t * eu, v = y0 + t * ev;
        // Along an axis the other coordinate stays exactly on its line.
        if (std::abs(eu) < 1e-12 * std::abs(ev)) u = x0;
        if (std::abs(ev) < 1e-12 * std::abs(eu)) v = y0;
        if (u < -1e-9 || v < -1e-9 || u > double(g.cellsX()) + 1e-9 || v > double(g.cellsY()) + 1e-9) continue;
        const double h = surfaceAt(g, std::clamp(u, 0.0, double(g.cellsX())), std::clamp(v, 0.0, double(g.cellsY())), triangles);
        if (!std::isnan(h)) best = std::max(best, (h - z0 - s.dropPerSquareM * t * t) / t);
    }
    return best;
}

// The same from vertex (i, j) at its own height.
double marchTangent(const HeightGrid& g, int64_t i, int64_t j, double dirX, double dirY, bool triangles,
                    const HorizonSearch& s) {
    return marchTangentFrom(g, double(i), double(j), g.at(i, j), dirX, dirY, triangles, s);
}

// Fractal terrain with nodata patches (holes one and two cells wide), 33 x 33 vertices of 30 x 21 m. The nodata
// vertices hold heights 2 km up, so a walk that reads a hole as surface shows it.
HeightGrid holedFractal(std::mt19937_64& rng) {
    HeightGrid base = fractalTerrain({.size = 33, .seed = 5, .cellSizeM = 30.0, .offsetAt1KmM = 600.0});
    std::vector<float> z = base.copyHeights();
    std::vector<uint8_t> valid(z.size(), 1);
    std::uniform_int_distribution<int64_t> V(1, 31);
    for (int k = 0; k < 8; ++k) {
        const int64_t ci = V(rng), cj = V(rng);
        valid[size_t(cj * 33 + ci)] = 0;
        if (k % 2) valid[size_t(cj * 33 + ci + 1)] = 0;  // holes two cells wide too
    }
    for (size_t v = 0; v < z.size(); ++v)
        if (!valid[v]) z[v] += 2000.0f;
    return HeightGrid(33, 33, 30.0, 21.0, z, valid);
}

}  // namespace

TEST_CASE("Horizon walk: a ridge's horizon is its crest's elevation angle at any azimuth", "[heightfield][horizon]") {
    // A north-south ridge on flat ground: 0 m up to x = 10 cells, rising 8 m per cell to 40 m at x = 15, falling
    // back to 0 at x = 20. Heights vary along x only, so both surfaces are the same piecewise-linear ridge.
    const int64_t w = 31, h = 81;
    const double cx = 20.0, cy = 12.5;
    std::vector<float> z(size_t(w * h));
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) z[size_t(j * w + i)] = float(std::max<int64_t>(0, 40 - 8 * std::abs(i - 15)));
    const HeightGrid g(w, h, cx, cy, z);
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
        for (double az : {90.0, 60.0, 120.0, 45.0, 135.0, 77.3}) {
            INFO(cellMethodName(method) << " azimuth " << az);
            const double a = az * kPiHere / 180.0;
            // From vertex (4, 40) on the flat, the crest is (15 - 4) cells east, 11 * 20 / sin(az) metres away along
            // the azimuth, as long as the line reaches it inside the grid.
            const double dist = 11.0 * cx / std::sin(a);
            const double expected = deg(40.0 / dist);
            CHECK(deg(horizonTangent(g, 4, 40, std::sin(a), std::cos(a), method)) == Approx(expected).margin(1e-9));
            // From the crest's foot on the far side, looking back west over it.
            const double back = (az + 180.0) * kPiHere / 180.0;
            CHECK(deg(horizonTangent(g, 26, 40, std::sin(back), std::cos(back), method)) ==
                  Approx(deg(40.0 / (11.0 * cx / std::sin(a)))).margin(1e-9));
        }
        // Looking away from the ridge over flat ground, the horizon is flat; off the grid's west edge there is none.
        CHECK(horizonTangent(g, 4, 40, -1.0, 0.3, method) == 0.0);
        CHECK(horizonTangent(g, 0, 40, -1.0, 0.0, method) == -std::numeric_limits<double>::infinity());
        // Up the face from its foot, along the axis: the face's own slope (8 m per 20 m), seen at the start.
        CHECK(horizonTangent(g, 10, 40, 1.0, 0.0, method) == Approx(0.4).epsilon(1e-12));
        // A search radius short of the crest sees only the face below it: from x = 4, 8 cells east is 16 m high.
        HorizonSearch near;
        near.maxDistanceM = 8.0 * cx;
        CHECK(horizonTangent(g, 4, 40, 1.0, 0.0, method, near) == Approx(16.0 / (8.0 * cx)).epsilon(1e-12));
        // Curvature lowers the crest by k d^2 (the slope to the face, 0.4 - 48 / d - k d, still grows up to it).
        HorizonSearch curved;
        curved.dropPerSquareM = 1e-4;
        CHECK(horizonTangent(g, 4, 40, 1.0, 0.0, method, curved) ==
              Approx((40.0 - 1e-4 * 220.0 * 220.0) / 220.0).epsilon(1e-12));
    }
}

TEST_CASE("Horizon walk: the exact supremum of a dense march over fractal terrain with holes", "[heightfield][horizon]") {
    // 33 x 33 vertices of rugged terrain, cells of 30 x 21 m, with nodata patches: lines run over holes, along
    // grid lines beside them and through vertices between them.
    std::mt19937_64 rng(11);
    const HeightGrid g = holedFractal(rng);
    std::uniform_int_distribution<int64_t> I(0, 32);
    std::uniform_real_distribution<double> A(0.0, 360.0);
    HorizonSearch far, near, curved, raised;
    near.maxDistanceM = 250.0;
    curved.dropPerSquareM = 0.02;  // strong enough to bend within the grid
    raised.dropPerSquareM = -0.02;  // far points raised, as the terrain turned upside down sees the curvature
    int64_t compared = 0;
    double worst = 0.0;
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
        const bool triangles = method == CellMethod::Triangles;
        for (int k = 0; k < 90; ++k) {
            int64_t i = I(rng), j = I(rng);
            // The axes and the cells' diagonal (21 / 30) besides random azimuths.
            const double azimuths[] = {0.0, 90.0, 180.0, 270.0, std::atan2(30.0, 21.0) * 180.0 / kPiHere, A(rng)};
            const double az = azimuths[k % 6];
            bool onSurface = false;
            for (int64_t b = j - 1; b <= j; ++b)
                for (int64_t a = i - 1; a <= i; ++a)
                    onSurface = onSurface || (a >= 0 && b >= 0 && a < 32 && b < 32 && g.cellValid(a, b));
            if (!onSurface) continue;
            const double dx = std::sin(az * kPiHere / 180.0), dy = std::cos(az * kPiHere / 180.0);
            for (const HorizonSearch* s : {&far, &near, &curved, &raised}) {
                const double walk = horizonTangent(g, i, j, dx, dy, method, *s);
                const double march = marchTangent(g, i, j, dx, dy, triangles, *s);
                INFO(cellMethodName(method) << " vertex " << i << "," << j << " azimuth " << az << " radius "
                                            << s->maxDistanceM << " drop " << s->dropPerSquareM);
                if (std::isinf(march)) {
                    CHECK(walk == march);
                    continue;
                }
                // The march is a lower bound (up to the rounding of h - z0 over its first, micro-cell steps) and
                // comes within 1e-4 degrees of the supremum.
                CHECK(deg(walk) >= deg(march) - 1e-6);
                CHECK(deg(walk) - deg(march) < 1e-4);
                worst = std::max(worst, deg(walk) - deg(march));
                ++compared;
            }
        }
    }
    INFO(compared << " compared, worst " << worst << " degrees");
    CHECK(compared > 400);
}

TEST_CASE("Horizon walk: a hint changes the work and not the answer, and the distance names the horizon point",
          "[heightfield][horizon]") {
    const HeightGrid g = fractalTerrain({.size = 65, .seed = 9, .cellSizeM = 25.0, .offsetAt1KmM = 400.0});
    std::mt19937_64 rng(3);
    std::uniform_int_distribution<int64_t> I(0, 64);
    std::uniform_real_distribution<double> A(0.0, 360.0), H(0.0, 1800.0);
    int64_t hinted = 0;
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles})
        for (int k = 0; k < 400; ++k) {
            const int64_t i = I(rng), j = I(rng);
            const double az = A(rng) * kPiHere / 180.0, dx = std::sin(az), dy = std::cos(az);
            HorizonCounters plain;
            const HorizonPoint exact = horizonPoint(g, i, j, dx, dy, method, {}, 0.0, &plain);
            // Any hint: far off, near the horizon point, on it, or next to the vertex (where h - z0 is mostly rounding).
            for (double hint : {H(rng), exact.distanceM * 1.01, exact.distanceM, 3e-14, 1e-4, 0.03}) {
                HorizonCounters helped;
                const HorizonPoint p = horizonPoint(g, i, j, dx, dy, method, {}, hint, &helped);
                INFO(cellMethodName(method) << " vertex " << i << "," << j << " azimuth " << az << " hint " << hint);
                CHECK(p.tangent == Approx(exact.tangent).epsilon(1e-12).margin(1e-15));
                if (hint == exact.distanceM) hinted += helped.cellsVisited < plain.cellsVisited;
            }
            if (std::isinf(exact.tangent) || exact.distanceM == 0.0) continue;
            // The surface at the returned distance has exactly that slope.
            const double u = double(i) + exact.distanceM * dx / g.cellSizeXM(), v = double(j) + exact.distanceM * dy / g.cellSizeYM();
            const double h = surfaceAt(g, std::clamp(u, 0.0, 64.0), std::clamp(v, 0.0, 64.0), method == CellMethod::Triangles);
            CHECK((h - g.at(i, j)) / exact.distanceM == Approx(exact.tangent).epsilon(1e-9).margin(1e-12));
        }
    CHECK(hinted > 100);  // a hint at the horizon point saves cells
}

TEST_CASE("Horizon walk from an observer above the surface: the supremum of a dense march", "[heightfield][horizon]") {
    // Eyes anywhere over the grid (inside cells, on grid lines, at vertices, over holes), 0 to 60 m above the
    // surface or at a set height, looking along random azimuths and the axes, with and without a radius.
    std::mt19937_64 rng(23);
    const HeightGrid g = holedFractal(rng);
    std::uniform_real_distribution<double> X(0.0, 32.0), A(0.0, 360.0), H(0.0, 60.0);
    std::uniform_int_distribution<int> I(0, 32);
    HorizonSearch far, near, curved;
    near.maxDistanceM = 137.0;
    curved.dropPerSquareM = 0.01;
    int64_t compared = 0;
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
        const bool triangles = method == CellMethod::Triangles;
        for (int k = 0; k < 60; ++k) {
            double x = X(rng), y = X(rng);
            if (k % 5 == 1) x = double(I(rng));                // on a north-south grid line
            if (k % 5 == 2) y = double(I(rng));                // on an east-west one
            if (k % 5 == 3) x = double(I(rng)), y = double(I(rng));  // at a vertex
            const bool alongColumn = k % 10 == 9;
            if (alongColumn) {
                // Inside a column of cells that holds a hole, south of it, looking north along the column.
                bool found = false;
                for (int64_t cj = 2; cj < 32 && !found; ++cj)
                    for (int64_t ci = 1; ci < 32 && !found; ++ci)
                        if (!g.cellValid(ci, cj) && g.cellValid(ci - 1, cj) && g.cellValid(ci, cj - 2)) {
                            x = double(ci) + 0.3, y = double(cj) - 1.5;
                            found = true;
                        }
                REQUIRE(found);
            }
            const double ground = surfaceAt(g, x, y, triangles);
            const double z = std::isnan(ground) ? 400.0 : ground + (k % 3 == 0 ? 1.7 : H(rng));
            const double azimuths[] = {0.0, 90.0, 180.0, 270.0, A(rng), A(rng)};
            const double az = alongColumn ? 0.0 : azimuths[k % 6];
            const double dx = std::sin(az * kPiHere / 180.0), dy = std::cos(az * kPiHere / 180.0);
            for (const HorizonSearch* s : {&far, &near, &curved}) {
                const double walk = horizonTangentFrom(g, x * 30.0, y * 21.0, z, dx, dy, method, *s);
                const double march = marchTangentFrom(g, x, y, z, dx, dy, triangles, *s);
                INFO(cellMethodName(method) << " eye " << x << "," << y << " at " << z << " m, azimuth " << az
                                            << " radius " << s->maxDistanceM << " drop " << s->dropPerSquareM);
                if (std::isinf(march)) {
                    CHECK(walk == march);
                    continue;
                }
                CHECK(deg(walk) >= deg(march) - 1e-6);
                CHECK(deg(walk) - deg(march) < 1e-4);
                ++compared;
            }
        }
    }
    CHECK(compared > 250);
}
