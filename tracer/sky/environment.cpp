#include "tracer/sky/environment.h"

#include "tracer/core/angles.h"

#include <algorithm>
#include <cmath>

namespace terracast {

glm::dvec2 environmentCoordinates(const glm::dvec3& dir) {
    const double azimuth = std::atan2(dir.x, dir.y);  // clockwise from north
    const double fromZenith = std::acos(std::clamp(dir.z / glm::length(dir), -1.0, 1.0));
    return {0.5 + azimuth / (2.0 * kPi), fromZenith / kPi};
}

glm::vec3 environmentRadiance(const EnvironmentImage& image, const glm::dvec3& dir, double rotationDeg) {
    if (image.width <= 0 || image.height <= 0) return glm::vec3(0.0f);
    glm::dvec2 uv = environmentCoordinates(dir);
    uv.x -= rotationDeg / 360.0;
    return sampleLatLong(image.width, image.height, uv, [&](int i, int j) {
        const size_t k = (size_t(j) * size_t(image.width) + size_t(i)) * 3;
        return glm::vec3(image.rgb[k], image.rgb[k + 1], image.rgb[k + 2]);
    });
}

}  // namespace terracast
