// Rays that run exactly along a grid line beside nodata holes: the line's edges belong to the valid cells on
// its other side, so the terrain there stops the ray.
#include "heightfield/traversal.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

namespace {

// 9 x 9 vertices, 10 m apart, flat at 0 m but for a 50 m wall along the vertices x = 6 (or y = 6 when
// `transpose`); the vertices of row (column) `holeLine` are nodata, so the cells on both sides of it are holes.
HeightGrid walledGrid(bool transpose, int holeLine) {
    std::vector<float> z(81, 0.0f);
    std::vector<uint8_t> valid(81, 1);
    for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) {
            const int i = transpose ? b : a, j = transpose ? a : b;
            if (a == 6) z[size_t(j * 9 + i)] = 50.0f;
            if (b == holeLine) valid[size_t(j * 9 + i)] = 0;
        }
    return HeightGrid(9, 9, 10.0, 10.0, z, valid);
}

}  // namespace

TEST_CASE("Traversal: a ray along a grid line beside holes meets the valid cells' edge", "[heightfield][traversal]") {
    // The line y = 4 (x = 4): holes on its north (east) side when row 5 is nodata, on its south (west) side
    // when row 3 is; the valid cells on the other side hold the edge, which rises from 0 m at x = 5 to 50 m at
    // x = 6. A ray along the line at 10 m meets it at x = 5.2 cells going east and x = 6.8 going west.
    for (bool transpose : {false, true})
        for (int holeLine : {5, 3})
            for (CellMethod method : {CellMethod::Bilinear, CellMethod::BilinearDouble, CellMethod::Reference, CellMethod::Triangles}) {
                const HeightGrid g = walledGrid(transpose, holeLine);
                for (double sign : {1.0, -1.0}) {
                    INFO("transpose " << transpose << " holes beside row " << holeLine << " " << cellMethodName(method)
                                      << " direction " << sign);
                    const double along0 = sign > 0.0 ? 5.0 : 75.0, line = 40.0;
                    const glm::dvec3 origin = transpose ? glm::dvec3(line, along0, 10.0) : glm::dvec3(along0, line, 10.0);
                    const glm::dvec3 dir = transpose ? glm::dvec3(0.0, sign, 0.0) : glm::dvec3(sign, 0.0, 0.0);
                    const auto hit = intersect(g, Ray{origin, dir}, {0.0, kInfinity}, method);
                    REQUIRE(hit.has_value());
                    const double along = transpose ? hit->pointM.y : hit->pointM.x;
                    CHECK(along == Approx(sign > 0.0 ? 52.0 : 68.0).margin(1e-4));
                    CHECK(occluded(g, Ray{origin, dir}, {0.0, kInfinity}, method));
                    // Above the wall, nothing.
                    const glm::dvec3 high = origin + glm::dvec3(0.0, 0.0, 45.0);
                    CHECK_FALSE(occluded(g, Ray{high, dir}, {0.0, kInfinity}, method));
                    // The flat walk agrees with the pyramid's.
                    const auto flat = intersect(g, Ray{origin, dir}, {0.0, kInfinity}, method, nullptr, Traversal::Flat);
                    REQUIRE(flat.has_value());
                    CHECK(flat->t == hit->t);
                }
            }
}
