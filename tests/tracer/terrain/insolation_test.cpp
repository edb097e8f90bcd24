// Insolation per vertex: a day's sums on planes against GRASS r.sun's, and a ridge's cast shadow against its
// geometry.
#include "tracer/core/angles.h"
#include "tracer/terrain/insolation.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace terracast;

namespace {

// The sun over a day at latitude `latDeg` for a declination, as r.sun's geometry places it (local solar time,
// hour angle 15 degrees an hour; no refraction), at the middle of each `stepH`-hour interval.
std::vector<SunStep> solarDay(double latDeg, double declinationRad, double g0, double stepH) {
    const double phi = radians(latDeg), delta = declinationRad;
    std::vector<SunStep> steps;
    for (double t = 0.5 * stepH; t < 24.0; t += stepH) {
        const double omega = radians(15.0 * (t - 12.0));
        const double sinH = std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(omega);
        const double h = std::asin(sinH);
        const double cosA = (std::sin(delta) - sinH * std::sin(phi)) / (std::cos(h) * std::cos(phi));
        const double a = std::acos(std::clamp(cosA, -1.0, 1.0));
        SunStep s;
        s.azimuthRad = omega < 0.0 ? a : 2.0 * kPi - a;  // east in the morning
        s.elevationRad = s.apparentElevationRad = h;
        s.extraterrestrial = g0;
        s.hours = stepH;
        steps.push_back(s);
    }
    return steps;
}

// A plane through (0, 0, z0) falling at `slopeDeg` towards `aspectDeg` (clockwise from north).
HeightGrid tiltedPlane(int64_t n, double cellM, double slopeDeg, double aspectDeg, double z0) {
    std::vector<float> z(size_t(n * n));
    const double t = std::tan(radians(slopeDeg)), a = radians(aspectDeg);
    for (int64_t j = 0; j < n; ++j)
        for (int64_t i = 0; i < n; ++i)
            z[size_t(j * n + i)] = float(z0 - t * cellM * (double(i) * std::sin(a) + double(j) * std::cos(a)));
    return HeightGrid(n, n, cellM, cellM, z);
}

}  // namespace

TEST_CASE("Insolation: a day on planes sums to GRASS r.sun's daily irradiation", "[tracer][maps]") {
    // r.sun 8.2, mode 2 with step=0.05 h, -p (no terrain shadows, which a plane has none of): day 172, latitude
    // 44.995 N, 500 m, Linke 3, albedo 0.2 (scripts/compare_grass.sh). Wh/m^2 and hours; r.sun counts sunshine
    // in whole steps.
    struct Case {
        double slopeDeg, aspectDeg, beam, diffuse, reflected, sunshineH;
    };
    const Case cases[] = {
        {0, 180, 7691.773, 1278.647, 0, 15.4},
        {30, 180, 7288.274, 1237.801, 118.8074, 12.9},
        {30, 90, 6964.731, 1297.732, 113.7313, 12.4},
    };
    InsolationSettings s;
    s.steps = solarDay(44.995, 0.409115, extraterrestrialIrradiance(172, 1367.0), 0.05);
    for (const Case& c : cases) {
        // The plane's middle vertex stands at 500 m.
        const HeightGrid g = tiltedPlane(11, 10.0, c.slopeDeg, c.aspectDeg, 500.0 + 50.0 * std::tan(radians(c.slopeDeg)) *
                                         (std::sin(radians(c.aspectDeg)) + std::cos(radians(c.aspectDeg))));
        REQUIRE(g.at(5, 5) == Approx(500.0).margin(1e-3));
        const MapRaster r = insolationMap(g, s);
        REQUIRE(r.bands == kInsolationBands);
        INFO("slope " << c.slopeDeg << " aspect " << c.aspectDeg);
        CHECK(r.at(5, 5, kBeamBand) == Approx(c.beam).epsilon(2e-3));
        CHECK(r.at(5, 5, kDiffuseBand) == Approx(c.diffuse).epsilon(2e-3));
        CHECK(r.at(5, 5, kReflectedBand) == Approx(c.reflected).epsilon(2e-3).margin(1e-6));
        CHECK(r.at(5, 5, kGlobalBand) == Approx(c.beam + c.diffuse + c.reflected).epsilon(2e-3));
        CHECK(r.at(5, 5, kSunshineBand) == Approx(c.sunshineH).margin(0.06));
    }
}

