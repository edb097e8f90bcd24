#include "heightfield/height_tile.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace terracast {

namespace {

void setBit(std::vector<uint64_t>& bits, int64_t k) { bits[static_cast<size_t>(k) >> 6] |= uint64_t{1} << (k & 63); }

}  // namespace

HeightTile::HeightTile(const GridSummary& summary, int64_t firstX, int64_t firstY, int64_t verticesX,
                       int64_t verticesY, const float* heightsM, const uint8_t* valid)
    : firstX_(firstX), firstY_(firstY), verticesX_(verticesX), verticesY_(verticesY),
      codeOffset_(summary.codeOffset), codeScale_(summary.codeScale) {
    const auto n = static_cast<size_t>(verticesX * verticesY);
    bool allValid = true;
    for (size_t k = 0; valid != nullptr && k < n && allValid; ++k) allValid = valid[k] != 0;
    if (!allValid) {
        valid_.assign((n + 63) / 64, 0);
        for (size_t k = 0; k < n; ++k)
            if (valid[k] != 0) setBit(valid_, int64_t(k));
        const int64_t cellsX = verticesX - 1;
        cellValid_.assign(static_cast<size_t>(cellsX * (verticesY - 1) + 63) / 64, 0);
        for (int64_t j = 0; j + 1 < verticesY; ++j)
            for (int64_t i = 0; i < cellsX; ++i) {
                const size_t k = static_cast<size_t>(j * verticesX + i);
                if (valid[k] && valid[k + 1] && valid[k + size_t(verticesX)] && valid[k + size_t(verticesX) + 1])
                    setBit(cellValid_, j * cellsX + i);
            }
    }
    if (summary.storage == HeightStorage::Float32) {
        heightsM_.assign(heightsM, heightsM + n);
        buildPyramid(summary);
        return;
    }
    // As HeightGrid encodes: the nearest code, and the lowest code for a nodata vertex whose value has none.
    codes_.resize(n);
    const bool unitCodes = codeScale_ == 1.0;
    for (size_t k = 0; k < n; ++k) {
        // One metre per code (most DEMs): an integer height other than -0 has the code int16Code gives it,
        // found without its division and rounding; anything else takes int16Code itself.
        const float z = heightsM[k];
        if (unitCodes && z > -1.0e9f && z < 1.0e9f) {
            const int32_t whole = static_cast<int32_t>(z);
            const int64_t c = int64_t(whole) - codeOffset_;
            if (static_cast<float>(whole) == z && std::bit_cast<uint32_t>(z) != 0x80000000u &&
                c >= std::numeric_limits<int16_t>::min() && c <= std::numeric_limits<int16_t>::max()) {
                codes_[k] = static_cast<int16_t>(c);
                continue;
            }
        }
        const auto code = int16Code(z, codeScale_, codeOffset_);
        if (!code && (valid == nullptr || valid[k] != 0))
            throw GridError("tile at vertex (" + std::to_string(firstX + int64_t(k) % verticesX) + ", " +
                            std::to_string(firstY + int64_t(k) / verticesX) + "): height " +
                            std::to_string(heightsM[k]) + " has no int16 code at the grid's scale");
        codes_[k] = code.value_or(std::numeric_limits<int16_t>::min());
    }
    buildPyramid(summary);
}

// As HeightGrid builds its pyramid: level 1 from the valid vertices of each block's 3 x 3 (clipped), each
// level above from the one below. The tile's first vertex is a multiple of kTileCells, so its blocks are the
// grid's.
void HeightTile::buildPyramid(const GridSummary& summary) {
    levels_ = std::min(kTileLevels, pyramidLevelCount(summary.width - 1, summary.height - 1));
    const int64_t cellsX = verticesX_ - 1, cellsY = verticesY_ - 1;
    const bool int16 = !codes_.empty();
    std::vector<std::vector<int16_t>> highs(1), lows(1);
    const int64_t bx1 = (cellsX + 1) / 2, by1 = (cellsY + 1) / 2;
    highs[0].assign(static_cast<size_t>(bx1 * by1), PyramidCoding::kNoMax);
    lows[0].assign(highs[0].size(), PyramidCoding::kNoMin);
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int64_t bj = 0; bj < by1; ++bj)
        for (int64_t bi = 0; bi < bx1; ++bi) {
            // Codes order as heights do: the block's extreme heights, encoded once.
            int16_t hi = PyramidCoding::kNoMax, lo = PyramidCoding::kNoMin;
            float hiM = -kInf, loM = kInf;
            for (int64_t j = 2 * bj; j <= std::min(2 * bj + 2, cellsY); ++j)
                for (int64_t i = 2 * bi; i <= std::min(2 * bi + 2, cellsX); ++i) {
                    const int64_t k = j * verticesX_ + i;
                    if (!valid_.empty() && !bit(valid_, k)) continue;
                    if (int16) {
                        hi = std::max(hi, codes_[size_t(k)]);
                        lo = std::min(lo, codes_[size_t(k)]);
                    } else {
                        hiM = std::max(hiM, heightsM_[size_t(k)]);
                        loM = std::min(loM, heightsM_[size_t(k)]);
                    }
                }
            if (!int16 && hiM >= loM) {
                hi = summary.pyramid.encodeUp(hiM);
                lo = summary.pyramid.encodeDown(loM);
            }
            highs[0][size_t(bj * bx1 + bi)] = hi;
            lows[0][size_t(bj * bx1 + bi)] = lo;
        }
    int64_t bx = bx1, by = by1;
    for (int k = 2; k <= levels_; ++k) {
        highs.push_back(pyramidParentLevel(highs.back(), bx, by, true));
        lows.push_back(pyramidParentLevel(lows.back(), bx, by, false));
        bx = (bx + 1) / 2;
        by = (by + 1) / 2;
    }
    for (int k = 1; k <= levels_; ++k) {
        levelStart_[k - 1] = int64_t(maxCodes_.size());
        levelBlocksX_[k - 1] = (cellsX + (int64_t(1) << k) - 1) >> k;
        maxCodes_.insert(maxCodes_.end(), highs[size_t(k - 1)].begin(), highs[size_t(k - 1)].end());
        minCodes_.insert(minCodes_.end(), lows[size_t(k - 1)].begin(), lows[size_t(k - 1)].end());
    }
}

size_t HeightTile::bytes() const {
    return sizeof(*this) + codes_.capacity() * sizeof(int16_t) + heightsM_.capacity() * sizeof(float) +
           (valid_.capacity() + cellValid_.capacity()) * sizeof(uint64_t) +
           (maxCodes_.capacity() + minCodes_.capacity()) * sizeof(int16_t);
}

}  // namespace terracast
