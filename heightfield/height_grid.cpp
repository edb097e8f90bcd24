#include "heightfield/height_grid.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <string>

namespace terracast {

HeightGrid::HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                       std::vector<float> heightsM, std::vector<uint8_t> valid)
    : width_(width), height_(height), cellSizeXM_(cellSizeXM), cellSizeYM_(cellSizeYM),
      heightsM_(std::move(heightsM)), valid_(std::move(valid)) {
    if (width_ < 2 || height_ < 2)
        throw GridError("a height grid needs at least 2 x 2 vertices (one cell), got " + std::to_string(width_) +
                        " x " + std::to_string(height_));
    if (!(cellSizeXM_ > 0.0) || !(cellSizeYM_ > 0.0) || !std::isfinite(cellSizeXM_) || !std::isfinite(cellSizeYM_))
        throw GridError("cell sizes must be positive and finite, got " + std::to_string(cellSizeXM_) + " x " +
                        std::to_string(cellSizeYM_) + " m");
    const auto n = static_cast<size_t>(width_) * static_cast<size_t>(height_);
    if (heightsM_.size() != n)
        throw GridError("expected " + std::to_string(n) + " heights, got " + std::to_string(heightsM_.size()));
    if (!valid_.empty() && valid_.size() != n)
        throw GridError("expected " + std::to_string(n) + " validity flags, got " + std::to_string(valid_.size()));
    finish();
}

void HeightGrid::finish() {
    nodataVertices_ = 0;
    float lo = std::numeric_limits<float>::infinity();
    float hi = -lo;
    for (int64_t j = 0; j < height_; ++j) {
        for (int64_t i = 0; i < width_; ++i) {
            if (!vertexValid(i, j)) {
                ++nodataVertices_;
                continue;
            }
            const float h = at(i, j);
            if (!std::isfinite(h))
                throw GridError("height at vertex (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") is not finite (" + std::to_string(h) + ")");
            lo = std::min(lo, h);
            hi = std::max(hi, h);
        }
    }
    if (nodataVertices_ == 0) valid_.clear();

    cellValid_.clear();
    validCells_ = cellsX() * cellsY();
    if (!valid_.empty()) {
        cellValid_.assign(static_cast<size_t>(cellsX() * cellsY()), 0);
        validCells_ = 0;
        for (int64_t j = 0; j < cellsY(); ++j)
            for (int64_t i = 0; i < cellsX(); ++i) {
                const bool ok = vertexValid(i, j) && vertexValid(i + 1, j) && vertexValid(i, j + 1) &&
                                vertexValid(i + 1, j + 1);
                cellValid_[static_cast<size_t>(j * cellsX() + i)] = ok ? 1 : 0;
                validCells_ += ok ? 1 : 0;
            }
    }
    // Heights of vertices that belong to no valid cell still bound the box; harmless and conservative.
    if (lo > hi) lo = hi = 0.0f;
    minHeightM_ = lo;
    maxHeightM_ = hi;
    buildPyramid();
}

void HeightGrid::buildPyramid() {
    // Level 1 straight from the vertices: block (bi, bj) covers cells 2bi..2bi+1, 2bj..2bj+1, that is
    // vertices 2bi..2bi+2, 2bj..2bj+2. A cell's own maximum takes only its valid vertices, so a hole cell
    // next to a valid vertex still bounds it (the traversal's corner handling relies on that).
    const auto start = std::chrono::steady_clock::now();
    pyramid_.clear();
    constexpr float kNone = -std::numeric_limits<float>::infinity();
    auto vertexMax = [&](int64_t i, int64_t j) {
        if (i >= width_ || j >= height_ || !vertexValid(i, j)) return kNone;
        return at(i, j);
    };
    int64_t bx = (cellsX() + 1) / 2, by = (cellsY() + 1) / 2;
    std::vector<float> level(static_cast<size_t>(bx * by));
    for (int64_t bj = 0; bj < by; ++bj)
        for (int64_t bi = 0; bi < bx; ++bi) {
            float m = kNone;
            for (int64_t j = 2 * bj; j <= std::min(2 * bj + 2, cellsY()); ++j)
                for (int64_t i = 2 * bi; i <= std::min(2 * bi + 2, cellsX()); ++i) m = std::max(m, vertexMax(i, j));
            level[static_cast<size_t>(bj * bx + bi)] = m;
        }
    pyramid_.push_back(std::move(level));
    while (bx > 1 || by > 1) {
        const auto& prev = pyramid_.back();
        const int64_t px = bx, py = by;
        bx = (bx + 1) / 2;
        by = (by + 1) / 2;
        std::vector<float> next(static_cast<size_t>(bx * by), kNone);
        for (int64_t j = 0; j < py; ++j)
            for (int64_t i = 0; i < px; ++i) {
                float& m = next[static_cast<size_t>((j / 2) * bx + i / 2)];
                m = std::max(m, prev[static_cast<size_t>(j * px + i)]);
            }
        pyramid_.push_back(std::move(next));
    }
    pyramidBuildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void HeightGrid::scaleHeights(float k) {
    if (!std::isfinite(k) || k <= 0.0f)
        throw GridError("vertical exaggeration must be positive and finite, got " + std::to_string(k));
    for (float& h : heightsM_) h *= k;
    finish();
}

size_t HeightGrid::memoryBytes() const {
    size_t pyramid = 0;
    for (const auto& level : pyramid_) pyramid += level.capacity() * sizeof(float);
    return heightsM_.capacity() * sizeof(float) + valid_.capacity() + cellValid_.capacity() + pyramid;
}

}  // namespace terracast
