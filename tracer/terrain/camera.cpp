#include "tracer/terrain/camera.h"

#include "tracer/core/angles.h"

#include <cmath>
#include <sstream>

namespace terracast {

Ray PinholeCamera::generate(double fx, double fy, double aspect) const {
    const glm::dvec3 forward = glm::normalize(lookAtM - eyeM);
    glm::dvec3 right = glm::cross(forward, up);
    if (glm::dot(right, right) < 1e-20) right = glm::cross(forward, glm::dvec3(0, 1, 0));
    right = glm::normalize(right);
    const glm::dvec3 camUp = glm::cross(right, forward);
    const double halfH = std::tan(radians(fovYDeg) * 0.5);
    const double halfW = halfH * aspect;
    const double sx = (2.0 * fx - 1.0) * halfW;
    const double sy = (1.0 - 2.0 * fy) * halfH;
    return Ray{eyeM, glm::normalize(forward + sx * right + sy * camUp)};
}

PinholeCamera autoCamera(const HeightGrid& grid, double aspect, double fovYDeg) {
    const double zLo = grid.minHeightM(), zHi = grid.maxHeightM();
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

std::optional<std::string> parseCamera(const std::string& text, PinholeCamera& camera) {
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
            if (end == value.c_str() || *end != '\0' || !(fov > 0.0 && fov < 180.0))
                return "fov expects degrees in (0, 180), found '" + value + "'";
            camera.fovYDeg = fov;
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

}  // namespace terracast
