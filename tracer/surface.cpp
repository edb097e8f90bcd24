#include "tracer/surface.h"

#include <array>

namespace terracast {

namespace {
struct Name {
    SurfaceMethod method;
    const char* name;
};
constexpr std::array<Name, 7> kNames{{
    {SurfaceMethod::Bilinear, "bilinear"},
    {SurfaceMethod::BilinearDouble, "bilinear-double"},
    {SurfaceMethod::Triangles, "triangles"},
    {SurfaceMethod::Nearest, "nearest"},
    {SurfaceMethod::Reference, "reference"},
    {SurfaceMethod::Embree, "embree"},
    {SurfaceMethod::EmbreeGrid, "embree-grid"},
}};

CellMethod toCellMethod(SurfaceMethod m) {
    switch (m) {
    case SurfaceMethod::BilinearDouble: return CellMethod::BilinearDouble;
    case SurfaceMethod::Triangles: return CellMethod::Triangles;
    case SurfaceMethod::Nearest: return CellMethod::Nearest;
    case SurfaceMethod::Reference: return CellMethod::Reference;
    default: return CellMethod::Bilinear;
    }
}
}  // namespace

std::optional<SurfaceMethod> parseSurfaceMethod(std::string_view name) {
    for (const auto& n : kNames)
        if (name == n.name) return n.method;
    return std::nullopt;
}

const char* surfaceMethodName(SurfaceMethod method) {
    for (const auto& n : kNames)
        if (n.method == method) return n.name;
    return "?";
}

const char* surfaceMethodList() {
    return "bilinear, bilinear-double, triangles, nearest, reference, embree, embree-grid";
}

const std::vector<SurfaceMethod>& compareMethods() {
    static const std::vector<SurfaceMethod> methods{SurfaceMethod::Bilinear, SurfaceMethod::BilinearDouble,
                                                    SurfaceMethod::Triangles, SurfaceMethod::Nearest,
                                                    SurfaceMethod::Embree, SurfaceMethod::EmbreeGrid};
    return methods;
}

TerrainSurface::TerrainSurface(const HeightGrid& grid, SurfaceMethod method, int threads)
    : grid_(grid), method_(method), cell_(toCellMethod(method)) {
    if (method == SurfaceMethod::Embree)
        embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::TriangleMesh, threads);
    if (method == SurfaceMethod::EmbreeGrid) embree_ = std::make_unique<EmbreeTerrain>(grid, EmbreeLayout::Grid, threads);
}

std::optional<HeightFieldHit> TerrainSurface::intersect(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->intersect(ray, interval);
    return terracast::intersect(grid_, ray, interval, cell_);
}

bool TerrainSurface::occluded(const Ray& ray, Interval interval) const {
    if (embree_) return embree_->occluded(ray, interval);
    return terracast::occluded(grid_, ray, interval, cell_);
}

int64_t TerrainSurface::memoryBytes() const {
    if (embree_) return embree_->memoryBytes();
    return int64_t(grid_.memoryBytes());
}

}  // namespace terracast