TEST_CASE("Insolation: a ridge's shadow takes the sun exactly while it is below the ridge's crest", "[tracer][maps]") {
    // Flat ground at 0 m with an east-west ridge: the vertex row j = 10 at 100 m (its flanks fall over one cell
    // each side), cells of 10 m, 61 x 81 vertices. From vertex (30, 40), 300 m north of the crest, the crest lies
    // at slope 100 cos(t) / 300 towards azimuth 180 + t for |t| < 45 degrees (the crest ends at the grid's edges).
    const int64_t w = 61, h = 81;
    std::vector<float> z(size_t(w * h), 0.0f);
    for (int64_t i = 0; i < w; ++i) z[size_t(10 * w + i)] = 100.0f;
    const HeightGrid g(w, h, 10.0, 10.0, z);
    // A winter sun sweeping from south-east to south-west, rising to 25 degrees and back, every quarter hour (never
    // exactly at 45 degrees from south, where the line passes through the crest's end at the grid's corner).
    InsolationSettings s;
    const double g0 = extraterrestrialIrradiance(355, 1367.0);
    const auto shadowed = [](const SunStep& sun) {
        const double t = sun.azimuthRad - kPi;
        return std::abs(t) < radians(45.0) && std::tan(sun.apparentElevationRad) < 100.0 * std::cos(t) / 300.0;
    };
    int inShadow = 0, lit = 0;
    for (int k = 0; k <= 40; ++k) {
        SunStep sun;
        sun.azimuthRad = radians(131.25 + 2.5 * k);
        sun.elevationRad = radians(25.0 * std::sin(kPi * (k + 0.5) / 41.0));
        sun.apparentElevationRad = sun.elevationRad + radians(0.01);
        sun.extraterrestrial = g0;
        sun.hours = 0.25;
        // No step within rounding of the crest (a grazing sun is lit, but that is the horizon tests' business).
        const double t = sun.azimuthRad - kPi;
        if (std::abs(std::tan(sun.apparentElevationRad) - 100.0 * std::cos(t) / 300.0) < 1e-3) continue;
        s.steps.push_back(sun);
        (shadowed(sun) ? inShadow : lit) += 1;
    }
    REQUIRE(inShadow > 5);
    REQUIRE(lit > 5);
    const MapRaster r = insolationMap(g, s);
    // The same sums from the crest's geometry and the clear-sky model on flat ground.
    double beam = 0.0, diffuse = 0.0, sunshine = 0.0;
    for (const SunStep& sun : s.steps) {
        SunOnSurface at;
        at.elevationRad = sun.elevationRad;
        at.azimuthRad = sun.azimuthRad;
        at.cosIncidence = std::sin(sun.apparentElevationRad);
        at.shadowed = shadowed(sun);
        const Irradiance e = clearSkyIrradiance(s.sky, g0, at);
        beam += e.beam * sun.hours;
        diffuse += e.diffuse * sun.hours;
        sunshine += at.shadowed ? 0.0 : sun.hours;
    }
    CHECK(r.at(30, 40, kSunshineBand) == Approx(sunshine).margin(1e-6));
    CHECK(r.at(30, 40, kBeamBand) == Approx(beam).epsilon(1e-6));
    CHECK(r.at(30, 40, kDiffuseBand) == Approx(diffuse).epsilon(1e-6));
    CHECK(r.at(30, 40, kReflectedBand) == 0.0f);
    // Far north of the ridge (600 m from the crest) the sun is in the shadow only below 9.5 degrees; on the
    // ridge's own crest nothing shadows it.
    CHECK(r.at(30, 70, kSunshineBand) > r.at(30, 40, kSunshineBand));
    CHECK(r.at(30, 10, kSunshineBand) == Approx(0.25 * double(s.steps.size())).margin(1e-6));
    // A hole in the grid: no value there.
    std::vector<uint8_t> valid(size_t(w * h), 1);
    valid[size_t(40 * w + 30)] = 0;
    const MapRaster rh = insolationMap(HeightGrid(w, h, 10.0, 10.0, z, valid), s);
    CHECK(std::isnan(rh.at(30, 40, kGlobalBand)));
    CHECK(!std::isnan(rh.at(31, 40, kGlobalBand)));
}
