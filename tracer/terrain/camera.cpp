#include "tracer/terrain/camera.h"

#include "tracer/core/angles.h"
#include "tracer/core/errors.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace terracast {

PinholeCamera::Frame PinholeCamera::frame() const {
    Frame f;
    f.eye = eyeM;
    f.forward = glm::normalize(lookAtM - eyeM);
    glm::dvec3 right = glm::cross(f.forward, up);
    if (glm::dot(right, right) < 1e-20) right = glm::cross(f.forward, glm::dvec3(0, 1, 0));
    f.right = glm::normalize(right);
    f.up = glm::cross(f.right, f.forward);
    f.halfHeight = std::tan(radians(fovYDeg) * 0.5);
    return f;
}

PinholeCamera autoCamera(const HeightGrid& grid, double aspect, double fovYDeg, std::optional<double> bottomM) {
    const double zLo = std::min(double(grid.minHeightM()), bottomM.value_or(grid.minHeightM())), zHi = grid.maxHeightM();
    const glm::dvec3 lo{0.0, 0.0, zLo}, hi{grid.extentXM(), grid.extentYM(), zHi};
    const glm::dvec3 centre = 0.5 * (lo + hi);
    // Looking north-east (azimuth 45 degrees) and 30 degrees below the horizon.
    const double pitch = radians(30.0), azimuth = radians(45.0);
    const glm::dvec3 forward = directionFromRadians(azimuth, -pitch);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
    const glm::dvec3 camUp = glm::cross(right, forward);
    const double tanV = std::tan(radians(fovYDeg) * 0.5), tanH = tanV * aspect;
    // The smallest distance back from the centre at which all eight corners of the box are in frame.
    double distance = 0.0;
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z};
        const glm::dvec3 r = corner - centre;
        const double along = glm::dot(r, forward);
        distance = std::max({distance, std::abs(glm::dot(r, right)) / tanH - along,
                             std::abs(glm::dot(r, camUp)) / tanV - along});
    }
    distance *= 1.05;
    PinholeCamera cam;
    cam.fovYDeg = fovYDeg;
    cam.lookAtM = centre;
    cam.eyeM = centre - distance * forward;
    return cam;
}

std::optional<std::string> parseCamera(const std::string& text, PinholeCamera& camera, bool fisheye) {
    std::istringstream in(text);
    std::string item;
    bool haveEye = false, haveLook = false;
    auto parseVec = [](const std::string& s, glm::dvec3& v) {
        double a, b, c;
        char c1, c2;
        std::istringstream is(s);
        if (!(is >> a >> c1 >> b >> c2 >> c) || c1 != ',' || c2 != ',') return false;
        std::string rest;
        if (is >> rest) return false;
        // Beyond a million kilometres the camera's own arithmetic loses the DEM.
        constexpr double kFarM = 1e9;
        if (!(std::abs(a) <= kFarM && std::abs(b) <= kFarM && std::abs(c) <= kFarM)) return false;
        v = {a, b, c};
        return true;
    };
    while (in >> item) {
        const auto eq = item.find('=');
        if (eq == std::string::npos) return "expected key=value, found '" + item + "'";
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        if (key == "eye") {
            if (!parseVec(value, camera.eyeM)) return "eye expects x,y,z in metres (each within 1e9), found '" + value + "'";
            haveEye = true;
        } else if (key == "look") {
            if (!parseVec(value, camera.lookAtM)) return "look expects x,y,z in metres (each within 1e9), found '" + value + "'";
            haveLook = true;
        } else if (key == "up") {
            if (!parseVec(value, camera.up)) return "up expects x,y,z (each within 1e9), found '" + value + "'";
        } else if (key == "fov") {
            char* end = nullptr;
            const double fov = std::strtod(value.c_str(), &end);
            const bool inRange = fisheye ? fov > 0.0 && fov <= 360.0 : fov > 0.0 && fov < 180.0;
            if (end == value.c_str() || *end != '\0' || !inRange)
                return std::string(fisheye ? "fov expects degrees in (0, 360]" : "fov expects degrees in (0, 180)") +
                       ", found '" + value + "'";
            camera.fovYDeg = fov;
            camera.fovGiven = true;
        } else {
            return "unknown key '" + key + "' (expected eye, look, up or fov)";
        }
    }
    if (!haveEye || !haveLook) return std::string("both eye=x,y,z and look=x,y,z are required");
    const glm::dvec3 view = camera.lookAtM - camera.eyeM;
    if (glm::length(view) == 0.0) return std::string("eye and look are the same point");
    if (glm::length(glm::cross(glm::normalize(view), camera.up)) < 1e-9 * glm::length(camera.up) ||
        glm::length(camera.up) == 0.0)
        return std::string("up must be non-zero and not parallel to the view direction");
    return std::nullopt;
}

