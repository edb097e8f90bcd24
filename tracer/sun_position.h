// Where the sun stands for an instant and a place on the Earth, by the NOAA solar calculator's equations
// (after Meeus 1991, "Astronomical Algorithms"; good to about 0.01 degree for years 1800..2100).
#pragma once

#include <optional>
#include <string>

namespace terracast {

// An instant in UTC.
struct UtcInstant {
    int year = 2000;
    int month = 1;    // 1..12
    int day = 1;      // 1..31
    int hour = 0;     // 0..23
    int minute = 0;   // 0..59
    double second = 0.0;
};

// Reads the canonical UTC form "YYYY-MM-DDTHH:MM:SSZ" (as the scene reader and the CLI normalise times to).
std::optional<UtcInstant> parseCanonicalUtc(const std::string& text);

struct SolarPosition {
    double azimuthDeg = 0.0;            // clockwise from true north
    double elevationDeg = 0.0;          // geometric, above the horizon
    double apparentElevationDeg = 0.0;  // with the NOAA estimate of atmospheric refraction
};

// The sun's position seen from latitude and longitude (degrees, east positive) at an instant.
SolarPosition solarPosition(const UtcInstant& when, double latitudeDeg, double longitudeDeg);

}  // namespace terracast
