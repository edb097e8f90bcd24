// Map products at vertices against answers that do not come from the tracer: the horizon and shadows of a
// pyramid and the shadow of a cone from their geometry, a vertex beside a hole, a bowl under a zenith sun, and a brute-force march over
// the bilinear surface of a real DEM.
#include "loaders/dem_loader.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/maps.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>

using namespace terracast;

namespace {

// A square pyramid of 21 x 21 vertices, 10 m apart: apex 100 m at vertex (10, 10), falling 10 m per cell
// along the axes (a 45 degree slope on the faces).
HeightGrid pyramid() {
    std::vector<float> z(21 * 21);
    for (int j = 0; j < 21; ++j)
        for (int i = 0; i < 21; ++i) z[size_t(j * 21 + i)] = float(100 - 10 * std::max(std::abs(i - 10), std::abs(j - 10)));
    return HeightGrid(21, 21, 10.0, 10.0, std::move(z));
}

float valueAt(const MapRaster& r, int64_t i, int64_t j) { return r.values[size_t(j * r.width + i)]; }

// The horizon (degrees) from vertex (i, j) towards an azimuth by marching over the bilinear surface: the
// largest elevation angle to any sample, every thousandth of a cell for 5 cells and every hundredth beyond.
// A lower bound of the exact horizon, close to it. NaN when the march crosses a hole: how a line of sight
// passes holes is the walk's convention, not geometry.
double bruteHorizonDeg(const HeightGrid& g, int64_t i, int64_t j, double azimuthDeg) {
    const double x0 = double(i) * g.cellSizeXM(), y0 = double(j) * g.cellSizeYM(), z0 = g.at(i, j);
    const double sx = std::sin(radians(azimuthDeg)), sy = std::cos(radians(azimuthDeg));
    const double cell = std::min(g.cellSizeXM(), g.cellSizeYM());
    double best = -90.0;
    for (double r = 1e-4 * cell;; r = r < 1e-3 * cell ? r * 1.1 : r + (r < 5.0 * cell ? 1e-3 : 1e-2) * cell) {
        const double x = x0 + r * sx, y = y0 + r * sy;
        if (x < 0.0 || y < 0.0 || x > g.extentXM() || y > g.extentYM()) break;
        const double h = double(testing::bilinearHeightAt(g, x, y));
        if (std::isnan(h)) return h;
        best = std::max(best, degrees(std::atan2(h - z0, r)));
    }
    return best;
}

}  // namespace

TEST_CASE("Vertex maps: a pyramid's horizons and shadows are its geometry", "[tracer][maps]") {
    const HeightGrid g = pyramid();
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Reference, CellMethod::Triangles}) {
        INFO(cellMethodName(method));
        // From the apex along a grid line the face falls at 45 degrees; along a diagonal the vertices of the
        // diagonal are the highest points, 10 m lower for every 10 sqrt(2) m.
        CHECK(valueAt(horizonMap(g, radians(90.0), method), 10, 10) == Approx(-45.0).margin(1e-4));
        CHECK(valueAt(horizonMap(g, radians(180.0), method), 10, 10) == Approx(-45.0).margin(1e-4));
        const double diagonal = degrees(std::atan(-1.0 / std::sqrt(2.0)));
        for (double az : {45.0, 135.0, 225.0, 315.0})
            CHECK(valueAt(horizonMap(g, radians(az), method), 10, 10) == Approx(diagonal).margin(1e-4));
        // On the east face, looking up the face to the apex and down it away from it.
        CHECK(valueAt(horizonMap(g, radians(270.0), method), 15, 10) == Approx(45.0).margin(1e-4));
        CHECK(valueAt(horizonMap(g, radians(90.0), method), 15, 10) == Approx(-45.0).margin(1e-4));
        // A low sun anywhere leaves the apex lit; behind the pyramid, a sun lower than the faces shades them.
        for (double az : {45.0, 200.0, 225.0, 300.0})
            CHECK(valueAt(shadowMask(g, radians(az), radians(5.0), method), 10, 10) == 0.0f);
        CHECK(valueAt(shadowMask(g, radians(270.0), radians(44.0), method), 15, 10) == 1.0f);
        // A sun just below the horizontal still lights the apex (the faces fall away at 45 degrees); at the grid's
        // west edge, looking out over no surface, the ground beyond counts as a 0-degree horizon.
        CHECK(valueAt(shadowMask(g, radians(270.0), radians(-1.0), method), 10, 10) == 0.0f);
        CHECK(valueAt(shadowMask(g, radians(270.0), radians(-1.0), method), 0, 10) == 1.0f);
        CHECK(valueAt(shadowMask(g, radians(270.0), radians(1.0), method), 0, 10) == 0.0f);
        CHECK(valueAt(shadowMask(g, radians(270.0), radians(46.0), method), 15, 10) == 0.0f);
    }
}

