// Cameras: turn a film position into a primary ray.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"
#include "tracer/camera/camera.h"

#include <optional>
#include <string>

namespace terracast {

// A pinhole (perspective) camera in the grid's local frame.
struct PinholeCamera {
    glm::dvec3 eyeM{0.0};           // position, metres
    glm::dvec3 lookAtM{0, 1, 0};    // point looked at, metres
    glm::dvec3 up{0, 0, 1};         // approximate up direction
    double fovYDeg = 40.0;          // vertical field of view, degrees
    bool fovGiven = false;          // set by parseCamera when the text names a field of view

    // The ray through film position (fx, fy) in [0, 1]^2, (0, 0) at the top-left corner, for a film of
    // the given aspect ratio (width / height). Directions are unit length, so t is a distance in metres.
    Ray generate(double fx, double fy, double aspect) const { return frame().generate(fx, fy, aspect); }

    // The camera's orthonormal frame and the half height of its film at unit distance, worked out once for
    // many rays: frame().generate(fx, fy, aspect) is generate(fx, fy, aspect), bit for bit.
    struct Frame {
        glm::dvec3 eye, forward, right, up;
        double halfHeight = 0.0;
        Ray generate(double fx, double fy, double aspect) const {
            const double halfW = halfHeight * aspect;
            const double sx = (2.0 * fx - 1.0) * halfW;
            const double sy = (1.0 - 2.0 * fy) * halfHeight;
            return Ray{eye, glm::normalize(forward + sx * right + sy * up)};
        }
    };
    Frame frame() const;
};

// The default view of a grid: from the south-west, looking north-east and about 30 degrees down, far
// enough back that the whole grid (heights included) fits the frame.
// `bottomM`, when given, lowers the box's floor below the grid's lowest height (to frame a solid base too).
PinholeCamera autoCamera(const HeightGrid& grid, double aspect, double fovYDeg = 40.0,
                         std::optional<double> bottomM = std::nullopt);

// Parses "eye=x,y,z look=x,y,z fov=deg" (any order, fov optional; up optional as up=x,y,z). The field of view
// is in (0, 180), or for a fisheye (the full field) in (0, 360]. Returns an error message on failure.
std::optional<std::string> parseCamera(const std::string& text, PinholeCamera& camera, bool fisheye = false);

// The camera of `render --view orthographic|panorama|fisheye` (docs/architecture.md, "Views"); `given` is
// --camera's eye, look, up and field of view, or none for the view's default:
// - orthographic: looking as the automatic perspective view looks (or from eye to look), spanning the whole
//   grid, its rays starting in front of every part of it;
// - panorama: 360 degrees of azimuth and 180 of elevation, from 2 m above the ground at the grid's centre
//   (above the highest sample when the centre is a hole), centred on north;
// - fisheye: 180 degrees (equidistant), from the same point looking at the zenith, north up.
// Refuses (InputError) a field of view given to the orthographic or panorama view, which have none.
ViewCamera makeViewCamera(const HeightGrid& grid, CameraKind kind, const std::optional<PinholeCamera>& given,
                          double aspect);

}  // namespace terracast
