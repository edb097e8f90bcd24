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
    // Pixel centres sit at (i + 0.5) / width: x wraps around, y clamps at the poles.
    const double x = (uv.x - std::floor(uv.x)) * image.width - 0.5;
    const double y = std::clamp(uv.y * image.height - 0.5, 0.0, double(image.height - 1));
    const int x0 = int(std::floor(x)), y0 = int(y);
    const int y1 = std::min(y0 + 1, image.height - 1);
    const float fx = float(x - x0), fy = float(y - y0);
    const auto at = [&](int i, int j) {
        i = ((i % image.width) + image.width) % image.width;
        const size_t k = (size_t(j) * size_t(image.width) + size_t(i)) * 3;
        return glm::vec3(image.rgb[k], image.rgb[k + 1], image.rgb[k + 2]);
    };
    return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y1), at(x0 + 1, y1), fx), fy);
}

}  // namespace terracast