TEST_CASE("Vertex maps: a cone's shadow is the hull of its base and its apex's shadow, for suns all round",
          "[tracer][maps]") {
    // A right circular cone 24 m high with a base 40 m in radius (its sides rise at 31 degrees) on flat ground,
    // sampled every metre: 241 x 241 vertices, apex at vertex (120, 120).
    constexpr double kHeight = 24.0, kRadius = 40.0, kCentre = 120.0;
    std::vector<float> z(241 * 241);
    for (int j = 0; j < 241; ++j)
        for (int i = 0; i < 241; ++i)
            z[size_t(j * 241 + i)] =
                float(std::max(0.0, kHeight * (1.0 - std::hypot(i - kCentre, j - kCentre) / kRadius)));
    const HeightGrid cone(241, 241, 1.0, 1.0, std::move(z));
    const glm::dvec2 c(kCentre, kCentre);
    for (double az : {37.0, 128.0, 211.0, 304.0})
        for (double el : {12.0, 25.0}) {
            INFO("sun at azimuth " << az << ", elevation " << el);
            // A convex solid on a plane shades, on the plane, its projection along the sun: for a cone, the disc of
            // its base together with the triangle from the apex's shadow T to the two points where the lines
            // from T touch the base circle. On its own sides it shades exactly the points facing away from the sun.
            const glm::dvec2 h(std::sin(radians(az)), std::cos(radians(az)));
            const double d = kHeight / std::tan(radians(el));
            const glm::dvec2 T = c - d * h;
            const double alpha = std::acos(kRadius / d);
            const glm::dvec2 u = -h, w(-u.y, u.x);
            const glm::dvec2 P1 = c + kRadius * (std::cos(alpha) * u + std::sin(alpha) * w);
            const glm::dvec2 P2 = c + kRadius * (std::cos(alpha) * u - std::sin(alpha) * w);
            const auto cross = [](glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; };
            const auto inTriangle = [&](glm::dvec2 q) {
                const double s1 = cross(P1 - T, q - T), s2 = cross(P2 - P1, q - P1), s3 = cross(T - P2, q - P2);
                return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
            };
            const auto groundShadowed = [&](glm::dvec2 q) { return glm::length(q - c) <= kRadius || inTriangle(q); };
            const glm::dvec3 sun(std::cos(radians(el)) * h, std::sin(radians(el)));
            const MapRaster mask = shadowMask(cone, radians(az), radians(el), CellMethod::Bilinear);
            int64_t shadedGround = 0, litGround = 0, shadedSide = 0, litSide = 0, wrong = 0;
            std::string first;
            for (int j = 0; j < 241; ++j)
                for (int i = 0; i < 241; ++i) {
                    const glm::dvec2 q(i, j);
                    const double r = glm::length(q - c);
                    bool expected = false;
                    if (r > kRadius + 2.0) {
                        // Ground: compared only where every point within 1.5 m is on the same side of the edge.
                        expected = groundShadowed(q);
                        bool clear = true;
                        for (int k = 0; k < 16 && clear; ++k) {
                            const double a = 2.0 * kPi * k / 16.0;
                            clear = groundShadowed(q + 1.5 * glm::dvec2(std::cos(a), std::sin(a))) == expected;
                        }
                        if (!clear) continue;
                        (expected ? shadedGround : litGround)++;
                    } else if (r > 3.0 && r < kRadius - 2.0) {
                        // Side: the cone's normal there, away from the terminator.
                        const glm::dvec2 out = (q - c) / r;
                        const glm::dvec3 n = glm::normalize(glm::dvec3(kHeight / kRadius * out, 1.0));
                        const double facing = glm::dot(n, sun);
                        if (std::abs(facing) < 0.1) continue;
                        expected = facing < 0.0;
                        (expected ? shadedSide : litSide)++;
                    } else {
                        continue;
                    }
                    if ((valueAt(mask, i, j) == 1.0f) != expected) {
                        ++wrong;
                        if (first.empty())
                            first = "vertex " + std::to_string(i) + "," + std::to_string(j) + " should be " +
                                    (expected ? "shadowed" : "lit");
                    }
                }
            INFO(first);
            CHECK(wrong == 0);
            // The shadow reaches out to the apex's shadow, d = 24 m / tan(elevation) from the apex, and no further.
            INFO(shadedGround << " shadowed and " << litGround << " lit on the ground, " << shadedSide << " and " << litSide
                              << " on the sides");
            CHECK(shadedGround > (el < 20.0 ? 1500 : 40));
            CHECK(litGround > 20000);
            CHECK(shadedSide > 100);
            CHECK(litSide > 1500);
            const glm::dvec2 beforeTip = T + 2.0 * h, beyondTip = T - 2.0 * h;
            CHECK(valueAt(mask, int64_t(std::lround(beforeTip.x)), int64_t(std::lround(beforeTip.y))) == 1.0f);
            CHECK(valueAt(mask, int64_t(std::lround(beyondTip.x)), int64_t(std::lround(beyondTip.y))) == 0.0f);
        }
}

