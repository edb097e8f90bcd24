// The memory guard's model of a terrain job: what the grid, the film and Embree's scene will hold, checked
// against the limit before anything large is allocated.
#pragma once

#include "heightfield/height_grid.h"
#include "tracer/core/surface_method.h"

#include <string>

namespace terracast {

// Bytes per pixel of a film: linear RGB in float.
inline constexpr double kFilmBytesPerPixel = 12.0;

// Embree's bytes for `grid` with `method`, as measured on this project's DEMs (triangle mesh peak, grid
// geometry); 0 for the direct methods, which add nothing to the grid.
double embreeBytesEstimate(SurfaceMethod method, const HeightGrid& grid);

// The most a level of detail's coarser grids of `grid` hold (TerrainSurface::setLevelOfDetail): a third of the
// grid's bytes, or for a grid held as tiles its tile cache's budget.
double levelOfDetailBytes(const HeightGrid& grid);

// Bytes per pixel of a picture written as PNG or EXR beyond its film: the 8-bit or half copy handed to the
// encoder and the encoded bytes, held at once.
inline constexpr double kEncodeBytesPerPixel = 12.0;

// Refuses (InputError naming `path`) a job whose estimate exceeds `maxMemoryBytes` (0 = the default limit):
// what the process holds now (its libraries, the grid already loaded; measured, not modelled) plus
// `extraBytes` still to allocate. Callers load the libraries the job will need (the image codec) first.
void checkMemory(const std::string& path, double maxMemoryBytes, const HeightGrid& grid, double extraBytes,
                 const std::string& what);

}  // namespace terracast
