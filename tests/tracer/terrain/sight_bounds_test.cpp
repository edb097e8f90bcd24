// The slope bounds around an eye (tracer/terrain/sight_bounds.h) against the surface itself, sampled densely
// along sight lines; and the viewshed they speed up against walking every sight line whole.
#include "heightfield/fractal_terrain.h"
#include "heightfield/horizon.h"
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "tracer/terrain/maps.h"
#include "tracer/terrain/sight_bounds.h"

#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

using namespace terracast;
using terracast::testing::kSweepDivisor;

namespace {

// The bilinear surface's height at (x, y) metres, or NaN over a hole or outside the grid.
double surfaceAt(const HeightGrid& g, double x, double y) {
    const double fx = x / g.cellSizeXM(), fy = y / g.cellSizeYM();
    const int64_t i = std::clamp<int64_t>(int64_t(std::floor(fx)), 0, g.cellsX() - 1);
    const int64_t j = std::clamp<int64_t>(int64_t(std::floor(fy)), 0, g.cellsY() - 1);
    if (fx < 0.0 || fy < 0.0 || fx > double(g.cellsX()) || fy > double(g.cellsY()) || !g.cellValid(i, j))
        return std::numeric_limits<double>::quiet_NaN();
    const double u = fx - double(i), v = fy - double(j);
    return (g.at(i, j) * (1.0 - u) + g.at(i + 1, j) * u) * (1.0 - v) + (g.at(i, j + 1) * (1.0 - u) + g.at(i + 1, j + 1) * u) * v;
}

struct Checked {
    int64_t lines = 0, clearFar = 0, surelyKnown = 0;
};

// Sight lines from an eye `above` metres over the surface at (ex, ey) to random valid vertices: every stretch
// the bounds call clear is above the surface by the tolerance at every sample (1/64 of a cell apart), and every
// slope they say the surface reaches is reached by a sample.
Checked checkAgainstSamples(const HeightGrid& g, double ex, double ey, double above, uint32_t seed) {
    const double ez = surfaceAt(g, ex, ey) + above;
    REQUIRE(std::isfinite(ez));
    const double tolerance = 4.0 * grazingToleranceM(g);
    const SightBounds bounds(g, {ex, ey, ez}, tolerance, true, 2);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int64_t> pickI(0, g.width() - 1), pickJ(0, g.height() - 1);
    const double step = std::min(g.cellSizeXM(), g.cellSizeYM()) / 64.0;
    Checked c;
    while (c.lines < 300 / kSweepDivisor) {
        const int64_t i = pickI(rng), j = pickJ(rng);
        if (!g.vertexValid(i, j)) continue;
        const double dx = double(i) * g.cellSizeXM() - ex, dy = double(j) * g.cellSizeYM() - ey;
        const double reach = std::hypot(dx, dy);
        if (reach < 3.0 * step) continue;
        ++c.lines;
        const double ux = dx / reach, uy = dy / reach, slope = (double(g.at(i, j)) - ez) / reach;
        const double key = SightBounds::azimuthKey(dx, dy);
        const double clear = bounds.clearBefore(key, slope), surely = bounds.surelySlopeBefore(key, reach);
        // The most the samples rise above the line (minus the tolerance) before `clear`, and the steepest slope
        // s(P) = (z(P) - tolerance - z_eye) / |P - eye| they reach before the target, the best sample refined
        // 4096 times finer around it.
        const auto slopeAt = [&](double s) {
            const double z = surfaceAt(g, ex + s * ux, ey + s * uy);
            return std::isnan(z) ? -std::numeric_limits<double>::infinity() : (z - tolerance - ez) / s;
        };
        double worst = -std::numeric_limits<double>::infinity(), steepest = worst, best = 0.0;
        for (double s = step; s < reach; s += step) {
            const double z = surfaceAt(g, ex + s * ux, ey + s * uy);
            if (std::isnan(z)) continue;
            if (s < clear) worst = std::max(worst, z + tolerance - (ez + slope * s));
            if (slopeAt(s) > steepest) {
                steepest = slopeAt(s);
                best = s;
            }
        }
        for (double s = std::max(step / 4096.0, best - step); s < std::min(reach, best + step); s += step / 4096.0)
            steepest = std::max(steepest, slopeAt(s));
        INFO("eye (" << ex << ", " << ey << ", " << ez << ") target vertex (" << i << ", " << j << ") clear "
                     << clear << " m of " << reach << ", surely " << surely << " line " << slope);
        CHECK(worst < 0.0);
        if (surely > -std::numeric_limits<double>::infinity()) {
            CHECK(steepest >= surely - 1e-9 * std::abs(surely));
            ++c.surelyKnown;
        }
        c.clearFar += clear > 0.5 * reach;
    }
    return c;
}

}  // namespace

