// Tracing rays against a height grid: clip to the grid's box, walk the cells with the DDA, hit each cell
// with the chosen cell intersector.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace terracast {

// How each cell is hit (docs/architecture.md, "Cell intersectors"). Speed and accuracy trade against each other.
enum class CellMethod {
    Bilinear,        // exact bilinear patch, float arithmetic in cell-local coordinates
    BilinearDouble,  // the same in double
    Triangles,       // two triangles per cell, diagonal (i+1, j)-(i, j+1) as in Embree's grid geometry
    Nearest,         // a flat square per cell at the mean of its corners, with vertical walls
    Reference,       // the bilinear patch in long double: the yardstick of the accuracy report
};

// Parses "bilinear", "bilinear-double", "triangles", "nearest" or "reference".
std::optional<CellMethod> parseCellMethod(std::string_view name);
// The name parseCellMethod accepts.
const char* cellMethodName(CellMethod method);
// All methods, in the order reports list them.
const std::vector<CellMethod>& allCellMethods();

// How cells are reached: through the pyramids (skipping blocks the ray passes above, or under), or one by one.
// Both give exactly the same hits; the flat walk exists for comparison.
enum class Traversal { Pyramid, Flat };

// A ray's hit on the height field, in the grid's local frame (metres).
struct HeightFieldHit {
    double t = 0.0;             // ray parameter
    glm::dvec3 pointM{0.0};     // hit position
    glm::dvec3 normal{0, 0, 1}; // unit geometric normal, pointing up (+z side of the surface)
    int64_t cellX = 0;          // cell index along x
    int64_t cellY = 0;          // cell index along y
    double u = 0.0;             // position inside the cell, [0, 1] along x
    double v = 0.0;             // position inside the cell, [0, 1] along y
    double errorM = 0.0;        // bound on the hit position's rounding error; offset spawned rays by it
};

// Counters a trace can fill in (optional).
struct TraceCounters {
    int64_t cellsVisited = 0;   // cells the DDA walked
    int64_t cellsTested = 0;    // cells that reached the cell intersector
    int64_t blocksSkipped = 0;  // pyramid blocks passed over without visiting their cells
    bool ambiguous = false;     // the ray grazes the surface closer than the float tolerance (see below)
};

// The nearest hit of `ray` in `interval`, or none. Holes (nodata cells) are passed through.
// When `counters` is given, `ambiguous` is set if the ray comes within a float-precision tolerance of the
// surface without crossing it (a near-miss graze) or only dips below it by less than that tolerance:
// rays whose hit/miss verdict float arithmetic cannot be expected to reproduce.
std::optional<HeightFieldHit> intersect(const HeightGrid& grid, const Ray& ray, Interval interval,
                                        CellMethod method, TraceCounters* counters = nullptr,
                                        Traversal traversal = Traversal::Pyramid);

// True when `ray` meets the terrain anywhere in `interval`, taking the terrain as solid: a ray that is
// below the surface over a valid cell (having come in through a hole or over the grid's edge) is blocked
// too. This keeps occlusion monotone in elevation: if a ray towards the sun is blocked, so is every lower
// one. Stops at the first blocking cell.

bool occluded(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method,
              TraceCounters* counters = nullptr, Traversal traversal = Traversal::Pyramid);

// The same walk as occluded, which also tells where it found the ray blocked: the point of the first blocking
// cell (its entry for a ray that comes in under the surface), or none when occluded would return false.
std::optional<HeightFieldHit> firstBlock(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method);

// The nearest hits of a bundle of rays leaving one origin, such as a tile of a pinhole camera's pixels:
// hits[k] is exactly what intersect(grid, rays[k], interval, method, counters, traversal) returns. For the
// whole bundle at once, the pyramid first proves how far from the origin (horizontally) every ray stays above
// the terrain; each ray's walk then starts at its last cell boundary within that distance. Compact bundles (a
// few pixels across) gain most. When the rays do not all share the first one's origin, or one is vertical, or
// the traversal is flat, each is traced on its own. `counters` add up over the bundle: the same `ambiguous`
// verdict as the rays traced alone, fewer cells walked and blocks skipped wherever the shared stretch is used.
void intersectBundle(const HeightGrid& grid, std::span<const Ray> rays, Interval interval, CellMethod method,
                     std::span<std::optional<HeightFieldHit>> hits, TraceCounters* counters = nullptr,
                     Traversal traversal = Traversal::Pyramid);

// The origin of a ray leaving a hit point in direction `dir`: the point pushed along the geometric normal,
// to the side `dir` goes, by the hit's error bound, so that the new ray cannot re-hit the surface it starts
// on (pbrt-v4's conservative ray-origin offset).
glm::dvec3 spawnOrigin(const HeightFieldHit& hit, const glm::dvec3& dir);

// The instruction sets the tracing functions above are compiled for: baseline x86-64, and AVX2 with BMI2 (GCC
// on x86-64). Both round every operation alike and return the same bits; the wider one is used when the
// processor has it.
enum class KernelIsa { Baseline, Avx2 };
// The instruction set in use.
KernelIsa kernelIsa();
// Chooses the instruction set (for tests and benchmarks; not while rays are being traced). False, changing
// nothing, when this build or this processor lacks it.
bool setKernelIsa(KernelIsa isa);
// "baseline" or "avx2".
const char* kernelIsaName(KernelIsa isa);

// The tolerance in metres below which `intersect` flags a graze as ambiguous for this grid.
double grazingToleranceM(const HeightGrid& grid);

}  // namespace terracast