ViewCamera makeViewCamera(const HeightGrid& grid, CameraKind kind, const std::optional<PinholeCamera>& given,
                          double aspect) {
    CameraDescription d;
    d.kind = kind;
    if (given) {
        d.up = given->up;
        if (given->fovGiven && (kind == CameraKind::Orthographic || kind == CameraKind::Panorama))
            throw InputError(fmt::format("--camera: fov does not apply to --view {} (found fov={:g})",
                                         kind == CameraKind::Orthographic ? "orthographic" : "panorama",
                                         given->fovYDeg));
    }
    const glm::dvec3 lo{0.0, 0.0, grid.minHeightM()}, hi{grid.extentXM(), grid.extentYM(), grid.maxHeightM()};
    if (kind == CameraKind::Orthographic) {
        const PinholeCamera from = given ? *given : autoCamera(grid, aspect);
        const glm::dvec3 forward = glm::normalize(from.lookAtM - from.eyeM);
        const glm::dvec3 right = glm::normalize(glm::cross(forward, d.up));
        const glm::dvec3 up = glm::cross(right, forward);
        // The picture spans the grid's box as seen along `forward`, centred on the look-at point, with 5 % to spare;
        // the rays start a box diagonal behind the nearest corner, so no part of the grid is cut off.
        double halfH = 0.0, nearest = 0.0;
        for (int k = 0; k < 8; ++k) {
            const glm::dvec3 corner{k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z};
            const glm::dvec3 r = corner - from.lookAtM;
            halfH = std::max({halfH, std::abs(glm::dot(r, up)), std::abs(glm::dot(r, right)) / aspect});
            nearest = std::min(nearest, glm::dot(r, forward));
        }
        d.orthoHeightM = 2.1 * std::max(halfH, 1e-9);
        const double back = -nearest + glm::length(hi - lo) + 1.0;
        return ViewCamera(d, from.lookAtM - back * forward, from.lookAtM, aspect);
    }
    d.fovDeg = kind == CameraKind::Fisheye ? 180.0 : 40.0;
    if (given) {
        if (given->fovGiven) d.fovDeg = given->fovYDeg;
        return ViewCamera(d, given->eyeM, given->lookAtM, aspect);
    }
    // Standing 2 m above the ground at the grid's centre vertex, or above the highest sample over a hole.
    const int64_t i = (grid.width() - 1) / 2, j = (grid.height() - 1) / 2;
    const double ground = grid.vertexValid(i, j) ? double(grid.at(i, j)) : double(grid.maxHeightM());
    const glm::dvec3 eye{double(i) * grid.cellSizeXM(), double(j) * grid.cellSizeYM(), ground + 2.0};
    if (kind == CameraKind::Fisheye) {
        d.up = {0.0, 1.0, 0.0};  // north at the top of the picture
        return ViewCamera(d, eye, eye + glm::dvec3(0.0, 0.0, 1.0), aspect);
    }
    return ViewCamera(d, eye, eye + glm::dvec3(0.0, 1.0, 0.0), aspect);  // the panorama's centre looks north
}

}  // namespace terracast