TEST_CASE("Sight bounds never claim more than the surface allows, along lines from eyes on real and fractal "
          "terrain",
          "[tracer][maps]") {
    const std::string samples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
    FractalTerrainOptions fo;
    fo.size = 129;
    fo.seed = 7;
    const HeightGrid fractal = fractalTerrain(fo);
    const LoadedDem helens = loadDem(samples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    const LoadedDem nice = loadDem(samples + "srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif");
    // A tilted plane, where the cells' corner bounds are nearly the surface itself.
    std::vector<float> tilted(size_t(65 * 65));
    for (int64_t j = 0; j < 65; ++j)
        for (int64_t i = 0; i < 65; ++i) tilted[size_t(j * 65 + i)] = float(100.0 + 3.0 * double(i) - 1.5 * double(j));
    const HeightGrid plane(65, 65, 30.0, 30.0, std::move(tilted));
    // A level plane, where they are exact but for the lines' distances.
    const HeightGrid level(65, 97, 20.0, 30.0, std::vector<float>(size_t(65 * 97), 250.0f));
    uint32_t seed = 1;
    Checked total;
    for (const HeightGrid* g : {&level, &plane, &fractal, &helens.grid, &nice.grid}) {
        // The highest and the lowest vertex (a summit, a valley with the surface above the eye all round), and a
        // point inside a cell; 2 m and 60 m up.
        int64_t top = -1, low = -1;
        for (int64_t k = 0; k < g->width() * g->height(); ++k) {
            const int64_t i = k % g->width(), j = k / g->width();
            if (!g->vertexValid(i, j)) continue;
            if (top < 0 || g->at(i, j) > g->at(top % g->width(), top / g->width())) top = k;
            if (low < 0 || g->at(i, j) < g->at(low % g->width(), low / g->width())) low = k;
        }
        const auto place = [g](int64_t k) {
            return std::pair{double(k % g->width()) * g->cellSizeXM(), double(k / g->width()) * g->cellSizeYM()};
        };
        for (const auto& [x, y] : {place(top), place(low), std::pair{0.43 * g->extentXM() + 0.3 * g->cellSizeXM(),
                                                                      0.57 * g->extentYM() + 0.6 * g->cellSizeYM()}}) {
            if (std::isnan(surfaceAt(*g, x, y))) continue;
            for (double above : {2.0, 60.0}) {
                const Checked c = checkAgainstSamples(*g, x, y, above, seed++);
                total.lines += c.lines;
                total.clearFar += c.clearFar;
                total.surelyKnown += c.surelyKnown;
            }
        }
    }
    // The bounds must also say something: most lines are clear for a good part of their way, or surely hidden.
    INFO(total.lines << " lines: clear over half their way " << total.clearFar << ", surely reaching a slope "
                     << total.surelyKnown);
    CHECK(total.lines >= 7000 / kSweepDivisor);
    CHECK(total.clearFar > total.lines / 5);
    CHECK(total.surelyKnown > total.lines / 2);
}

TEST_CASE("Viewsheds settled by the sight bounds equal walking every sight line whole", "[tracer][maps]") {
    const std::string samples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
    const auto same = [](const MapRaster& a, const MapRaster& b) {
        REQUIRE(a.values.size() == b.values.size());
        int64_t differ = 0, seen = 0;
        for (size_t k = 0; k < a.values.size(); ++k) {
            const float x = a.values[k], y = b.values[k];
            differ += !(x == y || (std::isnan(x) && std::isnan(y)));
            seen += x == 1.0f || (!std::isnan(x) && x != 0.0f);
        }
        return std::pair{differ, seen};
    };
    struct Case {
        const char* file;
        double x, y, above, curvature;  // observer at (x, y) of the extent
        CellMethod method;
        ViewshedValues values;
    };
    for (const Case& c : {Case{"usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", 0.5, 0.55, 1.7, 0.85714,
                               CellMethod::Bilinear, ViewshedValues::Visible},
                          Case{"usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif", 0.2, 0.8, 25.0, 0.0,
                               CellMethod::Triangles, ViewshedValues::Angle},
                          Case{"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", 0.37, 0.61, 10.0, 0.85714,
                               CellMethod::Bilinear, ViewshedValues::Angle},
                          Case{"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", 0.8, 0.1, 1.7, 0.0,
                               CellMethod::Triangles, ViewshedValues::Visible},
                          Case{"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", 0.5, 0.5, 3.0, 0.85714,
                               CellMethod::Nearest, ViewshedValues::Visible},
                          Case{"srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif", 0.4, 0.6, 30.0, 0.85714,
                               CellMethod::BilinearDouble, ViewshedValues::Angle},
                          Case{"N44W072.srtm3-white-mountains-nh.hgt", 0.6967, 0.2706, 1.7, 0.85714,
                               CellMethod::Bilinear, ViewshedValues::Visible}}) {
        const LoadedDem dem = loadDem(samples + c.file);
        const HeightGrid& g = dem.grid;
        ViewshedSettings s;
        s.observerXM = c.x * g.extentXM();
        s.observerYM = c.y * g.extentYM();
        s.observerHeightM = c.above;
        s.curvatureCoeff = c.curvature;
        s.method = c.method;
        s.values = c.values;
        const MapRaster bounded = viewshed(g, s);
        s.boundSightLines = false;
        const MapRaster walked = viewshed(g, s);
        const auto [differ, seen] = same(bounded, walked);
        INFO(c.file << " observer at " << c.x << ", " << c.y << ": " << seen << " of " << walked.values.size()
                    << " vertices seen");
        CHECK(differ == 0);
        CHECK(seen > 1000);
        CHECK(seen < int64_t(walked.values.size()) - 1000);
    }
}

namespace {

// Each vertex's verdict by the occlusion walk of its whole sight line, as the viewshed defines it: from the eye
// `s.observerHeightM` above the surface (of the grid lowered for the curved earth) to a hundredth of a cell short
// of the target.
std::vector<float> wholeWalks(const HeightGrid& grid, const ViewshedSettings& s) {
    const HeightGrid* g = &grid;
    HeightGrid curved;
    if (s.curvatureCoeff != 0.0) {
        HeightTransform t;
        t.curvatureCoeff = s.curvatureCoeff;
        t.earthRadiusM = s.earthRadiusM;
        t.observerXM = s.observerXM;
        t.observerYM = s.observerYM;
        curved = grid.transformed(t);
        g = &curved;
    }
    const glm::dvec3 eye = surfacePointAt(*g, s.observerXM, s.observerYM, s.method)->pointM +
                           glm::dvec3(0.0, 0.0, s.observerHeightM);
    const double endGap = 0.01 * std::min(g->cellSizeXM(), g->cellSizeYM());
    std::vector<float> out(size_t(g->width() * g->height()), std::numeric_limits<float>::quiet_NaN());
    for (int64_t j = 0; j < g->height(); ++j)
        for (int64_t i = 0; i < g->width(); ++i) {
            if (!g->vertexValid(i, j)) continue;
            const glm::dvec3 d =
                glm::dvec3(double(i) * g->cellSizeXM(), double(j) * g->cellSizeYM(), g->at(i, j) + s.targetHeightM) - eye;
            const double len = glm::length(d);
            out[size_t(j * g->width() + i)] =
                len <= endGap || !occluded(*g, Ray{eye, d}, {0.0, 1.0 - endGap / len}, s.method) ? 1.0f : 0.0f;
        }
    return out;
}

int64_t differences(const std::vector<float>& a, const std::vector<float>& b) {
    int64_t n = 0;
    for (size_t k = 0; k < a.size(); ++k) n += !(a[k] == b[k] || (std::isnan(a[k]) && std::isnan(b[k])));
    return n;
}

}  // namespace

TEST_CASE("Viewsheds with sight bounds equal whole walks: a high corner in the row where a task's rings end",
          "[tracer][maps]") {
    // An eye on a vertex puts rows of cells exactly at ring boundaries. One such row holds the only corner above
    // the eye (a spike), with a row of holes beyond it so that no neighbouring cell carries that corner: its
    // upper bound must land in its ring whichever task fills which rings.
    for (int64_t row : {24, 23, 20}) {
        const int64_t w = 101, je = 100, h = je + 61;
        std::vector<float> z(size_t(w * h), 0.0f);
        std::vector<uint8_t> valid(size_t(w * h), 1);
        z[size_t((je + row + 1) * w + 50)] = 5000.0f;
        for (int64_t i = 0; i < w; ++i) valid[size_t((je + row + 2) * w + i)] = 0;
        const HeightGrid g(w, h, 10.0, 10.0, std::move(z), std::move(valid));
        for (CellMethod m : {CellMethod::Bilinear, CellMethod::Triangles, CellMethod::Nearest}) {
            ViewshedSettings s;
            s.observerXM = 500.0;
            s.observerYM = double(je) * 10.0;
            s.observerHeightM = 2.0;
            s.curvatureCoeff = 0.0;
            s.method = m;
            const MapRaster bounded = viewshed(g, s);
            INFO("spike row " << row << ", " << cellMethodName(m));
            CHECK(differences(bounded.values, wholeWalks(g, s)) == 0);
        }
    }
}

TEST_CASE("Viewsheds with and without sight bounds equal whole walks: random grids, holes, eyes on vertices, grid "
          "lines and edges, every method",
          "[tracer][maps]") {
    std::mt19937 rng(20261129);
    const auto real = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const auto pick = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
    int64_t cases = 0, hiddenSeen = 0, visibleSeen = 0;
    for (int it = 0; it < 120; ++it) {
        const int64_t w = pick(20, 180), h = pick(2, 180);
        const double cx = pick(0, 1) ? 10.0 : real(1.0, 40.0), cy = pick(0, 2) ? cx : real(1.0, 40.0);
        std::vector<float> z(size_t(w * h));
        const int kind = pick(0, 3);
        for (int64_t j = 0; j < h; ++j)
            for (int64_t i = 0; i < w; ++i)
                z[size_t(j * w + i)] = float(kind == 0   ? real(0.0, 50.0)
                                             : kind == 1 ? 30.0 * std::sin(double(i) * 0.3) * std::cos(double(j) * 0.2) + real(0.0, 5.0)
                                             : kind == 2 ? (pick(0, 20) == 0 ? real(0.0, 500.0) : 0.0)
                                                         : std::round(real(0.0, 3.0)) * 10.0);
        std::vector<uint8_t> valid;
        if (pick(0, 1)) {
            valid.assign(size_t(w * h), 1);
            for (int k = pick(0, 4); k > 0; --k) {
                const int64_t i0 = pick(0, int(w) - 1), j0 = pick(0, int(h) - 1), hw = pick(1, 6), hh = pick(1, 6);
                for (int64_t j = j0; j < std::min(h, j0 + hh); ++j)
                    for (int64_t i = i0; i < std::min(w, i0 + hw); ++i) valid[size_t(j * w + i)] = 0;
            }
            if (pick(0, 2) == 0) {
                const int64_t j = pick(0, int(h) - 1);
                for (int64_t i = 0; i < w; ++i) valid[size_t(j * w + i)] = 0;
            }
        }
        HeightGrid g;
        try {
            g = HeightGrid(w, h, cx, cy, std::move(z), std::move(valid));
        } catch (const GridError&) {
            continue;  // every vertex a hole
        }
        // Anywhere, on a vertex, on a horizontal grid line, or on the grid's south or north edge.
        ViewshedSettings s;
        const int where = pick(0, 4);
        s.observerXM = where == 1 ? double(pick(0, int(w) - 1)) * cx : real(0.0, g.extentXM());
        s.observerYM = where == 0   ? real(0.0, g.extentYM())
                       : where == 3 ? 0.0
                       : where == 4 ? g.extentYM()
                                    : double(pick(0, int(h) - 1)) * cy;
        s.observerHeightM = pick(0, 1) ? real(0.0, 3.0) : real(0.0, 200.0);
        s.curvatureCoeff = pick(0, 1) ? 0.0 : 0.85714;
        s.method = std::array{CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Triangles,
                              CellMethod::Nearest}[size_t(pick(0, 3))];
        s.targetHeightM = pick(0, 1) ? 0.0 : real(0.0, 5.0);
        MapRaster bounded;
        try {
            bounded = viewshed(g, s);
        } catch (const GridError&) {
            continue;  // the observer over a hole
        }
        const std::vector<float> walked = wholeWalks(g, s);
        ViewshedSettings unbounded = s;
        unbounded.boundSightLines = false;
        const MapRaster plain = viewshed(g, unbounded);
        INFO("case " << it << ": " << w << " x " << h << " cells of " << cx << " x " << cy << " m, eye at "
                     << s.observerXM << ", " << s.observerYM << " + " << s.observerHeightM << " m, "
                     << cellMethodName(s.method) << ", curvature " << s.curvatureCoeff);
        CHECK(differences(bounded.values, walked) == 0);
        CHECK(differences(plain.values, walked) == 0);
        ++cases;
        hiddenSeen += std::count(walked.begin(), walked.end(), 0.0f) > 0;
        visibleSeen += std::count(walked.begin(), walked.end(), 1.0f) > 1;
    }
    CHECK(cases > 90);
    CHECK(hiddenSeen > cases / 2);
    CHECK(visibleSeen > cases / 2);
}

namespace {

// A random grid and observer from one seed, drawn in a fixed order (the grid 200 to 600 cells wide, holes,
// non-square cells, eyes anywhere or on vertices and grid lines, all four methods).
void seededCase(uint32_t seed, HeightGrid& g, ViewshedSettings& s) {
    std::mt19937 rng(seed);
    const auto real = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
    const auto pick = [&](int a, int b) { return std::uniform_int_distribution<int>(a, b)(rng); };
    const int64_t w = pick(200, 600), h = pick(2, 600);
    const double cx = pick(0, 1) ? 10.0 : real(1.0, 40.0), cy = pick(0, 2) ? cx : real(1.0, 40.0);
    std::vector<float> z(size_t(w * h));
    const int kind = pick(0, 3);
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) {
            const double v = kind == 0   ? real(0.0, 50.0)
                             : kind == 1 ? 30.0 * std::sin(double(i) * 0.3) * std::cos(double(j) * 0.2) + real(0.0, 5.0)
                             : kind == 2 ? (pick(0, 20) == 0 ? real(0.0, 500.0) : 0.0)
                                         : std::round(real(0.0, 3.0)) * 10.0;
            z[size_t(j * w + i)] = float(v);
        }
    std::vector<uint8_t> valid;
    if (pick(0, 1)) {
        valid.assign(size_t(w * h), 1);
        const int holes = pick(0, 4);
        for (int k = 0; k < holes; ++k) {
            const int64_t i0 = pick(0, int(w) - 1), j0 = pick(0, int(h) - 1), hw = pick(1, 6), hh = pick(1, 6);
            for (int64_t j = j0; j < std::min(h, j0 + hh); ++j)
                for (int64_t i = i0; i < std::min(w, i0 + hw); ++i) valid[size_t(j * w + i)] = 0;
        }
        if (pick(0, 2) == 0) {
            const int64_t j = pick(0, int(h) - 1);
            for (int64_t i = 0; i < w; ++i) valid[size_t(j * w + i)] = 0;
        }
    }
    g = HeightGrid(w, h, cx, cy, std::move(z), std::move(valid));
    const int where = pick(0, 3);
    double ex = where == 0 ? real(0.0, g.extentXM()) : double(pick(0, int(w) - 1)) * cx;
    const double ey = where <= 1 ? (where == 0 ? real(0.0, g.extentYM()) : double(pick(0, int(h) - 1)) * cy)
                                 : double(pick(0, int(h) - 1)) * cy;
    if (where == 3) ex = real(0.0, g.extentXM());
    s.observerXM = ex;
    s.observerYM = ey;
    s.observerHeightM = pick(0, 1) ? real(0.0, 3.0) : real(0.0, 200.0);
    s.curvatureCoeff = pick(0, 1) ? 0.0 : 0.85714;
    s.method = std::array{CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Triangles,
                          CellMethod::Nearest}[size_t(pick(0, 3))];
    pick(0, 1);  // a draw the search spent on the kind of values; the verdicts are what is compared
    s.targetHeightM = pick(0, 1) ? 0.0 : real(0.0, 5.0);
}

}  // namespace

TEST_CASE("Viewsheds of nearest squares equal whole walks with and without sight bounds, where a walk started "
          "inside a cell would ask the bilinear surface",
          "[tracer][maps]") {
    // Seeds found by a longer random search in which the last-cells-first walk (a walk started inside a cell)
    // called a vertex hidden that the whole walk sees.
    for (uint32_t seed : {500112u, 500116u, 500214u, 500263u}) {
        HeightGrid g;
        ViewshedSettings s;
        seededCase(seed, g, s);
        REQUIRE(s.method == CellMethod::Nearest);
        const std::vector<float> walked = wholeWalks(g, s);
        const MapRaster bounded = viewshed(g, s);
        s.boundSightLines = false;
        const MapRaster plain = viewshed(g, s);
        INFO("seed " << seed);
        CHECK(differences(bounded.values, walked) == 0);
        CHECK(differences(plain.values, walked) == 0);
    }
}
