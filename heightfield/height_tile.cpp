#include "heightfield/height_tile.h"

#include "heightfield/pyramid_build.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>

namespace terracast {

namespace {

void setBit(std::vector<uint64_t>& bits, int64_t k) { bits[static_cast<size_t>(k) >> 6] |= uint64_t{1} << (k & 63); }

constexpr int32_t kLowestCode = std::numeric_limits<int16_t>::min();
constexpr int32_t kHighestCode = std::numeric_limits<int16_t>::max();

}  // namespace

// Vertex and cell validity bits from one flag per vertex, left empty when every vertex is valid.
void HeightTile::setValidity(const uint8_t* valid) {
    const auto n = static_cast<size_t>(verticesX_ * verticesY_);
    if (valid == nullptr || std::memchr(valid, 0, n) == nullptr) return;
    valid_.assign((n + 63) / 64, 0);
    for (size_t k = 0; k < n; ++k)
        if (valid[k] != 0) setBit(valid_, int64_t(k));
    const int64_t cellsX = verticesX_ - 1;
    cellValid_.assign(static_cast<size_t>(cellsX * (verticesY_ - 1) + 63) / 64, 0);
    for (int64_t j = 0; j + 1 < verticesY_; ++j)
        for (int64_t i = 0; i < cellsX; ++i) {
            const size_t k = static_cast<size_t>(j * verticesX_ + i);
            if (valid[k] && valid[k + 1] && valid[k + size_t(verticesX_)] && valid[k + size_t(verticesX_) + 1])
                setBit(cellValid_, j * cellsX + i);
        }
}

void HeightTile::throwNoCode(size_t k, double heightM) const {
    throw GridError("tile at vertex (" + std::to_string(firstX_ + int64_t(k) % verticesX_) + ", " +
                    std::to_string(firstY_ + int64_t(k) / verticesX_) + "): height " + std::to_string(heightM) +
                    " has no int16 code at the grid's scale");
}

HeightTile::HeightTile(const GridSummary& summary, int64_t firstX, int64_t firstY, int64_t verticesX,
                       int64_t verticesY, const float* heightsM, const uint8_t* valid)
    : firstX_(firstX), firstY_(firstY), verticesX_(verticesX), verticesY_(verticesY),
      codeOffset_(summary.codeOffset), codeScale_(summary.codeScale) {
    const auto n = static_cast<size_t>(verticesX * verticesY);
    setValidity(valid);
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
            if (static_cast<float>(whole) == z && std::bit_cast<uint32_t>(z) != 0x80000000u && c >= kLowestCode &&
                c <= kHighestCode) {
                codes_[k] = static_cast<int16_t>(c);
                continue;
            }
        }
        const auto code = int16Code(z, codeScale_, codeOffset_);
        if (!code && (valid == nullptr || valid[k] != 0)) throwNoCode(k, heightsM[k]);
        codes_[k] = code.value_or(std::numeric_limits<int16_t>::min());
    }
    buildPyramid(summary);
}

bool HeightTile::takesWholeMetres(const GridSummary& summary) {
    return summary.storage == HeightStorage::Int16 && summary.codeScale == 1.0;
}

HeightTile::HeightTile(const GridSummary& summary, int64_t firstX, int64_t firstY, int64_t verticesX,
                       int64_t verticesY, const int16_t* wholeMetres, const uint8_t* valid)
    : firstX_(firstX), firstY_(firstY), verticesX_(verticesX), verticesY_(verticesY),
      codeOffset_(summary.codeOffset), codeScale_(summary.codeScale) {
    if (!takesWholeMetres(summary)) throw GridError("a tile of whole metres needs a grid of one metre per code");
    const auto n = static_cast<size_t>(verticesX * verticesY);
    setValidity(valid);
    codes_.resize(n);
    // The code of an integer height h at one metre per code is h - offset (the float constructor's fast path),
    // taken modulo 2^16 here; the loop keeps the range of the heights so that one check after it finds any code
    // that int16 cannot hold. (16-bit lanes throughout, which the compiler vectorises eight to a register.)
    const auto offset = static_cast<uint16_t>(codeOffset_);
    int16_t lowestM = std::numeric_limits<int16_t>::max(), highestM = std::numeric_limits<int16_t>::min();
    {
        const int16_t* __restrict in = wholeMetres;
        int16_t* __restrict out = codes_.data();
        for (size_t k = 0; k < n; ++k) {
            out[k] = static_cast<int16_t>(static_cast<uint16_t>(in[k]) - offset);
            lowestM = std::min(lowestM, in[k]);
            highestM = std::max(highestM, in[k]);
        }
    }
    const int32_t lowest = int32_t(lowestM) - codeOffset_, highest = int32_t(highestM) - codeOffset_;
    if (lowest < kLowestCode || highest > kHighestCode) {
        // A valid height off the grid's codes means the DEM is not the one summarised; a nodata vertex's 0 may be
        // off them too, and takes the lowest code as in the float constructor.
        for (size_t k = 0; k < n; ++k) {
            const int32_t c = int32_t(wholeMetres[k]) - codeOffset_;
            if (c >= kLowestCode && c <= kHighestCode) continue;
            if (valid == nullptr || valid[k] != 0) throwNoCode(k, wholeMetres[k]);
            codes_[k] = std::numeric_limits<int16_t>::min();
        }
    }
    buildPyramid(summary);
}

