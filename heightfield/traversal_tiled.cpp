// The traversal kernels for tiled grids (docs/architecture.md, "Tiled grids"): the same walk as whole grids'
// reading heights, cell flags and pyramid codes through TiledHeights, in a translation unit of its own.
#include "heightfield/traversal.h"

#include "heightfield/cell_intersectors.h"
#include "heightfield/dda.h"
#include "heightfield/height_tile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <span>
#include <type_traits>

#define TERRACAST_TILED_KERNELS 1
#include "heightfield/kernel_isas.h"

namespace terracast::tiled_kernels {

bool trace(const HeightGrid& g, const Ray& ray, Interval interval, CellMethod method, bool anyHit,
           TraceCounters* counters, Traversal tr, HeightFieldHit* out) {
#if TERRACAST_AVX2_KERNELS
    if (kernelIsa() == KernelIsa::Avx2) return avx2::dispatch(g, ray, interval, method, anyHit, counters, tr, out);
#endif
    return baseline::dispatch(g, ray, interval, method, anyHit, counters, tr, out);
}

void traceBundle(const HeightGrid& grid, std::span<const Ray> rays, Interval interval, CellMethod method,
                 std::span<std::optional<HeightFieldHit>> hits, TraceCounters* counters, Traversal traversal) {
#if TERRACAST_AVX2_KERNELS
    if (kernelIsa() == KernelIsa::Avx2) return avx2::traceBundle(grid, rays, interval, method, hits, counters, traversal);
#endif
    baseline::traceBundle(grid, rays, interval, method, hits, counters, traversal);
}

}  // namespace terracast::tiled_kernels
