// The first raster row and column of a source's storage blocks, kept as the blocks are read
// (docs/architecture.md, "Tiled grids"). A tile's window is a block and one more row and column, the first of
// three other blocks; GDAL decodes a compressed block whole, so reading those again costs two to three times
// the block's own decoding. Kept, they fill the window's last row and column instead.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <unordered_map>
#include <vector>

namespace terracast {

class BlockEdges {
public:
    // Reads raster window (column0, row0), w x h samples, into `raw`, its rows `stride` samples apart.
    using ReadWindow =
        std::function<void(int64_t column0, int64_t row0, int64_t w, int64_t h, unsigned char* raw, int64_t stride)>;

    // For a raster of width x height samples stored in blocks of blockColumns x blockRows.
    BlockEdges(int64_t width, int64_t height, int64_t blockColumns, int64_t blockRows);

    // Whether read() serves the window: it starts at a block's corner and reaches one row or column (or both)
    // past the block.
    bool serves(int64_t column0, int64_t row0, int64_t w, int64_t h) const;

    // Reads a window that serves() accepts, of `bytes`-byte samples of one type (`type`: edges of different
    // types are kept apart): the block through `read`, its last row and column from the kept edges of the
    // blocks beyond (read through `read`, and kept, when none are). Keeps the block's own edges too. Safe to
    // call from several threads; `read` must be safe for the calling thread. Throws what `read` throws.
    void read(int type, int bytes, int64_t column0, int64_t row0, int64_t w, int64_t h, unsigned char* raw,
              const ReadWindow& read) const;

private:
    struct Edges {
        std::vector<unsigned char> firstRow, firstColumn;
    };
    uint64_t key(int type, int64_t column0, int64_t row0) const;
    Edges edgesOf(int type, int bytes, int64_t column0, int64_t row0, const ReadWindow& read) const;
    void keep(uint64_t key, const Edges& e) const;

    // A bound, not a policy: when full, the kept edges are dropped and kept again as blocks are read.
    static constexpr size_t kBudgetBytes = size_t(16) << 20;

    int64_t width_, height_, blockColumns_, blockRows_;
    mutable std::mutex mutex_;
    mutable std::unordered_map<uint64_t, Edges> edges_;
    mutable size_t bytes_ = 0;
};

}  // namespace terracast
