// The height grid: W x H vertices of float32 heights on a regular metric lattice, with a nodata mask.
#pragma once

#include <glm/glm.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace terracast {

// Thrown for grids that cannot be traced (too small, non-finite heights, inconsistent sizes).
class GridError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Vertex (i, j) sits at local position (i * cellSizeXM, j * cellSizeYM, height(i, j)); j grows northward.
// Cell (i, j) spans vertices i..i+1 and j..j+1. A cell touching a nodata vertex is a hole.
class HeightGrid {
public:
    HeightGrid() = default;

    // Builds a grid from row-major heights (row j = southmost first). `valid` is empty (every vertex valid)
    // or holds one flag per vertex. Throws GridError on a size mismatch, fewer than 2 x 2 vertices,
    // non-positive cell sizes or a non-finite height at a valid vertex.
    HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM, std::vector<float> heightsM,
               std::vector<uint8_t> valid = {});

    int64_t width() const { return width_; }    // vertices along x
    int64_t height() const { return height_; }  // vertices along y
    int64_t cellsX() const { return width_ - 1; }
    int64_t cellsY() const { return height_ - 1; }
    double cellSizeXM() const { return cellSizeXM_; }
    double cellSizeYM() const { return cellSizeYM_; }

    float at(int64_t i, int64_t j) const { return heightsM_[static_cast<size_t>(j * width_ + i)]; }
    bool vertexValid(int64_t i, int64_t j) const {
        return valid_.empty() || valid_[static_cast<size_t>(j * width_ + i)] != 0;
    }
    // True when all four corners of cell (i, j) are valid.
    bool cellValid(int64_t i, int64_t j) const {
        return cellValid_.empty() || cellValid_[static_cast<size_t>(j * cellsX() + i)] != 0;
    }
    bool hasNodata() const { return !valid_.empty(); }
    int64_t nodataVertexCount() const { return nodataVertices_; }
    int64_t validCellCount() const { return validCells_; }

    // Height range over valid vertices (metres); both 0 for a grid without valid cells.
    float minHeightM() const { return minHeightM_; }
    float maxHeightM() const { return maxHeightM_; }

    // Extent of the vertex lattice in local metres.
    double extentXM() const { return static_cast<double>(cellsX()) * cellSizeXM_; }
    double extentYM() const { return static_cast<double>(cellsY()) * cellSizeYM_; }

    // Multiplies every height by k (vertical exaggeration).
    void scaleHeights(float k);

    // Bytes held by the grid's own arrays (heights, masks and the max pyramid).
    size_t memoryBytes() const;

    // The maximum pyramid (Tevs, Ihrke, Seidel 2008, "Maximum mipmaps for fast, accurate, and scalable
    // dynamic height field rendering"): level k >= 1 holds, for each block of 2^k x 2^k cells, the highest
    // valid vertex of its cells (-infinity for a block without one). Level 0 is not stored: it is the cells.
    int pyramidLevels() const { return int(pyramid_.size()); }
    // Seconds the last pyramid build took.
    double pyramidBuildSeconds() const { return pyramidBuildSeconds_; }
    // Blocks along x and y at level k.
    int64_t pyramidBlocksX(int k) const { return (cellsX() + (int64_t(1) << k) - 1) >> k; }
    int64_t pyramidBlocksY(int k) const { return (cellsY() + (int64_t(1) << k) - 1) >> k; }
    // The highest valid height in block (bi, bj) of level k (1 <= k <= pyramidLevels()).
    float blockMaxM(int k, int64_t bi, int64_t bj) const {
        return pyramid_[size_t(k - 1)][size_t(bj * pyramidBlocksX(k) + bi)];
    }

    const std::vector<float>& heights() const { return heightsM_; }

private:
    void finish();
    void buildPyramid();

    int64_t width_ = 0;
    int64_t height_ = 0;
    double cellSizeXM_ = 1.0;
    double cellSizeYM_ = 1.0;
    std::vector<float> heightsM_;
    std::vector<uint8_t> valid_;      // per vertex; empty when all valid
    std::vector<uint8_t> cellValid_;  // per cell; empty when all valid
    int64_t nodataVertices_ = 0;
    int64_t validCells_ = 0;
    float minHeightM_ = 0.0f;
    float maxHeightM_ = 0.0f;
    std::vector<std::vector<float>> pyramid_;  // levels 1..n, row-major blocks
    double pyramidBuildSeconds_ = 0.0;
};

}  // namespace terracast
