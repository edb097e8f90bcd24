#include "loaders/block_edges.h"

#include <algorithm>
#include <cstring>

namespace terracast {

BlockEdges::BlockEdges(int64_t width, int64_t height, int64_t blockColumns, int64_t blockRows)
    : width_(width), height_(height), blockColumns_(std::max<int64_t>(1, blockColumns)),
      blockRows_(std::max<int64_t>(1, blockRows)) {}

bool BlockEdges::serves(int64_t column0, int64_t row0, int64_t w, int64_t h) const {
    return blockColumns_ > 1 && blockRows_ > 1 && column0 % blockColumns_ == 0 && row0 % blockRows_ == 0 &&
           w <= blockColumns_ + 1 && h <= blockRows_ + 1 && (w == blockColumns_ + 1 || h == blockRows_ + 1);
}

uint64_t BlockEdges::key(int type, int64_t column0, int64_t row0) const {
    return (uint64_t(type) << 56) ^ (uint64_t(row0 / blockRows_) << 28) ^ uint64_t(column0 / blockColumns_);
}

void BlockEdges::keep(uint64_t key, const Edges& e) const {
    std::lock_guard guard(mutex_);
    if (bytes_ > kBudgetBytes) {
        edges_.clear();
        bytes_ = 0;
    }
    if (edges_.emplace(key, e).second) bytes_ += e.firstRow.size() + e.firstColumn.size() + 64;
}

BlockEdges::Edges BlockEdges::edgesOf(int type, int bytes, int64_t column0, int64_t row0, const ReadWindow& read) const {
    const uint64_t k = key(type, column0, row0);
    {
        std::lock_guard guard(mutex_);
        if (const auto it = edges_.find(k); it != edges_.end()) return it->second;
    }
    // The block's first row, then its first column: GDAL decodes the block once for both.
    const int64_t w = std::min(blockColumns_, width_ - column0), h = std::min(blockRows_, height_ - row0);
    Edges e;
    e.firstRow.resize(size_t(w) * size_t(bytes));
    e.firstColumn.resize(size_t(h) * size_t(bytes));
    read(column0, row0, w, 1, e.firstRow.data(), w);
    read(column0, row0, 1, h, e.firstColumn.data(), 1);
    keep(k, e);
    return e;
}

void BlockEdges::read(int type, int bytes, int64_t column0, int64_t row0, int64_t w, int64_t h, unsigned char* raw,
                      const ReadWindow& read) const {
    const auto b = size_t(bytes);
    const int64_t cw = std::min(w, blockColumns_), ch = std::min(h, blockRows_);
    read(column0, row0, cw, ch, raw, w);
    // The block just read holds its own first row and column, for the windows that end in it.
    if (cw == std::min(blockColumns_, width_ - column0) && ch == std::min(blockRows_, height_ - row0)) {
        Edges own;
        own.firstRow.assign(raw, raw + size_t(cw) * b);
        own.firstColumn.resize(size_t(ch) * b);
        for (int64_t r = 0; r < ch; ++r) std::memcpy(own.firstColumn.data() + size_t(r) * b, raw + size_t(r * w) * b, b);
        keep(key(type, column0, row0), own);
    }
    if (w > cw) {  // the column past the block: the first column of the block to its right
        const Edges right = edgesOf(type, bytes, column0 + blockColumns_, row0, read);
        for (int64_t r = 0; r < ch; ++r)
            std::memcpy(raw + size_t(r * w + cw) * b, right.firstColumn.data() + size_t(r) * b, b);
    }
    if (h > ch) {  // the row past the block: the first row of the block below it
        const Edges below = edgesOf(type, bytes, column0, row0 + blockRows_, read);
        std::memcpy(raw + size_t(ch * w) * b, below.firstRow.data(), size_t(cw) * b);
        if (w > cw) {
            const Edges corner = edgesOf(type, bytes, column0 + blockColumns_, row0 + blockRows_, read);
            std::memcpy(raw + size_t(ch * w + cw) * b, corner.firstRow.data(), b);
        }
    }
}

}  // namespace terracast
