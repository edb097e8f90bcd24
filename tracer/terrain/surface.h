// A traceable terrain surface: the direct tracer with one cell method, or the Embree tessellation.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"
#include "tracer/core/surface_method.h"
#include "tracer/terrain/embree_terrain.h"

#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

namespace terracast {

// A level of detail (docs/architecture.md, "Level of detail"): seen from `eyeM`, where the grid's cells span
// fewer than `pixels` pixels of a picture whose pixels subtend `radiansPerPixel` each, the surface is that of
// a coarser grid (every other vertex, then every fourth, ...).
struct LevelOfDetail {
    glm::dvec3 eyeM{0.0};
    double radiansPerPixel = 0.0;
    double pixels = 1.0;
};

// A surface that answers nearest-hit and occlusion queries in the grid's local frame.
class TerrainSurface {
public:
    // `threads` bounds Embree's build threads (0 = all cores); the direct tracer builds nothing here.
    // `traversal` picks how the direct tracer reaches cells (the flat walk is for comparisons); Embree ignores it.
    TerrainSurface(const HeightGrid& grid, SurfaceMethod method, int threads = 0,
                   Traversal traversal = Traversal::Pyramid);

    std::optional<HeightFieldHit> intersect(const Ray& ray, Interval interval) const;
    bool occluded(const Ray& ray, Interval interval) const;
    // hits[k] = intersect(rays[k], interval), for rays sharing an origin: the direct tracer proves a free
    // stretch for the whole bundle first (see terracast::intersectBundle); Embree traces them one by one.
    void intersectBundle(std::span<const Ray> rays, Interval interval,
                         std::span<std::optional<HeightFieldHit>> hits) const;

    // Switches to a level of detail: builds the coarser grids (in memory: about a third of the grid's bytes) and
    // from then on traces each stretch of a ray on the level its distance from the eye calls for. Hits are given
    // in this grid's cells (pointM is the coarse surface's point; cellX, cellY, u and v locate it in this grid,
    // clamped to it). A grid held as tiles keeps only the coarser grids that fit in its tile cache's budget (from
    // firstDetailLevel() on, made by reading each tile once) and serves the finer levels from its tiles. Throws
    // std::invalid_argument for Embree or settings that are not positive and finite.
    void setLevelOfDetail(const LevelOfDetail& lod);
    // The coarser grids in use (0 without a level of detail), and the distance from the eye from which each is
    // used (metres, increasing).
    int detailLevels() const { return int(coarse_.size()); }
    // How many steps coarser than the grid the first of them is (1 but for a grid held as tiles), and the bytes
    // they hold.
    int firstDetailLevel() const { return firstDetailLevel_; }
    size_t detailBytes() const;
    const std::vector<double>& detailDistancesM() const { return fromM_; }

    // The smooth shading normal (heightfield/shading_normals.h) at a hit this surface returned: the grid's, or
    // under a level of detail that of the level the hit's distance from the eye calls for, so that a distant hit
    // reads the coarse grid it lies on rather than the grid's tiles.
    glm::dvec3 smoothNormalAt(const HeightFieldHit& hit) const;

    SurfaceMethod method() const { return method_; }
    Traversal traversal() const { return traversal_; }
    // Seconds spent building acceleration data: Embree's BVH, or the grid's pyramids.
    double buildSeconds() const { return embree_ ? embree_->buildSeconds() : grid_.pyramidBuildSeconds(); }
    // Bytes of the surface's own data: the grid for the direct tracer; Embree's own count for Embree
    // (it copies the vertices).
    int64_t memoryBytes() const;
    // The most bytes held at once while building: Embree's peak; the grid's bytes for the direct tracer.
    int64_t peakMemoryBytes() const;

private:
    const HeightGrid& grid_;
    SurfaceMethod method_;
    CellMethod cell_ = CellMethod::Bilinear;
    Traversal traversal_ = Traversal::Pyramid;
    int threads_ = 0;
    std::unique_ptr<EmbreeTerrain> embree_;
    // The level of detail: coarse_[k] is used from fromM_[k] metres from eye_ on (until fromM_[k + 1]).
    std::vector<std::unique_ptr<HeightGrid>> coarse_;
    std::vector<double> fromM_;
    int firstDetailLevel_ = 1;
    glm::dvec3 eye_{0.0};
    glm::dvec3 boxLo_{0.0}, boxHi_{0.0};  // holds every level's surface

    // Calls visit(level, stretch) for the stretches of `interval` along `ray` on which one level holds, nearest
    // first, until it returns true; returns whether one did. Level 0 is the grid itself.
    template <class Visit>
    bool byLevel(const Ray& ray, Interval interval, Visit&& visit) const;
    const HeightGrid& level(int k) const { return k == 0 ? grid_ : *coarse_[size_t(k - 1)]; }
    // intersect with a level of detail; `fromSwitch`: the interval starts where the ray passes from one level to
    // another (tested for lying under the new level's surface there).
    std::optional<HeightFieldHit> intersectLevels(const Ray& ray, Interval interval, bool fromSwitch) const;
    // Where the ray at t lies under level k's surface (the bilinear patch of its cell there): that point of the
    // surface, as a hit at t located in this grid's cells.
    std::optional<HeightFieldHit> underLevel(int k, const Ray& ray, double t) const;
    // A hit on level k located in this grid's cells.
    HeightFieldHit inFineCells(HeightFieldHit hit) const { return inCellsOf(grid_, hit); }
    // `hit` located in grid g's cells (cellX, cellY, u, v from its point, clamped to the grid).
    static HeightFieldHit inCellsOf(const HeightGrid& g, HeightFieldHit hit);
    // The level a point at `distanceM` from the eye is traced on (0: the grid itself).
    int levelAt(double distanceM) const;
};

}  // namespace terracast
