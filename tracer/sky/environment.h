// An environment image: the light arriving from every direction, stored as an equirectangular picture (a
// latitude-longitude map, as HDR panoramas are distributed). `[sky] model = "image"` shows it behind the scene
// and lights the scene with it.
#pragma once

#include <glm/glm.hpp>

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

}  // namespace terracast
