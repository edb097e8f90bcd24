// Where the sun stands for an instant and a place on the Earth, by the NOAA solar calculator's equations
// (after Meeus 1991, "Astronomical Algorithms"; good to about 0.01 degree for years 1800..2100).
#pragma once

#include "tracer/sky/calendar.h"

namespace terracast {

struct SolarPosition {
    double azimuthDeg = 0.0;            // clockwise from true north
    double elevationDeg = 0.0;          // geometric, above the horizon
    double apparentElevationDeg = 0.0;  // with the NOAA estimate of atmospheric refraction
};

// The sun's position seen from latitude and longitude (degrees, east positive) at an instant.
SolarPosition solarPosition(const UtcInstant& when, double latitudeDeg, double longitudeDeg);

}  // namespace terracast
