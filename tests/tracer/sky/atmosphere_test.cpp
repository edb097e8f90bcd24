// The single-scattering atmosphere against direct numerical integration, and the qualitative physics of a
// clear sky as assertions.
#include "tracer/core/angles.h"
#include "tracer/sky/atmosphere.h"

#include "tracer/scene/scene.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

using namespace terracast;

namespace {


// A unit direction by compass azimuth and elevation, degrees.
glm::dvec3 fromAngles(double azimuthDeg, double elevationDeg) { return directionFromDegrees(azimuthDeg, elevationDeg); }

double maxRelativeError(const glm::dvec3& value, const glm::dvec3& reference) {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(value[c] / reference[c] - 1.0));
    return worst;
}

const std::shared_ptr<const TransmittanceTable>& table() {
    static const auto t = std::make_shared<const TransmittanceTable>(AtmosphereParameters{});
    return t;
}

}  // namespace

TEST_CASE("Optical depth straight up matches the closed form of an exponential atmosphere", "[tracer][sky]") {
    // Vertically, the integral of beta exp(-h / H) from 0 to the top is beta H (1 - exp(-top / H)).
    const AtmosphereParameters a;
    const double top = a.topRadiusM - a.earthRadiusM;
    for (const double h0 : {0.0, 1500.0, 9000.0}) {
        const glm::dvec3 tau = opticalDepthToTop(a, a.earthRadiusM + h0, 1.0, 2000);
        const auto closed = [&](double beta, double H) { return beta * H * (std::exp(-h0 / H) - std::exp(-top / H)); };
        const glm::dvec3 expected = glm::dvec3(closed(a.rayleighScattering.x, a.rayleighScaleHeightM),
                                               closed(a.rayleighScattering.y, a.rayleighScaleHeightM),
                                               closed(a.rayleighScattering.z, a.rayleighScaleHeightM)) +
                                    glm::dvec3(closed(a.mieExtinction, a.mieScaleHeightM));
        INFO("altitude " << h0);
        CHECK(maxRelativeError(tau, expected) < 1e-9);
    }
}

TEST_CASE("The transmittance table matches direct integration within 0.1 %", "[tracer][sky]") {
    // Every altitude from the ground to the top, every direction from the zenith down to the horizon, the
    // rows packed towards the horizon where optical depth changes fastest.
    const AtmosphereParameters a;
    double worst = 0.0;
    int checked = 0;
    for (double h = 0.0; h <= 60000.0; h += h < 3000.0 ? 250.0 : 2500.0) {
        const double r = a.earthRadiusM + h;
        const double horizon = -std::acos(a.earthRadiusM / r);
        for (int k = 0; k <= 60; ++k) {
            const double e = horizon + 1e-6 + (0.5 * kPi - horizon) * std::pow(k / 60.0, 2.0);
            const double mu = std::sin(e);
            const glm::dvec3 reference = glm::exp(-opticalDepthToTop(a, r, mu, 8000));
            worst = std::max(worst, maxRelativeError(table()->toTop(r, mu), reference));
            ++checked;
        }
    }
    INFO(checked << " rays, worst relative error " << worst);
    CHECK(worst < 1e-3);
    // A ray into the ground never reaches the top.
    CHECK(table()->toTop(a.earthRadiusM + 1000.0, -0.5) == glm::dvec3(0.0));
}

