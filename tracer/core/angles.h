// Angles and directions in the one convention every part of terracast uses: x east, y north, z up; azimuth
// clockwise from north, elevation above the horizontal plane. Pi itself is GLM's constant.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include <cmath>

namespace terracast {

inline constexpr double kPi = glm::pi<double>();

inline double radians(double degrees) { return degrees * kPi / 180.0; }
inline double degrees(double radians) { return radians * 180.0 / kPi; }

// The unit vector at `azimuthRad` clockwise from north and `elevationRad` above the horizon.
inline glm::dvec3 directionFromRadians(double azimuthRad, double elevationRad) {
    return {std::sin(azimuthRad) * std::cos(elevationRad), std::cos(azimuthRad) * std::cos(elevationRad),
            std::sin(elevationRad)};
}

// The same from degrees: the direction towards a sun at (azimuth, elevation).
inline glm::dvec3 directionFromDegrees(double azimuthDeg, double elevationDeg) {
    return directionFromRadians(radians(azimuthDeg), radians(elevationDeg));
}

}  // namespace terracast
