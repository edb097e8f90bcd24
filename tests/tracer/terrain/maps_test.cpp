// Map products: shadow masks against horizon angles, viewsheds on hand-made DEMs, and the map view against
// analytic shading.
#include "loaders/dem_loader.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/maps.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

namespace {
constexpr double kDeg = M_PI / 180.0;
}

TEST_CASE("Shadow mask agrees with the horizon raster", "[tracer][maps]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    const HeightGrid& g = dem.grid;
    std::vector<int64_t> shadowedAt;
    for (double sunElevationDeg : {8.0, 20.0}) {
        const double az = 250.0 * kDeg, el = sunElevationDeg * kDeg;
        const MapRaster mask = shadowMask(g, az, el, CellMethod::Bilinear);
        const MapRaster horizon = horizonMap(g, az, CellMethod::Bilinear);
        REQUIRE(mask.values.size() == horizon.values.size());
        int64_t compared = 0, mismatched = 0, shadowed = 0, ties = 0;
        for (size_t k = 0; k < mask.values.size(); ++k) {
            const float m = mask.values[k], hDeg = horizon.values[k];
            REQUIRE(std::isnan(m) == std::isnan(hDeg));
            if (std::isnan(m)) continue;
            if (std::abs(hDeg * kDeg - el) < 1e-6) {
                ++ties;
                continue;
            }
            ++compared;
            const bool lit = el > hDeg * kDeg;
            mismatched += lit != (m == 0.0f);
            shadowed += m == 1.0f;
        }
        INFO("sun at " << sunElevationDeg << " degrees: " << compared << " vertices, " << shadowed << " shadowed, "
                       << ties << " ties");
        CHECK(mismatched == 0);
        CHECK(compared > 10000);
        CHECK(shadowed > 100);       // the test means something: some vertices are in shadow
        CHECK(shadowed < compared);  // and some are lit
        shadowedAt.push_back(shadowed);
    }
    CHECK(shadowedAt[0] > shadowedAt[1]);  // a lower sun casts more shadow
}

TEST_CASE("A soft sun gives partial shadow between the hard mask's values", "[tracer][maps]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    const MapRaster soft = shadowMask(dem.grid, 250.0 * kDeg, 8.0 * kDeg, CellMethod::Bilinear, 2.0 * kDeg, 16);
    int64_t partial = 0;
    for (float v : soft.values)
        if (!std::isnan(v)) {
            REQUIRE(v >= 0.0f);
            REQUIRE(v <= 1.0f);
            partial += v > 0.0f && v < 1.0f;
        }
    CHECK(partial > 50);
}

TEST_CASE("Viewshed: a wall hides exactly what lies behind it, and flat ground is all visible", "[tracer][maps]") {
    // 41 x 21 vertices at 10 m on flat ground; a wall 50 m high along vertex column 20.
    const int64_t w = 41, h = 21;
    std::vector<float> z(size_t(w * h), 0.0f);
    for (int64_t j = 0; j < h; ++j) z[size_t(j * w + 20)] = 50.0f;
    const HeightGrid walled(w, h, 10.0, 10.0, z);
    ViewshedSettings s;
    s.observerXM = 55.0;
    s.observerYM = 100.0;
    s.observerHeightM = 2.0;
    s.curvatureCoeff = 0.0;
    const MapRaster vis = viewshed(walled, s);
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) {
            INFO("vertex " << i << ", " << j);
            CHECK(vis.values[size_t(j * w + i)] == (i <= 20 ? 1.0f : 0.0f));
        }
    // The observer's own cell is visible.
    CHECK(vis.values[size_t(10 * w + 5)] == 1.0f);
    CHECK(vis.values[size_t(10 * w + 6)] == 1.0f);
    // Flat ground with flat-earth settings: everything visible.
    const HeightGrid flat(w, h, 10.0, 10.0, std::vector<float>(size_t(w * h), 100.0f));
    const MapRaster all = viewshed(flat, s);
    for (float v : all.values) CHECK(v == 1.0f);
    // With curvature, far low targets on a large flat DEM drop below the horizon (a 2 m observer sees the
    // ground to about 5 km); near ones stay visible.
    const HeightGrid wide(401, 3, 50.0, 50.0, std::vector<float>(401 * 3, 0.0f));
    ViewshedSettings c = s;
    c.observerXM = 0.0;
    c.observerYM = 50.0;
    c.curvatureCoeff = 0.85714;
    const MapRaster curved = viewshed(wide, c);
    CHECK(curved.values[size_t(1 * 401 + 20)] == 1.0f);   // 1 km
    CHECK(curved.values[size_t(1 * 401 + 400)] == 0.0f);  // 20 km
    // The ground lowered by k d^2 / (2 R) is concave, so a target on it at distance D is seen exactly while the
    // drop there, k D^2 / (2 R), stays under the eye's height: D = sqrt(2 R h / k), 5456 m for h = 2 m.
    const double horizonM = std::sqrt(2.0 * c.earthRadiusM * c.observerHeightM / c.curvatureCoeff);
    REQUIRE(horizonM == Approx(5456.0).margin(1.0));
    for (int64_t i = 100; i <= 120; ++i) {
        const double d = 50.0 * double(i);
        if (std::abs(d - horizonM) < 60.0) continue;  // within about a cell of the horizon: the grazing zone
        INFO("target " << d << " m away, horizon " << horizonM << " m");
        CHECK(curved.values[size_t(1 * 401 + i)] == (d < horizonM ? 1.0f : 0.0f));
    }
    // An observer off the grid is refused.
    ViewshedSettings off = s;
    off.observerXM = -500.0;
    CHECK_THROWS_AS(viewshed(flat, off), GridError);
}

