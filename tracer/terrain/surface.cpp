#include "tracer/terrain/surface.h"

#include <array>
#include <string>
#include <utility>

namespace terracast {

TerrainSurface::TerrainSurface(const HeightGrid& grid, SurfaceMethod method, int threads, Traversal traversal)
    : grid_(grid), method_(method), cell_(directCellMethod(method).value_or(CellMethod::Bilinear)), traversal_(traversal) {
    if (method == SurfaceMethod::Embree)
        embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::TriangleMesh, threads);
    if (method == SurfaceMethod::EmbreeGrid) embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::Grid, threads);
}

std::optional<HeightFieldHit> TerrainSurface::intersect(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->intersect(ray, interval);
    return terracast::intersect(grid_, ray, interval, cell_, nullptr, traversal_);
}

void TerrainSurface::intersectBundle(std::span<const Ray> rays, Interval interval,
                                     std::span<std::optional<HeightFieldHit>> hits) const {
    if (!embree_) return terracast::intersectBundle(grid_, rays, interval, cell_, hits, nullptr, traversal_);
    for (size_t k = 0; k < std::min(rays.size(), hits.size()); ++k) hits[k] = embree_->intersect(rays[k], interval);
}

bool TerrainSurface::occluded(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->occluded(ray, interval);
    return terracast::occluded(grid_, ray, interval, cell_, nullptr, traversal_);
}

int64_t TerrainSurface::memoryBytes() const {
    if (embree_) return embree_->memoryBytes();
    return int64_t(grid_.memoryBytes());
}

int64_t TerrainSurface::peakMemoryBytes() const {
    if (embree_) return embree_->peakMemoryBytes();
    return int64_t(grid_.memoryBytes());
}

}  // namespace terracast
