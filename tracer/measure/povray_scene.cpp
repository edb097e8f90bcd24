#include "tracer/measure/povray_scene.h"

#include "tracer/core/angles.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace terracast {

namespace {

// A point or direction of terracast's frame as a POV-Ray vector (the y and z axes swapped).
std::string pov(const glm::dvec3& v) { return fmt::format("<{:.17g}, {:.17g}, {:.17g}>", v.x, v.z, v.y); }

}  // namespace

std::string povrayHeightFieldScene(const PovrayHeightFieldView& v) {
    // POV-Ray's `angle` is the horizontal field of view; terracast's camera gives the vertical one.
    const double tanV = std::tan(radians(v.camera.fovYDeg) * 0.5);
    const double horizontalDeg = degrees(2.0 * std::atan(tanV * v.aspect));
    std::string s = "#version 3.7;\n";
    s += "global_settings { assumed_gamma 1.0 max_trace_level 2 }\n";
    s += fmt::format("camera {{ perspective location {} look_at {} sky {} right x * {:.17g} up y angle {:.17g} }}\n",
                     pov(v.camera.eyeM), pov(v.camera.lookAtM), pov(v.camera.up), v.aspect, horizontalDeg);
    const std::string field = fmt::format("height_field {{ png \"{}\" smooth scale <{:.17g}, {:.17g}, {:.17g}>", v.heightMap,
                                          v.extentXM, 65535.0 * v.metresPerUnit, v.extentYM);
    if (v.silhouette) {
        s += "background { colour rgb 0 }\n";
        s += field + " pigment { colour rgb 1 } finish { emission 1 ambient 0 diffuse 0 } }\n";
        return s;
    }
    // A parallel sun far beyond the grid, towards (azimuth, elevation).
    const glm::dvec3 toSun = directionFromDegrees(v.sunAzimuthDeg, v.sunElevationDeg);
    const double far = 100.0 * std::max({v.extentXM, v.extentYM, 1.0});
    s += "background { colour rgb <0.55, 0.65, 0.8> }\n";
    s += fmt::format("light_source {{ {} colour rgb 1 parallel point_at <0, 0, 0> }}\n", pov(far * toSun));
    s += field + " pigment { colour rgb <0.55, 0.5, 0.42> } finish { ambient 0.15 diffuse 0.85 } }\n";
    return s;
}

}  // namespace terracast
