// The solid base under a rendered DEM: vertical walls from the grid's outer edges down to a floor below its
// lowest point, so that the terrain stands as a block (a cut-out of the Earth) rather than a sheet floating in
// the air. Along an edge the surface is linear between the two vertices (a bilinear patch's boundary), and so
// is the wall's top; where an edge vertex is nodata the wall has a gap.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"

#include <optional>

namespace terracast {

struct WallHit {
    double t = 0.0;          // distance along the ray
    glm::dvec3 point{0.0};   // local metres
    glm::dvec3 normal{0.0};  // the wall's outward normal (horizontal, unit)
};

// The floor the walls reach down to: below the lowest height by a tenth of the relief, and by at least a
// hundredth of the grid's longer side (so that a flat grid still stands on a slab).
double solidBaseFloorM(const HeightGrid& grid);

// Where `ray` first meets the outer face of a wall, nearer than tMax; none if it does not. Only the outside
// faces count: a ray leaving the block from within (through a hole, say) passes.
std::optional<WallHit> intersectSolidBase(const HeightGrid& grid, double floorM, const Ray& ray, double tMax);

}  // namespace terracast
