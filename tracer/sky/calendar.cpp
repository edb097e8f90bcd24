#include "tracer/sky/calendar.h"

#include <cstdio>

namespace terracast {

namespace {

// `value` with at least two digits.
std::string twoDigits(int64_t value) {
    char text[32];
    std::snprintf(text, sizeof text, "%02lld", static_cast<long long>(value));
    return text;
}

}  // namespace

int64_t daysFromCivil(int64_t y, int64_t m, int64_t d) {
    y -= m <= 2 ? 1 : 0;
    const int64_t era = (y >= 0 ? y : y - 399) / 400;
    const int64_t yoe = y - era * 400;
    const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
    const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + doe - 719468;
}

CivilDate civilFromDays(int64_t z) {
    z += 719468;
    const int64_t era = (z >= 0 ? z : z - 146096) / 146097;
    const int64_t doe = z - era * 146097;
    const int64_t yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const int64_t doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const int64_t mp = (5 * doy + 2) / 153;
    const int64_t d = doy - (153 * mp + 2) / 5 + 1;
    const int64_t m = mp < 10 ? mp + 3 : mp - 9;
    return {era * 400 + yoe + (m <= 2 ? 1 : 0), m, d};
}

int64_t daysInMonth(int64_t year, int64_t month) {
    static constexpr int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
    return month == 2 && leap ? 29 : kDays[month - 1];
}

std::optional<std::string> readIsoTime(std::string_view text, ZonedTime& out) {
    size_t pos = 0;
    const auto digits = [&](size_t count, int64_t& value) {
        if (pos + count > text.size()) return false;
        value = 0;
        for (size_t i = 0; i < count; ++i) {
            const char c = text[pos + i];
            if (c < '0' || c > '9') return false;
            value = value * 10 + (c - '0');
        }
        pos += count;
        return true;
    };
    const auto literal = [&](char c) {
        if (pos >= text.size() || text[pos] != c) return false;
        ++pos;
        return true;
    };
    if (!digits(4, out.year) || !literal('-') || !digits(2, out.month) || !literal('-') || !digits(2, out.day))
        return "the date must be YYYY-MM-DD";
    if (!(literal('T') || literal('t') || literal(' '))) return "a time of day must follow the date after 'T'";
    if (!digits(2, out.hour) || !literal(':') || !digits(2, out.minute)) return "the time of day must be HH:MM";
    if (literal(':')) {
        if (!digits(2, out.second)) return "seconds must be two digits";
        if (literal('.')) {
            int64_t ignored = 0;
            if (!digits(1, ignored)) return "a decimal point must be followed by digits";
            while (digits(1, ignored)) {
            }
        }
    }
    if (literal('Z') || literal('z')) {
        out.offsetMinutes = 0;
    } else if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) {
        const int64_t sign = text[pos++] == '-' ? -1 : 1;
        int64_t hours = 0;
        int64_t minutes = 0;
        if (!digits(2, hours)) return "the offset from UTC must be +HH:MM";
        if (literal(':') ? !digits(2, minutes) : (pos < text.size() && !digits(2, minutes)))
            return "the offset from UTC must be +HH:MM";
        if (hours > 23 || minutes > 59) return "the offset from UTC must be at most 23:59";
        out.offsetMinutes = sign * (hours * 60 + minutes);
    } else {
        return "the time needs a zone: Z for UTC or an offset such as +02:00";
    }
    if (pos != text.size()) return "unexpected text after the time";
    if (out.month < 1 || out.month > 12) return "month " + std::to_string(out.month) + " is not in 01..12";
    if (out.day < 1 || out.day > daysInMonth(out.year, out.month))
        return "day " + std::to_string(out.day) + " is not in month " + twoDigits(out.month);
    if (out.hour > 23) return "hour " + std::to_string(out.hour) + " is not in 00..23";
    if (out.minute > 59) return "minute " + std::to_string(out.minute) + " is not in 00..59";
    if (out.second > 59) return "second " + std::to_string(out.second) + " is not in 00..59";
    return std::nullopt;
}

int64_t unixSeconds(const UtcInstant& t) {
    return daysFromCivil(t.year, t.month, t.day) * 86400 + t.hour * 3600 + t.minute * 60 + int64_t(t.second);
}

std::optional<UtcInstant> instantFromUnixSeconds(int64_t seconds) {
    const int64_t days = seconds >= 0 ? seconds / 86400 : -((-seconds + 86399) / 86400);
    const int64_t inDay = seconds - days * 86400;
    const CivilDate date = civilFromDays(days);
    if (date.year < 1 || date.year > 9999) return std::nullopt;
    return UtcInstant{int(date.year), int(date.month), int(date.day), int(inDay / 3600), int(inDay / 60 % 60),
                      double(inDay % 60)};
}

std::optional<UtcInstant> toUtc(const ZonedTime& t) {
    return instantFromUnixSeconds(daysFromCivil(t.year, t.month, t.day) * 86400 + t.hour * 3600 + t.minute * 60 +
                                  t.second - t.offsetMinutes * 60);
}

std::optional<UtcInstant> parseIsoTime(std::string_view text, std::string& why) {
    ZonedTime zoned;
    if (const auto problem = readIsoTime(text, zoned)) {
        why = *problem;
        return std::nullopt;
    }
    const auto utc = toUtc(zoned);
    if (!utc) why = "its UTC date falls outside the years 0001..9999";
    return utc;
}

std::string formatUtc(const UtcInstant& t) {
    char text[64];
    std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02dZ", t.year, t.month, t.day, t.hour, t.minute,
                  int(t.second));
    return text;
}

}  // namespace terracast