TEST_CASE("Viewshed heights and angles: a ridge asks targets behind it for the height similar triangles give",
          "[tracer][maps]") {
    // Flat ground at 0 m with an east-west ridge: vertex row 10 at 100 m (flanks over one cell), cells of 10 m.
    // The eye 1.7 m above vertex (30, 40). A target at row j < 10 lies D metres away; the sight line crosses the
    // crest at the share (40 - 10) / (40 - j) of D, so a target there needs (100 - 1.7) (40 - j) / 30 + 1.7 m.
    const int64_t w = 61, h = 81;
    std::vector<float> z(size_t(w * h), 0.0f);
    for (int64_t i = 0; i < w; ++i) z[size_t(10 * w + i)] = 100.0f;
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
        const HeightGrid g(w, h, 10.0, 10.0, z);
        ViewshedSettings s;
        s.observerXM = 300.0;
        s.observerYM = 400.0;
        s.observerHeightM = 1.7;
        s.curvatureCoeff = 0.0;
        s.method = method;
        s.values = ViewshedValues::Height;
        const MapRaster need = viewshed(g, s);
        s.values = ViewshedValues::Angle;
        const MapRaster angle = viewshed(g, s);
        for (int64_t j = 0; j < h; ++j)
            for (int64_t i = 0; i < w; i += 7) {
                INFO(cellMethodName(method) << " vertex " << i << ", " << j);
                if (j < 9) {
                    CHECK(need.at(i, j) == Approx((100.0 - 1.7) * double(40 - j) / 30.0 + 1.7).epsilon(1e-6));
                    CHECK(std::isnan(angle.at(i, j)));
                } else if (j > 10) {
                    // In front of the ridge (and on its north flank, which faces the eye) the ground is seen.
                    CHECK(need.at(i, j) == 0.0f);
                    const double dx = double(i) * 10.0 - 300.0, dy = double(j) * 10.0 - 400.0;
                    const double expected = std::atan2(double(z[size_t(j * w + i)]) - 1.7, std::hypot(dx, dy)) / kDeg;
                    if (std::hypot(dx, dy) > 0.0) CHECK(angle.at(i, j) == Approx(expected).margin(1e-4));
                }
            }
        // On the crest itself the ground is seen, up at 100 m.
        CHECK(need.at(30, 10) == 0.0f);
        CHECK(angle.at(30, 10) == Approx(std::atan2(98.3, 300.0) / kDeg).margin(1e-4));
        // Beyond --max-distance: no value.
        s.values = ViewshedValues::Height;
        s.maxDistanceM = 250.0;
        const MapRaster near = viewshed(g, s);
        CHECK(std::isnan(near.at(30, 5)));
        CHECK(near.at(30, 20) == 0.0f);
    }
}

TEST_CASE("Viewshed: the height a target needs agrees with the sight lines at every vertex of real DEMs",
          "[tracer][maps]") {
    // Two independent computations: the occlusion walk of each sight line to a target 0 and 5 m up, and the
    // horizon walk from the eye that gives the height needed. They must agree wherever that height is not within
    // a centimetre above the target's (where the sight line grazes the terrain and either verdict is right). The
    // ground that is seen needs 0 exactly: the walk's supremum includes the target itself.
    for (const char* name : {"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif",
                             "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"}) {
        const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name);
        const HeightGrid& g = dem.grid;
        ViewshedSettings s;
        s.observerXM = 0.37 * g.extentXM();
        s.observerYM = 0.61 * g.extentYM();
        s.observerHeightM = 10.0;
        s.values = ViewshedValues::Height;
        const MapRaster need = viewshed(g, s);
        for (double targetM : {0.0, 5.0}) {
            s.values = ViewshedValues::Visible;
            s.targetHeightM = targetM;
            const MapRaster seen = viewshed(g, s);
            int64_t compared = 0, disagree = 0, hidden = 0;
            for (size_t v = 0; v < seen.values.size(); ++v) {
                if (std::isnan(seen.values[v])) {
                    CHECK(std::isnan(need.values[v]));
                    continue;
                }
                if (need.values[v] > 0.0f && std::abs(double(need.values[v]) - targetM) < 0.01) continue;
                ++compared;
                hidden += seen.values[v] == 0.0f;
                disagree += (seen.values[v] == 1.0f) != (need.values[v] <= targetM);
            }
            INFO(name << " target " << targetM << " m: " << compared << " compared, " << hidden << " hidden");
            CHECK(disagree == 0);
            CHECK(hidden > 1000);
            CHECK(compared - hidden > 1000);
        }
    }
}

