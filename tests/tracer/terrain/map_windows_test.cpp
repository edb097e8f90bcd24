// Map products a window at a time (docs/architecture.md, "Tiled outputs"): every product computed over the
// windows of a real DEM, holes and all, holds exactly the values of the whole grid's map; the windows the
// tiled writer uses (columns from multiples of 64) and, for the products without horizon chains, windows at
// any offset.
#include "loaders/dem_loader.h"
#include "tracer/core/angles.h"
#include "tracer/terrain/insolation.h"
#include "tracer/terrain/maps.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

using namespace terracast;

namespace {

const std::string kHelens =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";

// Bits of a float, so that NaN equals NaN and -0 differs from 0.
uint32_t bits(float v) {
    uint32_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// Computes `product` over windows `step` vertices wide and `rows` high starting at (offsetI, offsetJ) (and the
// strips before them) and counts the values that differ from `whole`'s.
int64_t windowMismatches(const HeightGrid& grid, const MapRaster& whole,
                         const std::function<MapRaster(const VertexWindow&)>& product, int64_t step, int64_t rows,
                         int64_t offsetI = 0, int64_t offsetJ = 0) {
    int64_t mismatches = 0, compared = 0;
    std::vector<int64_t> is{0}, js{0};
    for (int64_t i = offsetI; i < grid.width(); i += step) if (i > 0) is.push_back(i);
    for (int64_t j = offsetJ; j < grid.height(); j += rows) if (j > 0) js.push_back(j);
    is.push_back(grid.width());
    js.push_back(grid.height());
    for (size_t b = 0; b + 1 < js.size(); ++b)
        for (size_t a = 0; a + 1 < is.size(); ++a) {
            const VertexWindow w{is[a], js[b], is[a + 1], js[b + 1]};
            const MapRaster r = product(w);
            REQUIRE(r.width == w.i1 - w.i0);
            REQUIRE(r.height == w.j1 - w.j0);
            REQUIRE(r.i0 == w.i0);
            REQUIRE(r.j0 == w.j0);
            REQUIRE(r.bands == whole.bands);
            for (int64_t j = w.j0; j < w.j1; ++j)
                for (int64_t i = w.i0; i < w.i1; ++i)
                    for (int k = 0; k < r.bands; ++k) {
                        ++compared;
                        mismatches += bits(r.at(i - w.i0, j - w.j0, k)) != bits(whole.at(i, j, k));
                    }
        }
    REQUIRE(compared == whole.width * whole.height * whole.bands);
    return mismatches;
}

}  // namespace

TEST_CASE("Map windows: every product over windows holds the whole grid's values", "[maps][tiles][heavy]") {
    const LoadedDem dem = loadDem(kHelens);
    const HeightGrid& g = dem.grid;
    REQUIRE(g.hasNodata());
    const CellMethod m = CellMethod::Bilinear;
    HorizonSearch far;
    far.dropPerSquareM = 0.85714 / (2.0 * 6378137.0);

    SECTION("shadow, point and disc suns") {
        const MapRaster whole = shadowMask(g, radians(135.0), radians(20.0), m, 0.0, 16, 2, far);
        const auto tile = [&](const VertexWindow& w) {
            return shadowMask(g, radians(135.0), radians(20.0), m, 0.0, 16, 2, far, {}, w);
        };
        CHECK(windowMismatches(g, whole, tile, 128, 100) == 0);
        CHECK(windowMismatches(g, whole, tile, 97, 61, 37, 51) == 0);
        const MapRaster disc = shadowMask(g, radians(250.0), radians(8.0), m, radians(0.25), 9, 2);
        CHECK(windowMismatches(g, disc, [&](const VertexWindow& w) {
                  return shadowMask(g, radians(250.0), radians(8.0), m, radians(0.25), 9, 2, {}, {}, w);
              }, 64, 200) == 0);
    }
    SECTION("shadow series") {
        const std::vector<glm::dvec2> suns{{radians(90.0), radians(10.0)}, {radians(200.0), radians(30.0)}};
        const MapRaster whole = shadowMasks(g, suns, m, 2);
        CHECK(windowMismatches(g, whole, [&](const VertexWindow& w) { return shadowMasks(g, suns, m, 2, {}, {}, w); },
                               128, 77, 5, 3) == 0);
    }
    SECTION("horizons, exact and nearest") {
        const std::vector<double> azimuths{radians(45.0), radians(225.0), radians(300.0)};
        const MapRaster whole = horizonMaps(g, azimuths, m, 2, far);
        CHECK(windowMismatches(g, whole, [&](const VertexWindow& w) { return horizonMaps(g, azimuths, m, 2, far, {}, w); },
                               128, 90) == 0);
        const MapRaster nearest = horizonMaps(g, {radians(100.0)}, CellMethod::Nearest, 2);
        CHECK(windowMismatches(g, nearest, [&](const VertexWindow& w) {
                  return horizonMaps(g, {radians(100.0)}, CellMethod::Nearest, 2, {}, {}, w);
              }, 192, 300) == 0);
    }
    SECTION("sky view") {
        SkyViewSettings s;
        s.directions = 8;
        s.search.maxDistanceM = 600.0;
        const MapRaster whole = skyView(g, s);
        const auto maker = skyViewMaker(g, s);
        CHECK(windowMismatches(g, whole, [&](const VertexWindow& w) { return maker(w, {}); }, 64, 128) == 0);
    }
    SECTION("viewsheds, flat and curved, every kind of value") {
        for (const ViewshedValues values : {ViewshedValues::Visible, ViewshedValues::Angle, ViewshedValues::Height}) {
            ViewshedSettings s;
            s.observerXM = 0.45 * g.extentXM();
            s.observerYM = 0.55 * g.extentYM();
            s.values = values;
            s.curvatureCoeff = values == ViewshedValues::Height ? 0.0 : 0.85714;
            const MapRaster whole = viewshed(g, s);
            const auto maker = viewshedMaker(g, s);
            CHECK(windowMismatches(g, whole, [&](const VertexWindow& w) { return maker(w, {}); }, 128, 111, 17, 29) == 0);
        }
    }
    SECTION("insolation with the sun placed per block") {
        InsolationSettings s;
        s.threads = 2;
        s.stepsAt = [](double col, double row) {
            std::vector<SunStep> steps;
            for (int k = 0; k < 4; ++k) {
                SunStep sun;
                sun.azimuthRad = radians(100.0 + 40.0 * k + 0.01 * col);
                sun.elevationRad = sun.apparentElevationRad = radians(12.0 + 0.02 * row);
                sun.extraterrestrial = 1361.0;
                sun.hours = 1.0;
                steps.push_back(sun);
            }
            return steps;
        };
        const MapRaster whole = insolationMap(g, s);
        CHECK(windowMismatches(g, whole, [&](const VertexWindow& w) {
                  InsolationSettings one = s;
                  one.window = w;
                  return insolationMap(g, one);
              }, 128, 70, 33, 41) == 0);
    }
}

TEST_CASE("Map windows: a window outside the grid is refused", "[maps][tiles]") {
    const LoadedDem dem = loadDem(kHelens);
    CHECK_THROWS_AS(shadowMask(dem.grid, 0.0, 0.5, CellMethod::Bilinear, 0.0, 16, 1, {}, {},
                               VertexWindow{0, 0, dem.grid.width() + 1, 10}),
                    std::invalid_argument);
    CHECK_THROWS_AS(shadowMask(dem.grid, 0.0, 0.5, CellMethod::Bilinear, 0.0, 16, 1, {}, {}, VertexWindow{5, 5, 5, 9}),
                    std::invalid_argument);
}
