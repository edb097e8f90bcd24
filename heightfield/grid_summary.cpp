#include "heightfield/grid_summary.h"

#include "heightfield/height_tile.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace terracast {

GridSummaryBuilder::GridSummaryBuilder(int64_t width, int64_t height, double scaleHint)
    : width_(width), height_(height), previousValid_(size_t(std::max<int64_t>(width, 0)), 1),
      scales_(int16CandidateScales(scaleHint)), roundTrips_(scales_.size(), 1),
      lo_(std::numeric_limits<float>::infinity()), hi_(-std::numeric_limits<float>::infinity()) {
    const TileLayout layout{std::max<int64_t>(width, 2), std::max<int64_t>(height, 2)};
    tilesX_ = layout.tilesX();
    tileHigh_.assign(size_t(layout.tileCount()), hi_);
    tileLow_.assign(size_t(layout.tileCount()), lo_);
}

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
        // The tiles the row's vertices belong to: a vertex on a tile edge belongs to both sides.
        const int64_t tilesY = int64_t(tileHigh_.size()) / tilesX_;
        for (int64_t tj = std::max<int64_t>(0, (j - 1) / kTileCells); tj <= std::min(j / kTileCells, tilesY - 1); ++tj) {
            if (j < tj * kTileCells || j > (tj + 1) * kTileCells) continue;
            for (int64_t ti = 0; ti < tilesX_; ++ti) {
                float high = tileHigh_[size_t(tj * tilesX_ + ti)], low = tileLow_[size_t(tj * tilesX_ + ti)];
                for (int64_t i = ti * kTileCells; i <= std::min((ti + 1) * kTileCells, width_ - 1); ++i)
                    if (ok == nullptr || ok[i] != 0) {
                        high = std::max(high, z[i]);
                        low = std::min(low, z[i]);
                    }
                tileHigh_[size_t(tj * tilesX_ + ti)] = high;
                tileLow_[size_t(tj * tilesX_ + ti)] = low;
            }
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
    s.pyramid = PyramidCoding::forHeights(s.storage == HeightStorage::Int16, s.codeOffset, s.codeScale, s.minHeightM,
                                          s.maxHeightM);
    s.tileMaxCodes.resize(tileHigh_.size());
    s.tileMinCodes.resize(tileLow_.size());
    for (size_t t = 0; t < tileHigh_.size(); ++t) {
        const bool any = tileLow_[t] <= tileHigh_[t];
        if (!any) {
            s.tileMaxCodes[t] = PyramidCoding::kNoMax;
            s.tileMinCodes[t] = PyramidCoding::kNoMin;
        } else if (s.storage == HeightStorage::Int16) {
            // The heights' own codes, as the whole grid's pyramid holds them.
            s.tileMaxCodes[t] = *int16Code(tileHigh_[t], s.codeScale, s.codeOffset);
            s.tileMinCodes[t] = *int16Code(tileLow_[t], s.codeScale, s.codeOffset);
        } else {
            s.tileMaxCodes[t] = s.pyramid.encodeUp(tileHigh_[t]);
            s.tileMinCodes[t] = s.pyramid.encodeDown(tileLow_[t]);
        }
    }
    return s;
}

}  // namespace terracast
