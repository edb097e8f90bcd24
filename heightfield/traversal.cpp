#include "heightfield/traversal.h"

#include "heightfield/cell_intersectors.h"
#include "heightfield/dda.h"
#include "heightfield/height_tile.h"

#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <type_traits>

#include "heightfield/kernel_isas.h"

namespace terracast {

namespace {

struct MethodName {
    CellMethod method;
    const char* name;
};
constexpr std::array<MethodName, 5> kMethodNames{{
    {CellMethod::Bilinear, "bilinear"},
    {CellMethod::BilinearDouble, "bilinear-double"},
    {CellMethod::Triangles, "triangles"},
    {CellMethod::Nearest, "nearest"},
    {CellMethod::Reference, "reference"},
}};

static_assert(std::is_trivially_destructible_v<std::optional<HeightFieldHit>>);

bool processorHasAvx2() {
#if TERRACAST_AVX2_KERNELS
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("bmi") && __builtin_cpu_supports("bmi2") &&
           __builtin_cpu_supports("lzcnt") && __builtin_cpu_supports("popcnt") && __builtin_cpu_supports("f16c") &&
           __builtin_cpu_supports("movbe");
#else
    return false;
#endif
}

std::atomic<KernelIsa>& currentIsa() {
    static std::atomic<KernelIsa> isa{processorHasAvx2() ? KernelIsa::Avx2 : KernelIsa::Baseline};
    return isa;
}

#if TERRACAST_AVX2_KERNELS
bool useAvx2() { return currentIsa().load(std::memory_order_relaxed) == KernelIsa::Avx2; }
#endif

bool dispatch(const HeightGrid& g, const Ray& ray, Interval interval, CellMethod method, bool anyHit,
              TraceCounters* counters, Traversal tr, HeightFieldHit* out) {
    if (g.tiled()) return tiled_kernels::trace(g, ray, interval, method, anyHit, counters, tr, out);
#if TERRACAST_AVX2_KERNELS
    if (useAvx2()) return avx2::dispatch(g, ray, interval, method, anyHit, counters, tr, out);
#endif
    return baseline::dispatch(g, ray, interval, method, anyHit, counters, tr, out);
}

}  // namespace

std::optional<CellMethod> parseCellMethod(std::string_view name) {
    for (const auto& m : kMethodNames)
        if (name == m.name) return m.method;
    return std::nullopt;
}

const char* cellMethodName(CellMethod method) {
    for (const auto& m : kMethodNames)
        if (m.method == method) return m.name;
    return "?";
}

const std::vector<CellMethod>& allCellMethods() {
    static const std::vector<CellMethod> methods{CellMethod::Bilinear, CellMethod::BilinearDouble,
                                                 CellMethod::Triangles, CellMethod::Nearest, CellMethod::Reference};
    return methods;
}

KernelIsa kernelIsa() { return currentIsa().load(std::memory_order_relaxed); }

bool setKernelIsa(KernelIsa isa) {
    if (isa == KernelIsa::Avx2 && !processorHasAvx2()) return false;
    currentIsa().store(isa, std::memory_order_relaxed);
    return true;
}

const char* kernelIsaName(KernelIsa isa) { return isa == KernelIsa::Avx2 ? "avx2" : "baseline"; }

std::optional<HeightFieldHit> intersect(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method,
                                        TraceCounters* counters, Traversal traversal) {
    std::optional<HeightFieldHit> hit(std::in_place);
    if (!dispatch(grid, ray, interval, method, false, counters, traversal, &*hit)) hit.reset();
    return hit;
}

bool occluded(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method, TraceCounters* counters,
              Traversal traversal) {
    return dispatch(grid, ray, interval, method, true, counters, traversal, nullptr);
}

std::optional<HeightFieldHit> firstBlock(const HeightGrid& grid, const Ray& ray, Interval interval, CellMethod method) {
    std::optional<HeightFieldHit> hit(std::in_place);
    if (!dispatch(grid, ray, interval, method, true, nullptr, Traversal::Pyramid, &*hit)) hit.reset();
    return hit;
}

void intersectBundle(const HeightGrid& grid, std::span<const Ray> rays, Interval interval, CellMethod method,
                     std::span<std::optional<HeightFieldHit>> hits, TraceCounters* counters, Traversal traversal) {
    if (grid.tiled()) return tiled_kernels::traceBundle(grid, rays, interval, method, hits, counters, traversal);
#if TERRACAST_AVX2_KERNELS
    if (useAvx2()) return avx2::traceBundle(grid, rays, interval, method, hits, counters, traversal);
#endif
    baseline::traceBundle(grid, rays, interval, method, hits, counters, traversal);
}

glm::dvec3 spawnOrigin(const HeightFieldHit& hit, const glm::dvec3& dir) {
    const double side = glm::dot(hit.normal, dir) >= 0.0 ? 1.0 : -1.0;
    return hit.pointM + side * hit.errorM * hit.normal;
}

double grazingToleranceM(const HeightGrid& grid) {
    const double scale = std::max({std::abs(double(grid.minHeightM())), std::abs(double(grid.maxHeightM())),
                                   grid.cellSizeXM(), grid.cellSizeYM()});
    return 8.0 * double(std::numeric_limits<float>::epsilon()) * scale;
}

}  // namespace terracast

