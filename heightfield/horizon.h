// The exact horizon of a vertex along an azimuth, in one walk over the cells (docs/architecture.md, "Horizon
// walk"): the largest slope from the vertex to any point of the surface along the horizontal line, solved per
// cell in closed form, with the maximum pyramid skipping blocks that cannot raise it.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"

#include <cstdint>
#include <limits>

namespace terracast {

// What the horizon walk looks at.
struct HorizonSearch {
    // Points farther than this (horizontal metres) are ignored.
    double maxDistanceM = std::numeric_limits<double>::infinity();
    // Earth curvature less refraction: a point at horizontal distance d is lowered by dropPerSquareM * d^2, that
    // is coeff / (2 R) for an earth of radius R and a curvature coefficient coeff (1 - refraction). 0 = flat;
    // negative values raise far points (the terrain turned upside down sees the earth's curvature so).
    double dropPerSquareM = 0.0;
};

// Counters a horizon walk can fill in (optional).
struct HorizonCounters {
    int64_t cellsVisited = 0;   // cells whose surface was solved
    int64_t blocksSkipped = 0;  // pyramid blocks passed without visiting their cells
};

// The tangent of the horizon's elevation angle at vertex (i, j) towards the horizontal direction (dirX, dirY)
// (metres; need not be unit): the supremum over the surface points p along that line, at horizontal distance
// d > 0, of (h(p) - drop(d) - h(i, j)) / d. Next to the vertex the limit d -> 0 counts, which is the surface's
// slope in that direction in the cell the line leaves over, so a direction below that slope is blocked at once.
// Holes carry no surface: the line passes over them and points beyond count. Along a grid line, a point is on
// the surface when either cell beside the line is valid. Returns -infinity when the line meets no surface
// (a vertex on the grid's edge looking out, or one with only holes that way).
// For the methods whose surface passes through the vertices: bilinear (all three precisions solve the same
// patch, in double) and triangles. Throws GridError for nearest.
double horizonTangent(const HeightGrid& grid, int64_t i, int64_t j, double dirX, double dirY, CellMethod method,
                      const HorizonSearch& search = {}, HorizonCounters* counters = nullptr);

// The horizon's tangent (as horizonTangent) and the horizontal distance of the surface point that gives it (0 when
// it is the slope at the vertex itself). `hintDistanceM` > 0 names a distance along the line where the horizon
// is likely to lie (the distance a neighbouring vertex's horizon point has, carried over): the surface there
// starts the walk as a lower bound, which lets it skip more. The answer is the same with or without a hint.
struct HorizonPoint {
    double tangent = -std::numeric_limits<double>::infinity();
    double distanceM = 0.0;
};
HorizonPoint horizonPoint(const HeightGrid& grid, int64_t i, int64_t j, double dirX, double dirY, CellMethod method,
                          const HorizonSearch& search = {}, double hintDistanceM = 0.0,
                          HorizonCounters* counters = nullptr);

// The horizon's tangent seen from a point above the surface (an observer's eye) at local (xM, yM) and height zM:
// the supremum over the surface points p along the horizontal line towards (dirX, dirY), at distance d > 0 up to
// search.maxDistanceM (included), of (h(p) - drop(d) - zM) / d, solved per cell as horizonTangent's walk;
// -infinity when the line meets no surface. The point is clamped to the grid. The point itself needs no surface
// under it; a point below the surface gets the same supremum (no start-cell rule applies).
double horizonTangentFrom(const HeightGrid& grid, double xM, double yM, double zM, double dirX, double dirY,
                          CellMethod method, const HorizonSearch& search = {}, HorizonCounters* counters = nullptr);

// True when the horizon at vertex (i, j) towards (dirX, dirY) lies strictly above the slope `tangent`: a ray
// from the vertex at that slope passes below the surface somewhere (a sun there is blocked; at exactly the
// horizon it grazes and is not). The same walk as horizonTangent, ending at the first point above the slope and
// skipping every block that cannot rise above it.
bool horizonAbove(const HeightGrid& grid, int64_t i, int64_t j, double dirX, double dirY, double tangent,
                  CellMethod method, const HorizonSearch& search = {}, HorizonCounters* counters = nullptr);

}  // namespace terracast
