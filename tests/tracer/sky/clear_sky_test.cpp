// The clear-sky irradiance model against GRASS r.sun 8.2 (mode 1, instantaneous, no terrain shadows), as run by
// scripts/compare_grass.sh's insolation part: one cell at latitude 44.995 N, 500 m above sea level, day 172,
// Linke turbidity 3, albedo 0.2, local solar times 4.5, 8, 12 and 17 h on slopes facing four ways.
#include "tracer/sky/clear_sky.h"

#include "tracer/core/angles.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace terracast;

TEST_CASE("Extraterrestrial irradiance follows the Earth's distance from the sun", "[tracer][sky]") {
    // r.sun's value for day 172 (1322.508495 W/m^2); the yearly extremes near perihelion and aphelion.
    CHECK(extraterrestrialIrradiance(172, 1367.0) == Approx(1322.508495).epsilon(1e-8));
    CHECK(extraterrestrialIrradiance(3, 1367.0) == Approx(1367.0 * 1.03344).epsilon(1e-4));
    CHECK(extraterrestrialIrradiance(185, 1367.0) == Approx(1367.0 * 0.96656).epsilon(1e-4));
}

TEST_CASE("Relative air mass is one at the zenith at sea level and about 38 at the horizon", "[tracer][sky]") {
    // Kasten and Young (1989): 1.0 at the zenith, 37.9 at the apparent horizon (the refraction correction lifts a
    // geometric elevation of 0 to about 0.6 degree here, so the ESRA air mass at h = 0 is lower).
    CHECK(relativeAirMass(0.5 * kPi, 0.0) == Approx(1.0).margin(1e-3));
    CHECK(relativeAirMass(radians(30.0), 0.0) == Approx(1.995).margin(0.01));  // about 1 / sin 30
    CHECK(relativeAirMass(0.0, 0.0) > 25.0);
    CHECK(relativeAirMass(0.0, 0.0) < 38.0);
    // Half the air 5.85 km up: the pressure ratio exp(-z / 8434.5).
    CHECK(relativeAirMass(0.5 * kPi, 8434.5 * std::log(2.0)) == Approx(0.5).margin(1e-3));
}

