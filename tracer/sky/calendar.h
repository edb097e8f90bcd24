// Civil time: dates of the proleptic Gregorian calendar, ISO 8601 instants with a zone, and the UTC instant
// that the sun's position is computed for. The scene-file reader and the CLI's --sun-time both read times here.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace terracast {

// An instant in UTC, to the second.
struct UtcInstant {
    int year = 2000;
    int month = 1;    // 1..12
    int day = 1;      // 1..31
    int hour = 0;     // 0..23
    int minute = 0;   // 0..59
    double second = 0.0;

    bool operator==(const UtcInstant&) const = default;
};

// Days from 1970-01-01 to a date, and back (Hinnant, "chrono-Compatible Low-Level Date Algorithms", 2013).
int64_t daysFromCivil(int64_t year, int64_t month, int64_t day);
struct CivilDate {
    int64_t year;
    int64_t month;
    int64_t day;
};
CivilDate civilFromDays(int64_t days);
int64_t daysInMonth(int64_t year, int64_t month);

// A date and time of day with its offset from UTC, as written.
struct ZonedTime {
    int64_t year = 0, month = 0, day = 0, hour = 0, minute = 0, second = 0;
    int64_t offsetMinutes = 0;
};

// Reads an ISO 8601 time with a zone: YYYY-MM-DDTHH:MM[:SS[.fff]] then Z or +HH:MM, +HHMM, +HH (or -).
// Returns the reason when `text` is not one.
std::optional<std::string> readIsoTime(std::string_view text, ZonedTime& out);

// The same instant in UTC (fractions of a second dropped), or nothing when an offset moves it out of the years
// 0001..9999.
std::optional<UtcInstant> toUtc(const ZonedTime& time);

// Whole seconds since 1970-01-01T00:00Z (the fraction of a second dropped), and back: nothing outside the years
// 0001..9999.
int64_t unixSeconds(const UtcInstant& t);
std::optional<UtcInstant> instantFromUnixSeconds(int64_t seconds);

// readIsoTime then toUtc; on failure, `why` says what is wrong.
std::optional<UtcInstant> parseIsoTime(std::string_view text, std::string& why);

// "YYYY-MM-DDTHH:MM:SSZ".
std::string formatUtc(const UtcInstant& t);

}  // namespace terracast
