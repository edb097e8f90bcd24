#include "tracer/terrain/memory_model.h"

#include "tracer/core/errors.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"

#include <fmt/format.h>

namespace terracast {

double embreeBytesEstimate(SurfaceMethod m, const HeightGrid& grid) {
    const double cells = double(grid.validCellCount());
    if (m == SurfaceMethod::Embree) return 230.0 * cells;
    if (m == SurfaceMethod::EmbreeGrid) return 40.0 * cells;
    return 0.0;
}

double levelOfDetailBytes(const HeightGrid& grid) {
    return grid.tiled() ? double(grid.tileSource()->cacheBudgetBytes()) : double(grid.memoryBytes()) / 3.0;
}

void checkMemory(const std::string& path, double maxMemoryBytes, const HeightGrid& grid, double extraBytes,
                 const std::string& what) {
    const double limit = memoryLimitBytes(maxMemoryBytes);
    const double held = currentResidentBytes();
    const double need = held + extraBytes;
    if (need > limit)
        throw InputError(fmt::format("{}: {} needs about {} ({} held already, {} of it the grid), more than the {} "
                                     "limit (--max-memory)",
                                     path, what, humanBytes(need), humanBytes(held),
                                     humanBytes(double(grid.memoryBytes())), humanBytes(limit)));
}

}  // namespace terracast
