// Civil time against the C library's own calendar (timegm and gmtime_r), an independent implementation.
#include "tracer/sky/calendar.h"

#include <catch2/catch.hpp>

#include <ctime>
#include <string>

using namespace terracast;

namespace {

// Seconds since 1970 of a UTC date and time, by the C library.
int64_t libcSeconds(int y, int m, int d, int hh = 0, int mm = 0, int ss = 0) {
    std::tm t{};
    t.tm_year = y - 1900;
    t.tm_mon = m - 1;
    t.tm_mday = d;
    t.tm_hour = hh;
    t.tm_min = mm;
    t.tm_sec = ss;
    return int64_t(timegm(&t));
}

}  // namespace

TEST_CASE("Calendar: days from civil dates agree with the C library, and round-trip", "[tracer][sky]") {
    for (int y : {1, 1600, 1899, 1900, 1970, 1999, 2000, 2024, 2100, 2400, 9999})
        for (int m = 1; m <= 12; ++m)
            for (int d : {1, 28, int(daysInMonth(y, m))}) {
                INFO(y << "-" << m << "-" << d);
                const int64_t days = daysFromCivil(y, m, d);
                CHECK(days * 86400 == libcSeconds(y, m, d));
                const CivilDate back = civilFromDays(days);
                CHECK(back.year == y);
                CHECK(back.month == m);
                CHECK(back.day == d);
            }
    CHECK(daysInMonth(2024, 2) == 29);
    CHECK(daysInMonth(1900, 2) == 28);
    CHECK(daysInMonth(2000, 2) == 29);
}

TEST_CASE("Calendar: an ISO 8601 time with an offset is the UTC instant the C library gives", "[tracer][sky]") {
    struct Case {
        const char* text;
        int64_t utcSeconds;
    };
    const Case cases[] = {
        {"2026-06-21T21:30:00+02:00", libcSeconds(2026, 6, 21, 19, 30)},
        {"2026-01-01T00:30-01:30", libcSeconds(2026, 1, 1, 2, 0)},
        {"2024-03-01T00:15+0100", libcSeconds(2024, 2, 29, 23, 15)},  // back over a leap day
        {"1999-12-31T23:59:59-05", libcSeconds(2000, 1, 1, 4, 59, 59)},
        {"2026-06-21 19:30:07.25z", libcSeconds(2026, 6, 21, 19, 30, 7)},
    };
    for (const auto& c : cases) {
        INFO(c.text);
        std::string why;
        const auto t = parseIsoTime(c.text, why);
        REQUIRE(t);
        CHECK(libcSeconds(t->year, t->month, t->day, t->hour, t->minute, int(t->second)) == c.utcSeconds);
        // The canonical form reads back as the same instant.
        const auto again = parseIsoTime(formatUtc(*t), why);
        REQUIRE(again);
        CHECK(*again == *t);
    }
    std::string why;
    CHECK(formatUtc(*parseIsoTime("2026-06-21T21:30+02:00", why)) == "2026-06-21T19:30:00Z");
    CHECK_FALSE(parseIsoTime("2026-02-29T10:00Z", why));
    CHECK(why == "day 29 is not in month 02");
    CHECK_FALSE(parseIsoTime("9999-12-31T23:30-01:00", why));
    CHECK(why == "its UTC date falls outside the years 0001..9999");
}

TEST_CASE("Calendar: seconds since 1970 are the C library's, and come back as the same instant", "[tracer][sky]") {
    for (int64_t s : {int64_t(0), int64_t(-1), int64_t(86399), int64_t(951782399), int64_t(1782070207),
                      libcSeconds(1, 1, 1), libcSeconds(9999, 12, 31, 23, 59, 59), libcSeconds(1600, 2, 29, 12)}) {
        INFO(s);
        const auto t = instantFromUnixSeconds(s);
        REQUIRE(t);
        CHECK(unixSeconds(*t) == s);
        std::tm c{};
        const std::time_t tt = std::time_t(s);
        gmtime_r(&tt, &c);
        CHECK(t->year == c.tm_year + 1900);
        CHECK(t->month == c.tm_mon + 1);
        CHECK(t->day == c.tm_mday);
        CHECK(t->hour == c.tm_hour);
        CHECK(t->minute == c.tm_min);
        CHECK(int(t->second) == c.tm_sec);
    }
    CHECK_FALSE(instantFromUnixSeconds(libcSeconds(1, 1, 1) - 1));
    CHECK_FALSE(instantFromUnixSeconds(libcSeconds(9999, 12, 31, 23, 59, 59) + 1));
}