TEST_CASE("The sky tables match brute-force single scattering within 1 %", "[tracer][sky]") {
    // Over sun elevations from 2 to 85 degrees and view directions all round, from straight down through the
    // horizon to the zenith; the brute force integrates sunlight transmittance directly at every step.
    const AtmosphereParameters a;
    const double altitude = 1500.0;
    double worst = 0.0;
    int checked = 0;
    for (const double sunEl : {2.0, 12.0, 35.0, 85.0}) {
        const glm::dvec3 sun = fromAngles(40.0, sunEl);
        const SkyTables sky(table(), altitude, sun);
        for (const double el : {-60.0, -8.0, -1.0, 0.0, 0.7, 3.0, 10.0, 30.0, 60.0, 89.0})
            for (const double az : {40.0, 55.0, 130.0, 220.0, 300.0}) {
                const glm::dvec3 v = fromAngles(az, el);
                const glm::dvec3 reference = referenceRadiance(a, altitude, v, sun, 1500);
                const double e = maxRelativeError(glm::dvec3(sky.radiance(v)), reference);
                INFO("sun " << sunEl << ", view azimuth " << az << " elevation " << el);
                CHECK(e < 0.01);
                worst = std::max(worst, e);
                ++checked;
            }
    }
    INFO(checked << " directions, worst relative error " << worst);
    CHECK(worst < 0.01);
}

TEST_CASE("Aerial perspective matches brute-force integration along the segment", "[tracer][sky]") {
    const AtmosphereParameters a;
    const double altitude = 2000.0;
    const glm::dvec3 sun = fromAngles(250.0, 25.0);
    const SkyTables sky(table(), altitude, sun);
    for (const double el : {-3.0, -0.5, 0.0, 2.0, 10.0})
        for (const double distance : {800.0, 5000.0, 30000.0, 90000.0}) {
            const glm::dvec3 v = fromAngles(200.0, el);
            // Only segments that stay above the ground: the table holds the air, not the Earth behind it.
            const double r = a.earthRadiusM + altitude;
            if (rayHitsGround(a, r, v.z) && -r * v.z - std::sqrt(r * r * (v.z * v.z - 1.0) + a.earthRadiusM * a.earthRadiusM) < distance)
                continue;
            glm::vec3 transmittance, inscattered;
            sky.aerial(v, distance, transmittance, inscattered);
            const glm::dvec3 reference = referenceRadiance(a, altitude, v, sun, 1500, distance);
            // Transmittance of the segment, from the integral of extinction along it.
            glm::dvec3 tau(0.0);
            const int n = 4000;
            for (int i = 0; i < n; ++i) {
                const glm::dvec3 p = glm::dvec3(0.0, 0.0, r) + (i + 0.5) * distance / n * v;
                tau += a.extinctionAt(glm::length(p) - a.earthRadiusM) * (distance / n);
            }
            INFO("elevation " << el << ", distance " << distance);
            CHECK(maxRelativeError(glm::dvec3(inscattered), reference) < 0.02);
            CHECK(maxRelativeError(glm::dvec3(transmittance), glm::exp(-tau)) < 0.01);
        }
}

TEST_CASE("A clear noon sky is blue at the zenith and paler at the horizon", "[tracer][sky]") {
    const SkyTables sky(table(), 500.0, fromAngles(180.0, 70.0));
    const glm::vec3 zenith = sky.radiance({0.0, 0.0, 1.0});
    CHECK(zenith.b > zenith.g);
    CHECK(zenith.g > zenith.r);
    // The horizon, away from the sun: brighter, and less saturated (max / min of the channels nearer one).
    const glm::vec3 horizon = sky.radiance(fromAngles(0.0, 1.0));
    const auto luminance = [](const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; };
    const auto saturation = [](const glm::vec3& c) { return std::max({c.r, c.g, c.b}) / std::min({c.r, c.g, c.b}); };
    CHECK(luminance(horizon) > luminance(zenith));
    CHECK(saturation(horizon) < saturation(zenith));
}

TEST_CASE("A low sun's light is reddened: red above green above blue at 2 degrees", "[tracer][sky]") {
    const AtmosphereParameters a;
    const glm::dvec3 t = table()->sunlight(a.earthRadiusM + 200.0, std::sin(2.0 * kPi / 180.0));
    CHECK(t.r > t.g);
    CHECK(t.g > t.b);
    CHECK(t.b > 0.0);
    // And a high sun much less so.
    const glm::dvec3 high = table()->sunlight(a.earthRadiusM + 200.0, std::sin(60.0 * kPi / 180.0));
    CHECK(high.b / high.r > 5.0 * t.b / t.r);
    // Below the horizon it is gone.
    CHECK(table()->sunlight(a.earthRadiusM + 200.0, std::sin(-2.0 * kPi / 180.0)) == glm::dvec3(0.0));
}