TEST_CASE("Map view without shadows or sky equals Lambert shading of the analytic normals", "[tracer][maps]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    const HeightGrid& g = dem.grid;
    MapViewSettings s;
    s.castShadows = false;
    s.skySamples = 0;
    s.sun = Sun{300.0, 40.0};
    // At scale 1 the pixels are the DEM's samples, shaded at the vertices.
    const MapImage image = renderMapView(g, s);
    const Film& film = image.film;
    REQUIRE(film.width == g.width());
    REQUIRE(film.height == g.height());
    const glm::dvec3 toSun = s.sun.direction();
    int64_t checked = 0, holes = 0;
    for (int py = 0; py < film.height; ++py)
        for (int px = 0; px < film.width; ++px) {
            const int64_t i = px, j = g.height() - 1 - py;
            // The vertex's normal: the mean of its valid cells' unit normals, each from the corner heights as the
            // plane through the vertex and its two neighbours in that cell.
            glm::dvec3 sum(0.0);
            for (int64_t cj = j - 1; cj <= j; ++cj)
                for (int64_t ci = i - 1; ci <= i; ++ci) {
                    if (ci < 0 || cj < 0 || ci >= g.cellsX() || cj >= g.cellsY() || !g.cellValid(ci, cj)) continue;
                    const int64_t ni = ci == i ? i + 1 : i - 1, nj = cj == j ? j + 1 : j - 1;  // the neighbours
                    const double sx = (g.at(ni, j) - g.at(i, j)) / (double(ni - i) * g.cellSizeXM());
                    const double sy = (g.at(i, nj) - g.at(i, j)) / (double(nj - j) * g.cellSizeYM());
                    sum += glm::normalize(glm::dvec3(-sx, -sy, 1.0));
                }
            const bool covered = image.covered[size_t(py) * size_t(film.width) + size_t(px)] != 0;
            if (sum == glm::dvec3(0.0)) {
                CHECK_FALSE(covered);
                CHECK(film.get(px, py).r == 0.0f);
                ++holes;
                continue;
            }
            REQUIRE(covered);
            const glm::dvec3 n = glm::normalize(sum);
            const double expected = 0.8 * (std::max(0.0, glm::dot(n, toSun)) + s.ambient);
            REQUIRE(film.get(px, py).r == Approx(expected).epsilon(1e-4));
            ++checked;
        }
    CHECK(checked > 10000);
    CHECK(holes > 100);
    // Cast shadows only darken, and sky visibility only darkens the ambient part.
    MapViewSettings full = s;
    full.castShadows = true;
    full.skySamples = 8;
    const MapImage shaded = renderMapView(g, full);
    int64_t darker = 0;
    for (size_t k = 0; k < film.rgb.size(); ++k) {
        REQUIRE(shaded.film.rgb[k] <= film.rgb[k] + 1e-6f);
        darker += shaded.film.rgb[k] < film.rgb[k] - 1e-3f;
    }
    CHECK(darker > 1000);
    // A vertex's cast shadow is the shadow mask's verdict there.
    const MapRaster mask = shadowMask(g, radians(300.0), radians(40.0), CellMethod::Bilinear);
    MapViewSettings sunOnly = s;
    sunOnly.castShadows = true;
    sunOnly.ambient = 0.0f;
    const MapImage lit = renderMapView(g, sunOnly);
    int64_t shadowed = 0;
    for (int py = 0; py < film.height; ++py)
        for (int px = 0; px < film.width; ++px) {
            const float m = mask.at(px, g.height() - 1 - py);
            if (std::isnan(m) || film.get(px, py).r == 0.0f) continue;
            CHECK((lit.film.get(px, py).r == 0.0f) == (m == 1.0f || glm::dot(glm::dvec3(0, 0, 1), toSun) <= 0.0 ||
                                                        film.get(px, py).r <= 0.8f * s.ambient + 1e-6f));
            shadowed += m == 1.0f;
        }
    CHECK(shadowed > 50);
    // At scale 2, twice the pixels over the same footprint.
    MapViewSettings twice = s;
    twice.scale = 2.0;
    const MapImage fine = renderMapView(g, twice);
    CHECK(fine.film.width == 2 * g.width());
    CHECK(fine.film.height == 2 * g.height());
}