TEST_CASE("Clear-sky beam diffuse and reflected irradiance match GRASS r.sun", "[tracer][sky]") {
    struct Case {
        double slopeDeg, aspectDeg;              // aspect clockwise from north (r.sun 8.2 reads aspect_value so)
        double elevationDeg, azimuthDeg;         // r.sun's solar altitude and azimuth for the time
        double incidenceDeg;                     // r.sun's incidence: the sun's elevation above the slope
        double beam, diffuse, reflected;         // r.sun, W/m^2
    };
    const Case cases[] = {
        {0, 180, 68.4455, 180.0000, 68.44553, 895.3381, 105.4239, 0},
        {0, 180, 37.2767, 93.1005, 37.27668, 513.7122, 95.41219, 0},
        {0, 180, 1.8895, 58.0052, 1.889515, 6.132374, 18.09833, 0},
        {0, 180, 26.6914, 277.2929, 26.69137, 341.8522, 81.84771, 0},
        {30, 180, 68.4455, 180.0000, 81.55447, 952.2188, 112.5163, 13.40767},
        {30, 180, 37.2767, 93.1005, 33.09576, 463.1397, 91.23002, 8.160719},
        {30, 180, 26.6914, 277.2929, 19.40829, 252.8954, 70.88019, 5.676502},
        {30, 90, 68.4455, 180.0000, 53.65501, 775.3855, 97.36013, 13.40767},
        {30, 90, 37.2767, 93.1005, 67.19045, 781.8504, 129.1938, 8.160719},
        {30, 90, 1.8895, 58.0052, 26.89599, 84.13479, 25.61589, 0.32463},
        {30, 270, 37.2767, 93.1005, 7.310322, 107.9251, 48.91798, 8.160719},
        {30, 270, 26.6914, 277.2929, 56.31618, 633.2786, 123.2891, 5.676502},
        {45, 0, 68.4455, 180.0000, 23.44554, 383.0196, 65.09889, 29.31164},
        {45, 0, 37.2767, 93.1005, 23.44303, 337.4372, 77.18082, 17.84084},
        {45, 0, 1.8895, 58.0052, 23.43862, 73.97887, 23.36918, 0.7097011},
        {45, 0, 26.6914, 277.2929, 23.44183, 302.7596, 78.17643, 12.40988},
        {60, 180, 68.4455, 180.0000, 51.55446, 753.9533, 97.32077, 50.0381},
        {60, 180, 37.2767, 93.1005, 19.88323, 288.4694, 71.20056, 30.45622},
        {60, 180, 26.6914, 277.2929, 7.259994, 96.17552, 49.08622, 21.185},
        // Slopes that face away from the sun (any negative incidence): the shaded sky of Muneer's model.
        {30, 180, 1.8895, 58.0052, -5, 0, 16.13768, 0.2424717},
        {30, 270, 1.8895, 58.0052, -5, 0, 16.13768, 0.2424717},
        {30, 90, 26.6914, 277.2929, -5, 0, 72.98084, 1.096551},
        {60, 180, 1.8895, 58.0052, -5, 0, 11.55128, 0.9049168},
    };
    const ClearSky sky;  // Linke 3, albedo 0.2, 1367 W/m^2
    const double g0 = extraterrestrialIrradiance(172, sky.solarConstant);
    for (const Case& c : cases) {
        SunOnSurface at;
        at.elevationRad = radians(c.elevationDeg);
        at.azimuthRad = radians(c.azimuthDeg);
        at.cosIncidence = std::sin(radians(c.incidenceDeg));
        at.slopeRad = radians(c.slopeDeg);
        at.aspectRad = radians(c.aspectDeg);
        at.heightM = 500.0;
        const Irradiance e = clearSkyIrradiance(sky, g0, at);
        INFO("slope " << c.slopeDeg << " aspect " << c.aspectDeg << " sun " << c.azimuthDeg << ", " << c.elevationDeg);
        // r.sun's altitudes carry four decimals: 5e-5 degree moves the beam of the 1.9-degree sun by 0.03 %.
        CHECK(e.beam == Approx(c.beam).epsilon(1e-3).margin(0.01));
        CHECK(e.diffuse == Approx(c.diffuse).epsilon(1e-3).margin(0.01));
        CHECK(e.reflected == Approx(c.reflected).epsilon(1e-3).margin(0.01));
        CHECK(e.global() == Approx(c.beam + c.diffuse + c.reflected).epsilon(1e-3));
    }
}

TEST_CASE("Clear-sky irradiance in shadow and with the sun down", "[tracer][sky]") {
    const ClearSky sky;
    const double g0 = extraterrestrialIrradiance(172, sky.solarConstant);
    SunOnSurface at;
    at.elevationRad = radians(37.2767);
    at.azimuthRad = radians(93.1005);
    at.cosIncidence = std::sin(radians(33.09576));
    at.slopeRad = radians(30.0);
    at.aspectRad = radians(180.0);
    at.heightM = 500.0;
    const Irradiance lit = clearSkyIrradiance(sky, g0, at);
    at.shadowed = true;
    const Irradiance shade = clearSkyIrradiance(sky, g0, at);
    // No beam; the sky loses its circumsolar part (Muneer's shaded-surface factor); the ground around reflects
    // only the sky's light.
    CHECK(shade.beam == 0.0);
    CHECK(shade.diffuse < 0.95 * lit.diffuse);
    CHECK(shade.diffuse > 0.5 * lit.diffuse);
    CHECK(shade.reflected < 0.5 * lit.reflected);
    CHECK(shade.reflected > 0.0);
    // The same surface seen by r.sun when the sun is behind it is its shaded value too.
    at.shadowed = false;
    at.cosIncidence = -0.1;
    CHECK(clearSkyIrradiance(sky, g0, at).diffuse == Approx(shade.diffuse));
    at.elevationRad = -0.01;
    const Irradiance night = clearSkyIrradiance(sky, g0, at);
    CHECK(night.global() == 0.0);
}
