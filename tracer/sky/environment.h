// An environment image: the light arriving from every direction, stored as an equirectangular picture (a
// latitude-longitude map, as HDR panoramas are distributed). `[sky] model = "image"` shows it behind the scene
// and lights the scene with it.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

namespace terracast {

// Linear RGB radiance, row 0 at the zenith and the last row at the nadir; the middle column looks north (+y)
// and azimuth grows to the right (east), so the picture is the view from inside the sphere.
struct EnvironmentImage {
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width * height * 3
};

// The image's radiance along unit direction `dir` (x east, y north, z up), the image turned by `rotationDeg`
// about the vertical (clockwise seen from above: 90 puts the image's north in the east). Bilinear between
// pixel centres, wrapping in azimuth.
glm::vec3 environmentRadiance(const EnvironmentImage& image, const glm::dvec3& dir, double rotationDeg);

// The image position (u, v) in [0, 1]^2 of a direction, before any rotation: u = 0.5 + azimuth / 360 degrees
// (azimuth clockwise from north, in (-180, 180]), v = the angle from the zenith / 180 degrees.
glm::dvec2 environmentCoordinates(const glm::dvec3& dir);

// Bilinear interpolation on a width x height latitude-longitude grid at (u, v) in the layout above: sample
// centres at ((i + 0.5) / width, (j + 0.5) / height), wrapping around in u, clamped at the poles in v.
// `at(i, j)` reads sample i in [0, width) of row j in [0, height).
template <class At>
glm::vec3 sampleLatLong(int width, int height, glm::dvec2 uv, At&& at) {
    const double x = (uv.x - std::floor(uv.x)) * width - 0.5;
    const double y = std::clamp(uv.y * height - 0.5, 0.0, double(height - 1));
    const int x0 = int(std::floor(x)), y0 = int(y), y1 = std::min(y0 + 1, height - 1);
    const float fx = float(x - x0), fy = float(y - y0);
    const auto wrapped = [&](int i, int j) { return glm::vec3(at(((i % width) + width) % width, j)); };
    return glm::mix(glm::mix(wrapped(x0, y0), wrapped(x0 + 1, y0), fx),
                    glm::mix(wrapped(x0, y1), wrapped(x0 + 1, y1), fx), fy);
}

}  // namespace terracast
