#include "heightfield/shading_normals.h"

namespace terracast {

glm::dvec2 vertexGradient(const HeightGrid& grid, int64_t i, int64_t j) {
    const auto valid = [&](int64_t a, int64_t b) {
        return a >= 0 && b >= 0 && a < grid.width() && b < grid.height() && grid.vertexValid(a, b);
    };
    // The derivative along (di, dj) over a step of `step` metres between neighbours.
    const auto along = [&](int64_t di, int64_t dj, double step) {
        const bool below = valid(i - di, j - dj), above = valid(i + di, j + dj);
        if (below && above)
            return (double(grid.at(i + di, j + dj)) - double(grid.at(i - di, j - dj))) / (2.0 * step);
        if (above) return (double(grid.at(i + di, j + dj)) - double(grid.at(i, j))) / step;
        if (below) return (double(grid.at(i, j)) - double(grid.at(i - di, j - dj))) / step;
        return 0.0;
    };
    return {along(1, 0, grid.cellSizeXM()), along(0, 1, grid.cellSizeYM())};
}

glm::dvec3 smoothNormal(const HeightGrid& grid, int64_t cellX, int64_t cellY, double u, double v) {
    const glm::dvec2 g00 = vertexGradient(grid, cellX, cellY), g10 = vertexGradient(grid, cellX + 1, cellY);
    const glm::dvec2 g01 = vertexGradient(grid, cellX, cellY + 1), g11 = vertexGradient(grid, cellX + 1, cellY + 1);
    const glm::dvec2 g = (1.0 - v) * ((1.0 - u) * g00 + u * g10) + v * ((1.0 - u) * g01 + u * g11);
    return glm::normalize(glm::dvec3(-g.x, -g.y, 1.0));
}

}  // namespace terracast
