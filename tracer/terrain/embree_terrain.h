// The height grid tessellated into two triangles per cell and traced by Embree 3: the cross-check and the
// speed reference for the direct tracer.
#pragma once

#include "heightfield/geometry.h"
#include "heightfield/height_grid.h"
#include "heightfield/traversal.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace terracast {

// How the grid is handed to Embree.
enum class EmbreeLayout {
    TriangleMesh,  // RTC_GEOMETRY_TYPE_TRIANGLE: explicit index buffer, two triangles per valid cell
    Grid,          // RTC_GEOMETRY_TYPE_GRID: tiles of at most 256 x 256 cells (Embree's limit is 32767 vertices
                   // per side); tiles with holes are split into runs of valid cells per row
};

// One Embree device and one scene holding the terrain, owned together. The device's error callback turns
// Embree errors into exceptions naming the call; its memory-monitor callback counts Embree's bytes.
// Triangles use the diagonal (i+1, j)-(i, j+1), as CellMethod::Triangles does; nodata cells are left out.
class EmbreeTerrain {
public:
    // Builds the scene (RTC_SCENE_FLAG_ROBUST, medium build quality) on a device with `threads` build threads
    // (0 = all cores). Throws std::runtime_error on failure.
    EmbreeTerrain(const HeightGrid& grid, EmbreeLayout layout, int threads = 0);
    ~EmbreeTerrain();
    EmbreeTerrain(const EmbreeTerrain&) = delete;
    EmbreeTerrain& operator=(const EmbreeTerrain&) = delete;

    // The nearest hit in `interval`, in the grid's local frame (normal oriented up).
    std::optional<HeightFieldHit> intersect(const Ray& ray, Interval interval) const;
    // True when anything is hit in `interval`.
    bool occluded(const Ray& ray, Interval interval) const;

    // Bytes Embree holds now, as its memory-monitor callback reported them.
    int64_t memoryBytes() const { return embreeBytes_.load(); }
    // Peak of the above during the build.
    int64_t peakMemoryBytes() const { return peakBytes_.load(); }
    // Seconds spent building (buffers and BVH).
    double buildSeconds() const { return buildSeconds_; }
    // Number of triangles (two per valid cell).
    int64_t triangleCount() const { return triangles_; }

private:
    struct Impl;
    // The counters come first: the device, released with impl_, reports its last frees to them.
    std::atomic<int64_t> embreeBytes_{0};
    std::atomic<int64_t> peakBytes_{0};
    std::unique_ptr<Impl> impl_;
    double buildSeconds_ = 0.0;
    int64_t triangles_ = 0;
    double cellSizeXM_ = 1.0, cellSizeYM_ = 1.0;
    const HeightGrid* grid_ = nullptr;

    friend bool embreeMemoryMonitor(void* user, long bytes, bool post);
};

}  // namespace terracast
