#include "tracer/camera/camera.h"

#include "tracer/core/angles.h"
#include "tracer/sampling/warps.h"

#include <cmath>

namespace terracast {

const char* cameraKindName(CameraKind kind) {
    switch (kind) {
    case CameraKind::Pinhole: return "pinhole";
    case CameraKind::Orthographic: return "orthographic";
    case CameraKind::ThinLens: return "thin-lens";
    case CameraKind::Panorama: return "panorama";
    case CameraKind::Fisheye: return "fisheye";
    }
    return "camera";
}

ViewCamera::ViewCamera(const CameraDescription& description, const glm::dvec3& eye, const glm::dvec3& lookAt,
                         double aspect)
    : d_(description), eye_(eye), aspect_(aspect) {
    forward_ = glm::normalize(lookAt - eye);
    right_ = glm::normalize(glm::cross(forward_, d_.up));
    up_ = glm::cross(right_, forward_);
    tanHalfV_ = std::tan(radians(d_.fovDeg) * 0.5);
    focus_ = d_.focusDistanceM > 0.0 ? d_.focusDistanceM : glm::length(lookAt - eye);
}

std::optional<Ray> ViewCamera::generate(double fx, double fy, glm::dvec2 lens, double time) const {
    const double sx = 2.0 * fx - 1.0;  // -1 left .. 1 right
    const double sy = 1.0 - 2.0 * fy;  // -1 bottom .. 1 top
    const double shutter = d_.shutterOpen + time * (d_.shutterClose - d_.shutterOpen);
    const glm::dvec3 eye = eye_ + shutter * d_.velocity;
    Ray ray;
    ray.time = shutter;
    switch (d_.kind) {
    case CameraKind::Pinhole:
        ray.origin = eye;
        ray.dir = glm::normalize(forward_ + sx * tanHalfV_ * aspect_ * right_ + sy * tanHalfV_ * up_);
        return ray;
    case CameraKind::ThinLens: {
        // The pinhole ray meets the plane in focus at distance focus_ along the view axis; a ray from any point
        // of the lens aperture through that point keeps it sharp and blurs everything off the plane.
        const glm::dvec3 dir = forward_ + sx * tanHalfV_ * aspect_ * right_ + sy * tanHalfV_ * up_;
        const glm::dvec3 focusPoint = eye + focus_ * dir;  // dir's component along forward_ is 1
        const glm::dvec2 disk = d_.apertureRadiusM * squareToConcentricDisk(lens);
        ray.origin = eye + disk.x * right_ + disk.y * up_;
        ray.dir = glm::normalize(focusPoint - ray.origin);
        return ray;
    }
    case CameraKind::Orthographic: {
        const double halfH = 0.5 * d_.orthoHeightM;
        ray.origin = eye + sx * halfH * aspect_ * right_ + sy * halfH * up_;
        ray.dir = forward_;
        return ray;
    }
    case CameraKind::Panorama: {
        // Equirectangular: x spans 360 degrees of azimuth centred on the view direction, y spans 180 degrees
        // of elevation from the zenith (top) to the nadir (bottom), about the scene's up axis.
        const glm::dvec3 zUp = glm::normalize(d_.up);
        glm::dvec3 ahead = forward_ - glm::dot(forward_, zUp) * zUp;
        if (glm::dot(ahead, ahead) < 1e-20) ahead = glm::cross(zUp, right_);
        ahead = glm::normalize(ahead);
        const glm::dvec3 side = glm::cross(ahead, zUp);
        const double azimuth = sx * kPi, elevation = sy * kPi / 2.0;
        ray.origin = eye;
        ray.dir = glm::normalize(std::cos(elevation) * (std::cos(azimuth) * ahead + std::sin(azimuth) * side) +
                                 std::sin(elevation) * zUp);
        return ray;
    }
    case CameraKind::Fisheye: {
        // Equidistant fisheye: the angle from the view axis grows linearly with the distance from the picture's
        // centre; the circle inscribed in the shorter side spans the full field of view.
        const double px = sx * std::max(aspect_, 1.0), py = sy * std::max(1.0 / aspect_, 1.0);
        const double r = std::sqrt(px * px + py * py);
        if (r > 1.0) return std::nullopt;
        const double theta = r * radians(d_.fovDeg) * 0.5;
        const double phi = std::atan2(py, px);
        ray.origin = eye;
        ray.dir = glm::normalize(std::cos(theta) * forward_ +
                                 std::sin(theta) * (std::cos(phi) * right_ + std::sin(phi) * up_));
        return ray;
    }
    }
    return std::nullopt;
}

}  // namespace terracast
