// Cameras: turn a film position into a primary ray.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"

#include <optional>
#include <string>

namespace terracast {

// A pinhole (perspective) camera in the grid's local frame.
struct PinholeCamera {
    glm::dvec3 eyeM{0.0};           // position, metres
    glm::dvec3 lookAtM{0, 1, 0};    // point looked at, metres
    glm::dvec3 up{0, 0, 1};         // approximate up direction
    double fovYDeg = 40.0;          // vertical field of view, degrees

    // The ray through film position (fx, fy) in [0, 1]^2, (0, 0) at the top-left corner, for a film of
    // the given aspect ratio (width / height). Directions are unit length, so t is a distance in metres.
    Ray generate(double fx, double fy, double aspect) const;
};

// The default view of a grid: from the south-west, looking north-east and about 30 degrees down, far
// enough back that the whole grid (heights included) fits the frame.
PinholeCamera autoCamera(const HeightGrid& grid, double aspect, double fovYDeg = 40.0);

// Parses "eye=x,y,z look=x,y,z fov=deg" (any order, fov optional; up optional as up=x,y,z).
// Returns an error message on failure.
std::optional<std::string> parseCamera(const std::string& text, PinholeCamera& camera);

}  // namespace terracast