TEST_CASE("Vertex maps: shadows on real DEMs agree with a brute-force march towards the sun", "[tracer][maps]") {
    // Whether the sun is up over a vertex's horizon, from a march over the bilinear surface that shares nothing
    // with the shadow walk; vertices within 0.05 degrees of the sun (the march's error is under 0.02) are not
    // judged.
    const LoadedDem srtm = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/N44W072.srtm3-white-mountains-nh.hgt");
    std::vector<float> window;
    for (int64_t j = 500; j < 621; ++j)
        for (int64_t i = 600; i < 721; ++i) window.push_back(srtm.grid.at(i, j));
    const HeightGrid mountains(121, 121, srtm.grid.cellSizeXM(), srtm.grid.cellSizeYM(), std::move(window));
    const LoadedDem holed = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                    "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    for (const HeightGrid* grid : {&mountains, &holed.grid}) {
        const HeightGrid& g = *grid;
        std::mt19937_64 rng(11);
        std::uniform_int_distribution<int64_t> I(0, g.width() - 1), J(0, g.height() - 1);
        int64_t shaded = 0, lit = 0, wrong = 0;
        std::string misses;
        for (const auto& [az, el] : {std::pair{63.0, 8.0}, {142.0, 15.0}, {251.0, 5.0}, {333.0, 20.0}}) {
            const MapRaster mask = shadowMask(g, radians(az), radians(el), CellMethod::Bilinear);
            for (int k = 0; k < 250; ++k) {
                const int64_t i = I(rng), j = J(rng);
                if (std::isnan(valueAt(mask, i, j))) continue;
                const double horizon = bruteHorizonDeg(g, i, j, az);
                if (std::isnan(horizon) || std::abs(horizon - el) < 0.05) continue;
                const bool expected = horizon > el;
                (expected ? shaded : lit)++;
                if ((valueAt(mask, i, j) == 1.0f) != expected) {
                    ++wrong;
                    misses += "azimuth " + std::to_string(az) + ", vertex " + std::to_string(i) + "," +
                              std::to_string(j) + ": horizon " + std::to_string(horizon) + "\n";
                }
            }
        }
        INFO(shaded << " shadowed, " << lit << " lit, " << wrong << " wrong\n" << misses);
        CHECK(wrong == 0);
        CHECK(shaded > 35);
        CHECK(lit > 35);
    }
}

