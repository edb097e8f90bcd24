// A height grid as a 16-bit greyscale PNG height map, the kind `render FILE.png --cell-size ...` reads.
#pragma once

#include "heightfield/height_grid.h"

#include <string>

namespace terracast {

// The bytes of a 16-bit greyscale PNG of `grid`: one sample per vertex, heights rounded to whole metres and
// clamped to 0..65535 (nodata vertices become 0), the grid's northmost row first, as the PNG loader expects,
// encoded by the project's PNG encoder (libspng).
std::string encodeHeightPng16(const HeightGrid& grid);

}  // namespace terracast
