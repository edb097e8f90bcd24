#include "loaders/height_png.h"

#include "loaders/image_io.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace terracast {

std::string encodeHeightPng16(const HeightGrid& grid) {
    const int64_t W = grid.width(), H = grid.height();
    if (W <= 0 || H <= 0 || W > 0x7fffffff || H > 0x7fffffff) throw std::runtime_error("height PNG: bad grid size");
    std::vector<uint16_t> samples(size_t(W) * size_t(H));
    for (int64_t y = 0; y < H; ++y) {
        const int64_t j = H - 1 - y;  // the image's top row is the grid's northmost
        for (int64_t i = 0; i < W; ++i) {
            const float h = grid.vertexValid(i, j) ? grid.at(i, j) : 0.0f;
            samples[size_t(y * W + i)] = std::isfinite(h) ? uint16_t(std::clamp(std::lround(h), 0L, 65535L)) : 0;
        }
    }
    return encodeGreyPng16("height-map.png", int(W), int(H), samples);
}

}  // namespace terracast