TEST_CASE("Vertex maps: a vertex beside a hole has a value, one with no valid cell has none", "[tracer][maps]") {
    // Flat ground at 0 m, 11 x 11 vertices; vertex (6, 6) is nodata, so the four cells around it are holes and
    // vertex (5, 5) keeps only its south and west cells.
    std::vector<float> z(121, 0.0f);
    std::vector<uint8_t> valid(121, 1);
    valid[6 * 11 + 6] = 0;
    const HeightGrid g(11, 11, 30.0, 30.0, z, valid);
    for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
        // Over the valid cells and along their edges with the holes: the flat ground's horizon.
        for (double az : {0.0, 90.0, 180.0, 225.0, 270.0}) {
            INFO(cellMethodName(method) << " azimuth " << az);
            const float h = valueAt(horizonMap(g, radians(az), method), 5, 5);
            REQUIRE_FALSE(std::isnan(h));
            CHECK(std::abs(h) < 1e-4);
            CHECK(valueAt(shadowMask(g, radians(az), radians(1.0), method), 5, 5) == 0.0f);
            CHECK(valueAt(shadowMask(g, radians(az), radians(-1.0), method), 5, 5) == 1.0f);
        }
        // Over the hole a value too, and a sun above the horizon lights the vertex.
        CHECK_FALSE(std::isnan(valueAt(horizonMap(g, radians(45.0), method), 5, 5)));
        CHECK(valueAt(shadowMask(g, radians(45.0), radians(1.0), method), 5, 5) == 0.0f);
        CHECK(std::isnan(valueAt(horizonMap(g, 0.0, method), 6, 6)));
    }
}

TEST_CASE("Vertex maps: a zenith sun lights every vertex of a bowl and of a real crater", "[tracer][maps]") {
    std::vector<float> z(31 * 31);
    for (int j = 0; j < 31; ++j)
        for (int i = 0; i < 31; ++i) z[size_t(j * 31 + i)] = float((i - 15) * (i - 15) + (j - 15) * (j - 15));
    const HeightGrid bowl(31, 31, 5.0, 5.0, std::move(z));
    const LoadedDem crater = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                     "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    for (const HeightGrid* g : {&bowl, &crater.grid}) {
        const MapRaster mask = shadowMask(*g, radians(315.0), radians(90.0), CellMethod::Bilinear);
        int64_t lit = 0, shadowed = 0;
        for (float v : mask.values) {
            lit += v == 0.0f;
            shadowed += v == 1.0f;
        }
        CHECK(shadowed == 0);
        CHECK(lit > 900);
    }
}

TEST_CASE("Vertex maps: horizons agree with a brute-force march over a real DEM's bilinear surface",
          "[tracer][maps]") {
    // A 121 x 121 window of the White Mountains SRTM tile: rugged, and with cells of 92.6 x 66.3 m, so that no
    // azimuth but the axes' runs along a grid diagonal; and a small DEM with holes, where only marches that
    // meet none are compared.
    const LoadedDem srtm = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/N44W072.srtm3-white-mountains-nh.hgt");
    const HeightGrid& s = srtm.grid;
    std::vector<float> window;
    for (int64_t j = 500; j < 621; ++j)
        for (int64_t i = 600; i < 721; ++i) window.push_back(s.at(i, j));
    const HeightGrid mountains(121, 121, s.cellSizeXM(), s.cellSizeYM(), std::move(window));
    const LoadedDem holed = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                    "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    // A geographic DEM (degrees; metric cells from its latitude), where vertices must be evaluated from their own
    // indices and not from a probe that rounding can move into the west or south neighbour cell: a window of
    // the Nice coast tile, sea and all.
    const LoadedDem nice = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                   "/data-samples/srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif");
    std::vector<float> coast;
    const int64_t n0 = nice.grid.width() / 3, m0 = nice.grid.height() / 3;
    for (int64_t j = m0; j < m0 + 121; ++j)
        for (int64_t i = n0; i < n0 + 121; ++i) coast.push_back(nice.grid.at(i, j));
    const HeightGrid geographic(121, 121, nice.grid.cellSizeXM(), nice.grid.cellSizeYM(), std::move(coast));
    for (const HeightGrid* grid : {&mountains, &holed.grid, &geographic}) {
    const HeightGrid& g = *grid;
    std::mt19937_64 rng(7);
    std::uniform_int_distribution<int64_t> I(0, g.width() - 1), J(0, g.height() - 1);
    int64_t compared = 0, off = 0;
    double worst = 0.0;
    std::string misses;
    for (double az : {45.0, 90.0, 200.0, 315.0}) {
        const MapRaster horizon = horizonMap(g, radians(az), CellMethod::Bilinear);
        for (int k = 0; k < 150; ++k) {
            const int64_t i = I(rng), j = J(rng);
            const float exact = valueAt(horizon, i, j);
            if (std::isnan(exact)) continue;
            const double brute = bruteHorizonDeg(g, i, j, az);
            if (std::isnan(brute)) continue;
            // The march can only miss the highest point (it is a lower bound), by little.
            const double diff = double(exact) - brute;
            worst = std::max(worst, std::abs(diff));
            off += diff < -1e-3 || diff > 0.02;
            if (diff < -1e-3 || diff > 0.02)
                misses += "azimuth " + std::to_string(az) + ", vertex " + std::to_string(i) + "," + std::to_string(j) +
                          ": " + std::to_string(exact) + " against " + std::to_string(brute) + "\n";
            ++compared;
        }
    }
    INFO(compared << " vertices, " << off << " off, worst " << worst << " degrees\n" << misses);
    CHECK(compared > 80);
    CHECK(off == 0);
    }
}