TEST_CASE("The sky is symmetric about the sun's vertical plane", "[tracer][sky]") {
    const AtmosphereParameters a;
    const double sunAz = 123.0;
    const glm::dvec3 sun = fromAngles(sunAz, 20.0);
    const SkyTables sky(table(), 800.0, sun);
    for (const double off : {5.0, 40.0, 100.0, 170.0})
        for (const double el : {-5.0, 2.0, 25.0}) {
            const glm::vec3 left = sky.radiance(fromAngles(sunAz - off, el));
            const glm::vec3 right = sky.radiance(fromAngles(sunAz + off, el));
            INFO("azimuth offset " << off << ", elevation " << el);
            for (int c = 0; c < 3; ++c) CHECK(left[c] == Approx(right[c]).epsilon(1e-5));
            // The brute force agrees that the sides match: it knows nothing of the tables' folding.
            const glm::dvec3 refLeft = referenceRadiance(a, 800.0, fromAngles(sunAz - off, el), sun, 400);
            const glm::dvec3 refRight = referenceRadiance(a, 800.0, fromAngles(sunAz + off, el), sun, 400);
            CHECK(maxRelativeError(refLeft, refRight) < 1e-9);
        }
    // And it is not symmetric about other planes: towards the sun is brighter than away from it.
    CHECK(sky.radiance(fromAngles(sunAz, 10.0)).r > 2.0f * sky.radiance(fromAngles(sunAz + 180.0, 10.0)).r);
}

TEST_CASE("Below the horizon the tables return the lit ground through the air, not sky", "[tracer][sky]") {
    const AtmosphereParameters a;
    const double altitude = 3000.0;
    const glm::dvec3 sun = fromAngles(90.0, 40.0);
    const SkyTables sky(table(), altitude, sun);
    CHECK(sky.horizonElevation() < 0.0);
    // Just under the viewer's horizon the ray ends on the ground; its radiance is the brute force that stops there
    // and adds the ground's reflection, and differs from the sky just above.
    const double below = sky.horizonElevation() * 180.0 / kPi - 0.3;
    for (const double el : {below, -10.0, -45.0}) {
        const glm::dvec3 v = fromAngles(270.0, el);
        INFO("elevation " << el);
        CHECK(maxRelativeError(glm::dvec3(sky.radiance(v)), referenceRadiance(a, altitude, v, sun, 1500)) < 0.01);
    }
    // With no ground reflection at all, looking down still shows only the air in front of the ground.
    AtmosphereParameters dark;
    dark.groundAlbedo = 0.0;
    const glm::dvec3 down = fromAngles(270.0, -45.0);
    CHECK(referenceRadiance(dark, altitude, down, sun, 1500).b < referenceRadiance(a, altitude, down, sun, 1500).b);
}

TEST_CASE("Haze scales aerosol scattering: more haze, a whiter and brighter sky around the sun", "[tracer][sky]") {
    AtmosphereParameters hazy;
    hazy.haze = 4.0;
    const auto hazyTable = std::make_shared<const TransmittanceTable>(hazy);
    const glm::dvec3 sun = fromAngles(180.0, 30.0);
    const SkyTables clear(table(), 300.0, sun), thick(hazyTable, 300.0, sun);
    // Aerosols scatter mostly forwards: looking 10 degrees beside the sun.
    const glm::vec3 c = clear.radiance(fromAngles(190.0, 30.0)), h = thick.radiance(fromAngles(190.0, 30.0));
    CHECK(h.r > c.r);
    CHECK(h.r / h.b > c.r / c.b);
}
