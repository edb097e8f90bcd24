#include "heightfield/height_grid.h"

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
}

void HeightGrid::scaleHeights(float k) {
    if (!std::isfinite(k) || k <= 0.0f)
        throw GridError("vertical exaggeration must be positive and finite, got " + std::to_string(k));
    for (float& h : heightsM_) h *= k;
    finish();
}

size_t HeightGrid::memoryBytes() const {
    return heightsM_.capacity() * sizeof(float) + valid_.capacity() + cellValid_.capacity();
}

}  // namespace terracast
