// The scene renderer's cameras: pinhole, orthographic, thin lens, equirectangular panorama and fisheye.
#pragma once

#include "heightfield/geometry.h"
#include "tracer/scene/scene_description.h"

#include <optional>

namespace terracast {

class SceneCamera {
public:
    // `eye` and `lookAt` must differ; `up` must not be parallel to the view direction (checked by the caller).
    SceneCamera(const CameraDescription& description, const glm::dvec3& eye, const glm::dvec3& lookAt, double aspect);

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
