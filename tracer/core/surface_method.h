// The ways to trace a terrain surface, direct or triangulated, and their names: one list for the CLI's
// options, the scene files, the terrain surface and the measurements.
#pragma once

#include "heightfield/traversal.h"

#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace terracast {

enum class SurfaceMethod {
    Bilinear,        // direct: exact patch in float
    BilinearDouble,  // direct: exact patch in double
    Triangles,       // direct: two triangles per cell
    Nearest,         // direct: flat squares
    Reference,       // direct: exact patch in long double
    Embree,          // Embree triangle mesh
    EmbreeGrid,      // Embree grid geometry
};

// Every method, in the order lists and messages show them.
std::span<const SurfaceMethod> surfaceMethods();
// Parses a method name ("bilinear", ..., "embree", "embree-grid").
std::optional<SurfaceMethod> parseSurfaceMethod(std::string_view name);
const char* surfaceMethodName(SurfaceMethod method);
// The names parseSurfaceMethod accepts, comma-separated, for messages.
const char* surfaceMethodList();
// The cell method behind a direct method; none for Embree's.
std::optional<CellMethod> directCellMethod(SurfaceMethod method);
// The same for a command that traces the grid directly (`what`, as "shadow" or "--view map"): throws InputError
// for Embree's methods.
CellMethod requireDirectMethod(SurfaceMethod method, const std::string& what);

}  // namespace terracast
