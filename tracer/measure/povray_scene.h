// A POV-Ray 3.7 scene of a 16-bit PNG height map seen as `render` sees it: the peer `bench --file-to-picture`
// times beside terracast when Debian's povray is installed.
#pragma once

#include "tracer/terrain/camera.h"

#include <string>

namespace terracast {

struct PovrayHeightFieldView {
    std::string heightMap;          // the PNG's file name, read from the folder POV-Ray runs in
    double extentXM = 0.0;          // the grid's extent east and north, metres (cell size times cells)
    double extentYM = 0.0;
    double metresPerUnit = 1.0;     // height of one stored unit of the PNG
    PinholeCamera camera;           // as `render` places it, in the grid's local frame
    double aspect = 4.0 / 3.0;      // picture width / height
    double sunAzimuthDeg = 315.0;   // towards the sun, azimuth clockwise from north
    double sunElevationDeg = 35.0;
    // Silhouette: the terrain white and everything else black, unlit and unshaded (no light, no shadow), so
    // that each pixel says only whether its camera ray met the terrain.
    bool silhouette = false;
};

// The scene's text. POV-Ray's frame is left-handed with y up: terracast's (x east, y north, z up) maps to
// POV-Ray's <x, z, y>, a mirror that keeps the picture as terracast draws it. POV-Ray's height_field spans
// the unit square of x and z with its image's top row at z = 1 (north) and its heights as stored value /
// 65535, so it is scaled by the extents and by 65535 metres per unit; `smooth` interpolates its vertex normals
// over two triangles per cell, one shadow ray per hit towards a parallel sun.
std::string povrayHeightFieldScene(const PovrayHeightFieldView& view);

}  // namespace terracast
