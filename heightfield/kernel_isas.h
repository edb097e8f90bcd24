// The traversal kernels, compiled once for baseline x86-64 and once with AVX2 enabled, inside the namespaces
// `baseline` and `avx2` of the including file's anonymous namespace. Included by traversal.cpp (whole grids)
// and traversal_tiled.cpp (tiled grids, TERRACAST_TILED_KERNELS set to 1), each after its own includes: the
// kernels of the two kinds of grid are separate translation units, so that neither changes how the compiler
// inlines the other's. Not a header of its own: no pragma once.
#ifndef TERRACAST_TILED_KERNELS
#define TERRACAST_TILED_KERNELS 0
#endif

// GCC on x86-64 compiles the kernels a second time for processors with AVX2 and BMI2.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define TERRACAST_AVX2_KERNELS 1
#else
#define TERRACAST_AVX2_KERNELS 0
#endif

namespace terracast {

// The tiled grids' traces (traversal_tiled.cpp), which traversal.cpp's entry points hand tiled grids to.
namespace tiled_kernels {
bool trace(const HeightGrid& g, const Ray& ray, Interval interval, CellMethod method, bool anyHit,
           TraceCounters* counters, Traversal tr, HeightFieldHit* out);
void traceBundle(const HeightGrid& grid, std::span<const Ray> rays, Interval interval, CellMethod method,
                 std::span<std::optional<HeightFieldHit>> hits, TraceCounters* counters, Traversal traversal);
}  // namespace tiled_kernels

namespace {

// The kernels, once per instruction set. The second set is compiled with AVX2, BMI and BMI2 enabled for its
// own functions only (the target pragma leaves the library's and the headers' inline functions as they are, and
// GCC inlines those into the kernels), so no function another file might share is built for a processor that
// lacks them. Fused multiply-adds stay off: every operation rounds alike in both sets, which therefore return
// the same bits (tested), and the faster one is used when the processor has it.
namespace baseline {
#include "heightfield/height_accessors.h"
#include "heightfield/traversal_kernels.h"
#include "heightfield/bundle_kernels.h"
}  // namespace baseline

#if TERRACAST_AVX2_KERNELS
#pragma GCC push_options
#pragma GCC target("avx2,bmi,bmi2,lzcnt,popcnt,f16c,movbe")
namespace avx2 {
#include "heightfield/height_accessors.h"
#include "heightfield/traversal_kernels.h"
#include "heightfield/bundle_kernels.h"
}  // namespace avx2
#pragma GCC pop_options
#endif

}  // namespace
}  // namespace terracast
