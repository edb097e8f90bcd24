// Point files: observers for viewsheds, as CSV text or any vector file GDAL (OGR) reads.
#pragma once

#include "loaders/dem_loader.h"

#include <optional>
#include <string>
#include <vector>

namespace terracast {

// One point in the DEM's source CRS, with an optional height (metres above the terrain).
struct SitePoint {
    double x = 0.0;
    double y = 0.0;
    std::optional<double> heightM;
    std::string where;  // "file:line" or "file: feature N", for messages
};

// Reads points for a DEM placed by `geo`.
// - .csv and .txt: one point per line, "X,Y" or "X,Y,HEIGHT" in the DEM's CRS (commas, semicolons, tabs or
//   spaces between fields); blank lines and lines starting with # are skipped, and a first line that is not
//   numbers is a header.
// - anything else: a vector file read through GDAL, the point features of its first layer (multi-points give
//   each of their points), moved from the layer's CRS to the DEM's when both have one; a field named height,
//   HEIGHT or h gives the height.
// Throws InputError naming the file (and line or feature) for a missing or unreadable file, a malformed line,
// a geometry that is not a point, non-finite numbers, or no point at all.
std::vector<SitePoint> readSitePoints(const std::string& path, const GeoReference& geo);

}  // namespace terracast