// As HeightGrid builds its pyramid (pyramid_build.h): level 1 from the valid vertices of each block's 3 x 3
// (clipped), each level above from the one below. The tile's first vertex is a multiple of kTileCells, so its
// blocks are the grid's.
void HeightTile::buildPyramid(const GridSummary& summary) {
    levels_ = std::min(kTileLevels, pyramidLevelCount(summary.width - 1, summary.height - 1));
    const int64_t cellsX = verticesX_ - 1, cellsY = verticesY_ - 1;
    vertexOrigin_ = firstY_ * verticesX_ + firstX_;
    cellOrigin_ = firstY_ * cellsX + firstX_;
    unitCodes_ = !codes_.empty() && codeScale_ == 1.0;
    int64_t total = 0;
    for (int k = 1; k <= levels_; ++k) {
        levelStart_[k - 1] = total;
        levelBlocksX_[k - 1] = (cellsX + (int64_t(1) << k) - 1) >> k;
        levelOrigin_[k - 1] = total - (firstY_ >> k) * levelBlocksX_[k - 1] - (firstX_ >> k);
        total += levelBlocksX_[k - 1] * ((cellsY + (int64_t(1) << k) - 1) >> k);
    }
    maxCodes_.resize(static_cast<size_t>(total));
    minCodes_.resize(static_cast<size_t>(total));
    const int64_t by1 = (cellsY + 1) / 2;
    if (!codes_.empty()) {
        const int16_t* codes = codes_.data();
        auto same = [](int16_t q) { return q; };
        pyramidLevelOneRows(verticesX_, cellsX, cellsY, valid_, 0, by1, [codes](int64_t k) { return codes[k]; },
                            PyramidCoding::kNoMax, PyramidCoding::kNoMin, same, same, maxCodes_.data(),
                            minCodes_.data());
    } else {
        const float* h = heightsM_.data();
        constexpr float kInf = std::numeric_limits<float>::infinity();
        const PyramidCoding& coding = summary.pyramid;
        pyramidLevelOneRows(
            verticesX_, cellsX, cellsY, valid_, 0, by1, [h](int64_t k) { return h[k]; }, -kInf, kInf,
            [&](float z) { return z == -kInf ? PyramidCoding::kNoMax : coding.encodeUp(z); },
            [&](float z) { return z == kInf ? PyramidCoding::kNoMin : coding.encodeDown(z); }, maxCodes_.data(),
            minCodes_.data());
    }
    for (int k = 2; k <= levels_; ++k) {
        const int64_t px = levelBlocksX_[k - 2], py = (cellsY + (int64_t(1) << (k - 1)) - 1) >> (k - 1);
        pyramidParentLevel(maxCodes_.data() + levelStart_[k - 2], px, py, true, maxCodes_.data() + levelStart_[k - 1]);
        pyramidParentLevel(minCodes_.data() + levelStart_[k - 2], px, py, false, minCodes_.data() + levelStart_[k - 1]);
    }
}

size_t HeightTile::bytes() const {
    return sizeof(*this) + codes_.capacity() * sizeof(int16_t) + heightsM_.capacity() * sizeof(float) +
           (valid_.capacity() + cellValid_.capacity()) * sizeof(uint64_t) +
           (maxCodes_.capacity() + minCodes_.capacity()) * sizeof(int16_t);
}

}  // namespace terracast
