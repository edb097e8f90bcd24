// The cameras of both renderers: pinhole, orthographic, thin lens, equirectangular panorama and fisheye, as a
// description (what a scene file or `render --view` states) and the camera that turns film positions into rays.
#pragma once

#include "heightfield/geometry.h"
#include "tracer/core/source_location.h"

#include <glm/glm.hpp>

#include <optional>

namespace terracast {

enum class CameraKind { Pinhole, Orthographic, ThinLens, Panorama, Fisheye };

// The kind's name as scene files and `render --view` spell it ("pinhole", "orthographic", "thin-lens",
// "panorama", "fisheye").
const char* cameraKindName(CameraKind kind);

struct CameraDescription {
    CameraKind kind = CameraKind::Pinhole;
    // Eye and target in scene metres; unset means automatic framing of the terrain (or of all objects).
    std::optional<glm::dvec3> eye;
    std::optional<glm::dvec3> lookAt;
    glm::dvec3 up{0, 0, 1};
    double fovDeg = 40.0;              // pinhole and thin lens: vertical field of view; fisheye: full field
    double orthoHeightM = 0.0;         // orthographic: metres the picture spans vertically; 0 = fit the scene
    double apertureRadiusM = 0.0;      // thin lens: lens radius
    double focusDistanceM = 0.0;       // thin lens: distance to the plane in focus; 0 = distance to lookAt
    double shutterOpen = 0.0;          // motion blur: shutter interval in scene seconds
    double shutterClose = 0.0;
    glm::dvec3 velocity{0.0};          // motion blur: camera velocity, metres per second
    SourceLocation where;
};

class ViewCamera {
public:
    // `eye` and `lookAt` must differ; `up` must not be parallel to the view direction (checked by the caller).
    ViewCamera(const CameraDescription& description, const glm::dvec3& eye, const glm::dvec3& lookAt, double aspect);

    // The ray through film position (fx, fy) in [0, 1]^2 ((0, 0) top-left), with `lens` in [0, 1)^2 picking a
    // point on the thin lens and `time` in [0, 1) a moment of the shutter. None where the film has no view
    // (outside a fisheye's circle). Directions are unit length.
    std::optional<Ray> generate(double fx, double fy, glm::dvec2 lens = {0.5, 0.5}, double time = 0.0) const;

    CameraKind kind() const { return d_.kind; }
    const glm::dvec3& eye() const { return eye_; }
    const glm::dvec3& forward() const { return forward_; }
    double focusDistance() const { return focus_; }

private:
    CameraDescription d_;
    glm::dvec3 eye_, forward_, right_, up_;
    double aspect_;
    double tanHalfV_ = 0.0;
    double focus_ = 1.0;
};

}  // namespace terracast
