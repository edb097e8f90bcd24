// Solar positions against published values.
#include "tracer/sky/sun_position.h"

#include <catch2/catch.hpp>

using namespace terracast;

TEST_CASE("Solar positions match published values within 0.1 degree", "[tracer][sky]") {
    // NREL's Solar Position Algorithm report (Reda and Andreas 2004, table A5.1) and the value its reference
    // code gives a day later: Golden, Colorado (39.742476 N, 105.1786 W), 2003-10-17 and -18 at 19:30:30 UTC.
    struct Published {
        UtcInstant when;
        double elevationDeg, azimuthDeg;
    };
    const Published cases[] = {
        {{2003, 10, 17, 19, 30, 30.0}, 39.872046, 194.340241},
        {{2003, 10, 18, 19, 30, 30.0}, 39.505196, 194.311132},
    };
    for (const auto& c : cases) {
        const SolarPosition p = solarPosition(c.when, 39.742476, -105.1786);
        INFO("day " << c.when.day);
        CHECK(p.elevationDeg == Approx(c.elevationDeg).margin(0.1));
        CHECK(p.azimuthDeg == Approx(c.azimuthDeg).margin(0.1));
        // Refraction lifts the sun by about a minute of arc at 40 degrees.
        CHECK(p.apparentElevationDeg - p.elevationDeg == Approx(0.02).margin(0.01));
    }
}

TEST_CASE("At published sunrise times the sun's centre stands 0.833 degree below the horizon", "[tracer][sky]") {
    // NREL's SPA sunrise times for Golden, Colorado (MST = UTC - 7), where sunrise means the geometric
    // centre at -0.8333 degree (refraction plus the sun's radius).
    const UtcInstant sunrises[] = {{2015, 1, 2, 14, 21, 55.0}, {2015, 8, 2, 12, 0, 27.0}};
    for (const auto& when : sunrises) {
        const SolarPosition p = solarPosition(when, 39.742476, -105.1786);
        INFO("month " << when.month);
        CHECK(p.elevationDeg == Approx(-0.8333).margin(0.1));
        CHECK(p.azimuthDeg > 45.0);  // in the east
        CHECK(p.azimuthDeg < 135.0);
    }
}

TEST_CASE("Canonical UTC times are read back and malformed ones refused", "[tracer][sky]") {
    std::string why;
    const auto t = parseIsoTime("2026-06-21T19:30:05Z", why);
    REQUIRE(t);
    CHECK(t->year == 2026);
    CHECK(t->month == 6);
    CHECK(t->day == 21);
    CHECK(t->hour == 19);
    CHECK(t->minute == 30);
    CHECK(t->second == 5.0);
    CHECK_FALSE(parseIsoTime("2026-06-21T19:30:05", why));
    CHECK_FALSE(parseIsoTime("2026-13-21T19:30:05Z", why));
    CHECK_FALSE(parseIsoTime("2026-06-21T19:30:05Z trailing", why));
}
