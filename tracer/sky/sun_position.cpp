#include "tracer/sky/sun_position.h"

#include "tracer/core/angles.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace terracast {

namespace {

// Refraction in degrees at a geometric elevation, as the NOAA calculator estimates it (standard atmosphere).
double refractionDeg(double elevationDeg) {
    if (elevationDeg > 85.0) return 0.0;
    const double t = std::tan(radians(elevationDeg));
    double arcsec;
    if (elevationDeg > 5.0)
        arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
    else if (elevationDeg > -0.575)
        arcsec = 1735.0 + elevationDeg * (-518.2 + elevationDeg * (103.4 + elevationDeg * (-12.79 + elevationDeg * 0.711)));
    else
        arcsec = -20.772 / t;
    return arcsec / 3600.0;
}

}  // namespace

SolarPosition solarPosition(const UtcInstant& when, double latitudeDeg, double longitudeDeg) {
    const double dayMinutes = when.hour * 60.0 + when.minute + when.second / 60.0;
    const double julianDay = double(daysFromCivil(when.year, when.month, when.day)) + 2440587.5 +
                             dayMinutes / 1440.0;
    const double T = (julianDay - 2451545.0) / 36525.0;  // Julian centuries since J2000.0

    // The sun's ecliptic longitude and the Earth's orbit.
    const double meanLongitude = std::fmod(280.46646 + T * (36000.76983 + T * 0.0003032), 360.0);
    const double meanAnomaly = 357.52911 + T * (35999.05029 - 0.0001537 * T);
    const double eccentricity = 0.016708634 - T * (0.000042037 + 0.0000001267 * T);
    const double M = radians(meanAnomaly);
    const double centre = std::sin(M) * (1.914602 - T * (0.004817 + 0.000014 * T)) +
                          std::sin(2 * M) * (0.019993 - 0.000101 * T) + std::sin(3 * M) * 0.000289;
    const double omega = radians(125.04 - 1934.136 * T);
    const double apparentLongitude = meanLongitude + centre - 0.00569 - 0.00478 * std::sin(omega);

    // Obliquity, declination and the equation of time.
    const double meanObliquity = 23.0 + (26.0 + (21.448 - T * (46.815 + T * (0.00059 - T * 0.001813))) / 60.0) / 60.0;
    const double obliquity = radians(meanObliquity + 0.00256 * std::cos(omega));
    const double declination = std::asin(std::sin(obliquity) * std::sin(radians(apparentLongitude)));
    const double y = std::pow(std::tan(obliquity / 2.0), 2);
    const double L0 = radians(meanLongitude);
    const double equationOfTimeMin =
        4.0 * degrees(y * std::sin(2 * L0) - 2 * eccentricity * std::sin(M) +
                  4 * eccentricity * y * std::sin(M) * std::cos(2 * L0) - 0.5 * y * y * std::sin(4 * L0) -
                  1.25 * eccentricity * eccentricity * std::sin(2 * M));

    // Hour angle from the true solar time, then the horizontal coordinates.
    double trueSolarMin = std::fmod(dayMinutes + equationOfTimeMin + 4.0 * longitudeDeg, 1440.0);
    if (trueSolarMin < 0.0) trueSolarMin += 1440.0;
    double hourAngle = trueSolarMin / 4.0 - 180.0;
    if (hourAngle < -180.0) hourAngle += 360.0;
    const double lat = radians(latitudeDeg), ha = radians(hourAngle);
    const double cosZenith = std::clamp(std::sin(lat) * std::sin(declination) +
                                            std::cos(lat) * std::cos(declination) * std::cos(ha),
                                        -1.0, 1.0);
    const double zenith = std::acos(cosZenith);
    // Azimuth from north, clockwise: from the spherical triangle pole-zenith-sun, signed by the hour angle.
    const double azimuth = std::atan2(std::sin(ha), std::cos(ha) * std::sin(lat) - std::tan(declination) * std::cos(lat));
    SolarPosition p;
    p.azimuthDeg = std::fmod(degrees(azimuth) + 180.0 + 360.0, 360.0);
    p.elevationDeg = 90.0 - degrees(zenith);
    p.apparentElevationDeg = p.elevationDeg + refractionDeg(p.elevationDeg);
    return p;
}

}  // namespace terracast
