// Sky-view factor and openness against a valley's geometry: along a straight V-shaped valley the horizon in each
// direction is the wall's slope seen at that azimuth, the same at every distance.
#include "tracer/core/angles.h"
#include "tracer/terrain/maps.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

TEST_CASE("Sky view: a V-shaped valley's sky-view factor and openness are its walls' geometry", "[tracer][maps]") {
    // Walls rising 0.7 m per metre east and west of the valley floor x = 20 cells, cells of 10 x 7 m; long in y.
    const int64_t w = 41, h = 161;
    const double slope = 0.7;
    std::vector<float> z(size_t(w * h));
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) z[size_t(j * w + i)] = float(slope * 10.0 * double(std::abs(i - 20)));
    const HeightGrid g(w, h, 10.0, 7.0, z);
    for (int directions : {16, 8, 5}) {
        for (CellMethod method : {CellMethod::Bilinear, CellMethod::Triangles}) {
            SkyViewSettings s;
            s.directions = directions;
            s.method = method;
            s.search.maxDistanceM = 150.0;  // short of the grid's ends along the valley
            const MapRaster r = skyView(g, s);
            REQUIRE(r.bands == 3);
            // On the floor: towards azimuth a the wall rises at slope |sin a| per metre travelled; up the valley the
            // floor is flat. Below, the terrain everywhere rises, so the lowest angle is the same as the highest.
            double sinSum = 0.0, above = 0.0, under = 0.0;
            for (int k = 0; k < directions; ++k) {
                const double a = 2.0 * kPi * k / directions;
                const double up = std::atan(slope * std::abs(std::sin(a)));
                sinSum += std::sin(up);
                above += 90.0 - degrees(up);
                under += 90.0 + degrees(up);
            }
            INFO(directions << " directions, " << cellMethodName(method));
            CHECK(r.at(20, 80, 0) == Approx(1.0 - sinSum / directions).margin(1e-6));
            CHECK(r.at(20, 80, 1) == Approx(above / directions).margin(1e-4));
            CHECK(r.at(20, 80, 2) == Approx(under / directions).margin(1e-4));
            // High on the west wall (x = 5 cells, 105 m up, the far wall's crest 140 m up at x = 40 cells, out of
            // reach): looking east the wall falls away and the far wall, 150 m off, is not reached; the sky is open
            // above the down-slope, and the lowest angle east is the slope down to the floor.
            CHECK(r.at(5, 80, 0) > r.at(20, 80, 0));
            CHECK(r.at(5, 80, 2) < r.at(20, 80, 2));
        }
    }
    // Flat ground: the whole sky, openness 90 degrees both ways.
    const HeightGrid flat(21, 21, 5.0, 5.0, std::vector<float>(441, 12.0f));
    const MapRaster f = skyView(flat, {});
    CHECK(f.at(10, 10, 0) == Approx(1.0).margin(1e-12));
    CHECK(f.at(10, 10, 1) == Approx(90.0).margin(1e-9));
    CHECK(f.at(10, 10, 2) == Approx(90.0).margin(1e-9));
}
