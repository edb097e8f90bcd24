#include "heightfield/grid_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace terracast {

GridSummaryBuilder::GridSummaryBuilder(int64_t width, int64_t height, double scaleHint)
    : width_(width), height_(height), previousValid_(size_t(std::max<int64_t>(width, 0)), 1),
      scales_(int16CandidateScales(scaleHint)), roundTrips_(scales_.size(), 1),
      lo_(std::numeric_limits<float>::infinity()), hi_(-std::numeric_limits<float>::infinity()) {}

void GridSummaryBuilder::addRows(int64_t j0, int64_t rows, const float* heightsM, const uint8_t* valid) {
    if (j0 != nextRow_ || rows < 0 || j0 + rows > height_)
        throw std::invalid_argument("GridSummaryBuilder: rows " + std::to_string(j0) + "+" + std::to_string(rows) +
                                    " do not follow row " + std::to_string(nextRow_));
    for (int64_t r = 0; r < rows; ++r) {
        const int64_t j = j0 + r;
        const float* z = heightsM + r * width_;
        const uint8_t* ok = valid ? valid + r * width_ : nullptr;
        for (int64_t i = 0; i < width_; ++i) {
            const bool vertexOk = ok == nullptr || ok[i] != 0;
            if (!vertexOk) {
                ++nodata_;
                continue;
            }
            if (!std::isfinite(z[i]))
                throw GridError("height at vertex (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") is not finite (" + std::to_string(z[i]) + ")");
            lo_ = std::min(lo_, z[i]);
            hi_ = std::max(hi_, z[i]);
            for (size_t s = 0; s < scales_.size(); ++s)
                if (roundTrips_[s] && !int16RoundTrips(z[i], scales_[s])) roundTrips_[s] = 0;
        }
        // The cells of the row below this one, now that both their rows are known.
        if (j > 0)
            for (int64_t i = 0; i + 1 < width_; ++i) {
                const bool here = ok == nullptr || (ok[i] != 0 && ok[i + 1] != 0);
                validCells_ += here && previousValid_[size_t(i)] && previousValid_[size_t(i + 1)];
            }
        for (int64_t i = 0; i < width_; ++i) previousValid_[size_t(i)] = ok == nullptr || ok[i] != 0;
    }
    nextRow_ += rows;
}

GridSummary GridSummaryBuilder::finish() const {
    if (nextRow_ != height_)
        throw std::logic_error("GridSummaryBuilder: " + std::to_string(nextRow_) + " of " + std::to_string(height_) +
                               " rows added");
    GridSummary s;
    s.width = width_;
    s.height = height_;
    s.nodataVertices = nodata_;
    s.validCells = validCells_;
    // As HeightGrid: the height range of the valid vertices, and int16 codes at the first scale that holds every
    // valid height exactly within 65536 codes.
    s.minHeightM = lo_ <= hi_ ? lo_ : 0.0f;
    s.maxHeightM = lo_ <= hi_ ? hi_ : 0.0f;
    for (size_t k = 0; k < scales_.size(); ++k) {
        if (!roundTrips_[k]) continue;
        const auto offset = int16CodeOffset(s.minHeightM, s.maxHeightM, scales_[k]);
        if (!offset) continue;
        s.storage = HeightStorage::Int16;
        s.codeOffset = *offset;
        s.codeScale = scales_[k];
        break;
    }
    return s;
}

}  // namespace terracast
