#include "heightfield/height_tile.h"

#include <cmath>
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
        return;
    }
    // As HeightGrid encodes: the nearest code, and the lowest code for a nodata vertex whose value has none.
    codes_.resize(n);
    for (size_t k = 0; k < n; ++k) {
        const auto code = int16Code(heightsM[k], codeScale_, codeOffset_);
        if (!code && (valid == nullptr || valid[k] != 0))
            throw GridError("tile at vertex (" + std::to_string(firstX + int64_t(k) % verticesX) + ", " +
                            std::to_string(firstY + int64_t(k) / verticesX) + "): height " +
                            std::to_string(heightsM[k]) + " has no int16 code at the grid's scale");
        codes_[k] = code.value_or(std::numeric_limits<int16_t>::min());
    }
}

size_t HeightTile::bytes() const {
    return sizeof(*this) + codes_.capacity() * sizeof(int16_t) + heightsM_.capacity() * sizeof(float) +
           (valid_.capacity() + cellValid_.capacity()) * sizeof(uint64_t);
}

}  // namespace terracast