TEST_CASE("Vertex maps: occlusion walks and horizon walks agree at every vertex", "[tracer][maps][heavy]") {
    // Two different traversals answer the same question: a direction from a vertex is blocked (the occlusion walk
    // of blockedFromVertex) exactly when it lies below the vertex's horizon (the horizon walk of horizonMap). On
    // two real DEMs with holes, along the axes (grid lines beside holes) and at azimuths off the axes. (Not at an
    // exact cell diagonal: there the occlusion walk ignores a vertex the line passes through when the cells the
    // line crosses on both sides of it are holes, which the horizon walk counts.)
    for (const char* name : {"landfire-storm-lake-mt-utm12n-int16-small-nodata.tif", "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"}) {
        const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name);
        const HeightGrid& g = dem.grid;
        for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles})
            for (double az : {0.0, 90.0, 180.0, 270.0, 44.0, 222.5}) {
                const MapRaster horizon = horizonMap(g, radians(az), method);
                for (double el : {2.0, 12.0, 25.0}) {
                    int64_t compared = 0, disagree = 0;
                    std::string where;
                    for (int64_t j = 0; j < g.height(); ++j)
                        for (int64_t i = 0; i < g.width(); ++i) {
                            const float hz = valueAt(horizon, i, j);
                            if (std::isnan(hz) || std::abs(double(hz) - el) < 1e-5) continue;
                            ++compared;
                            const bool blocked = blockedFromVertex(g, i, j, directionFromDegrees(az, el), method);
                            if (blocked != (double(hz) > el) && ++disagree <= 5)
                                where += " vertex " + std::to_string(i) + "," + std::to_string(j) + " horizon " +
                                         std::to_string(hz) + " blocked " + std::to_string(blocked) + ";";
                        }
                    INFO(name << " " << cellMethodName(method) << " azimuth " << az << " sun " << el << ": " << disagree
                              << " of " << compared << where);
                    CHECK(compared > 10000);
                    CHECK(disagree == 0);
                }
            }
    }
}

TEST_CASE("Vertex maps: many suns in one pass give each sun's own mask, in order", "[tracer][maps]") {
    const HeightGrid g = pyramid();
    const std::vector<glm::dvec2> suns{{radians(270.0), radians(44.0)}, {radians(270.0), radians(46.0)},
                                       {radians(45.0), radians(5.0)}};
    const MapRaster all = shadowMasks(g, suns, CellMethod::Bilinear);
    REQUIRE(all.bands == 3);
    for (int k = 0; k < 3; ++k) {
        const MapRaster one = shadowMask(g, suns[size_t(k)].x, suns[size_t(k)].y, CellMethod::Bilinear);
        for (int64_t j = 0; j < g.height(); ++j)
            for (int64_t i = 0; i < g.width(); ++i) REQUIRE(all.at(i, j, k) == one.at(i, j));
    }
    // The east face in the 44-degree western sun is shadowed, in the 46-degree one lit (the faces slope 45).
    CHECK(all.at(15, 10, 0) == 1.0f);
    CHECK(all.at(15, 10, 1) == 0.0f);
}
