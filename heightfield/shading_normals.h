// Smooth shading normals for a height grid: the surface's gradient estimated at each vertex from its neighbours
// and interpolated across the cell, as height-field renderers do for "smooth" terrain (POV-Ray's height_field
// smooth interpolates vertex normals in the same spirit). Only shading reads them: the surface that rays hit,
// and its geometric normal, stay those of the cell intersectors (docs/architecture.md, "Shading normals").
#pragma once

#include "heightfield/height_grid.h"

#include <glm/glm.hpp>

#include <cstdint>

namespace terracast {

// The gradient (dh/dx, dh/dy) of the heights at vertex (i, j), in metres per metre, by central differences
// over its valid neighbours; one-sided at the grid's edges and beside holes, zero along an axis where neither
// neighbour is valid. Exact at every vertex for heights quadratic in x and y.
glm::dvec2 vertexGradient(const HeightGrid& grid, int64_t i, int64_t j);

// The smooth shading normal at (u, v) in [0, 1]^2 within cell (cellX, cellY): the four corners' gradients
// interpolated bilinearly, as a unit normal pointing up. It is continuous across cell edges (two cells sharing
// an edge interpolate the same two corners along it), equals each vertex's own normal there, and is exact for
// heights whose gradient is linear in x and y (a paraboloid) wherever the central differences are.
glm::dvec3 smoothNormal(const HeightGrid& grid, int64_t cellX, int64_t cellY, double u, double v);

}  // namespace terracast
