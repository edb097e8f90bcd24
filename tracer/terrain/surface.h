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
    std::unique_ptr<EmbreeTerrain> embree_;
};

}  // namespace terracast
