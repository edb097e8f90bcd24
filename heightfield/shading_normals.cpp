#include "heightfield/shading_normals.h"

#include "heightfield/height_tile.h"

namespace terracast {
namespace {

// vertexGradient over any reader of the grid's heights and validity, `grid` giving its size and cell sizes.
template <class At, class Valid>
glm::dvec2 gradient(const HeightGrid& grid, int64_t i, int64_t j, const At& at, const Valid& vertexValid) {
    const auto valid = [&](int64_t a, int64_t b) {
        return a >= 0 && b >= 0 && a < grid.width() && b < grid.height() && vertexValid(a, b);
    };
    // The derivative along (di, dj) over a step of `step` metres between neighbours.
    const auto along = [&](int64_t di, int64_t dj, double step) {
        const bool below = valid(i - di, j - dj), above = valid(i + di, j + dj);
        if (below && above) return (double(at(i + di, j + dj)) - double(at(i - di, j - dj))) / (2.0 * step);
        if (above) return (double(at(i + di, j + dj)) - double(at(i, j))) / step;
        if (below) return (double(at(i, j)) - double(at(i - di, j - dj))) / step;
        return 0.0;
    };
    return {along(1, 0, grid.cellSizeXM()), along(0, 1, grid.cellSizeYM())};
}

template <class At, class Valid>
glm::dvec3 smooth(const HeightGrid& grid, int64_t cellX, int64_t cellY, double u, double v, const At& at,
                  const Valid& valid) {
    const glm::dvec2 g00 = gradient(grid, cellX, cellY, at, valid), g10 = gradient(grid, cellX + 1, cellY, at, valid);
    const glm::dvec2 g01 = gradient(grid, cellX, cellY + 1, at, valid);
    const glm::dvec2 g11 = gradient(grid, cellX + 1, cellY + 1, at, valid);
    const glm::dvec2 g = (1.0 - v) * ((1.0 - u) * g00 + u * g10) + v * ((1.0 - u) * g01 + u * g11);
    return glm::normalize(glm::dvec3(-g.x, -g.y, 1.0));
}

}  // namespace

glm::dvec2 vertexGradient(const HeightGrid& grid, int64_t i, int64_t j) {
    return gradient(
        grid, i, j, [&](int64_t a, int64_t b) { return grid.at(a, b); },
        [&](int64_t a, int64_t b) { return grid.vertexValid(a, b); });
}

glm::dvec3 smoothNormal(const HeightGrid& grid, int64_t cellX, int64_t cellY, double u, double v) {
    if (grid.tiled()) {
        // The 4 x 4 vertices the four corners' gradients read, from the cell's own tile when it holds them all
        // (every cell but those along the tile's border): one tile lookup instead of one per read.
        const HeightTile& tile = grid.tileOfCell(cellX, cellY);
        if (cellX - 1 >= tile.firstX() && cellX + 2 < tile.firstX() + tile.verticesX() && cellY - 1 >= tile.firstY() &&
            cellY + 2 < tile.firstY() + tile.verticesY())
            return smooth(
                grid, cellX, cellY, u, v, [&](int64_t a, int64_t b) { return tile.at(a, b); },
                [&](int64_t a, int64_t b) { return tile.vertexValid(a, b); });
    }
    return smooth(
        grid, cellX, cellY, u, v, [&](int64_t a, int64_t b) { return grid.at(a, b); },
        [&](int64_t a, int64_t b) { return grid.vertexValid(a, b); });
}

}  // namespace terracast
