// A store of decoded tiles beside a DEM held as tiles (docs/architecture.md, "Tiled grids"): each tile's
// heights as the raster reader returns them (16-bit whole metres or float metres) and its validity bits, at a
// fixed offset of one file, so that a later run reads a tile with one read instead of decoding its blocks
// again. Like the summary sidecar it is a cache: named by the raster it was made from (made again when that
// changes), filled as tiles are first read, and never needed: a tile it does not hold, or holds torn (a record
// whose checksum disagrees, as after a crash), is read from the raster instead.
#pragma once

#include "heightfield/height_tile.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace terracast {

class TileStore {
public:
    // What a store holds per vertex.
    enum class Values { WholeMetres, FloatMetres };  // int16 heights in metres; float32 metres

    // The store's path: the DEM's own with ".terracast-tiles" appended.
    static std::string pathFor(const std::string& demPath);

    // Opens the store at `path` made under `key` (the raster's identity: files, sizes, times, decoding) for
    // tiles of `layout`, or makes a new one when the file is missing or was made for something else (through a
    // temporary file and a rename; the new file is sparse and fills as tiles are written). Nothing (and the reason
    // in `why`) when the file can be neither read nor made, as in a read-only folder.
    static std::unique_ptr<TileStore> open(const std::string& path, const std::string& key, const TileLayout& layout,
                                           Values values, std::string& why);
    ~TileStore();
    TileStore(const TileStore&) = delete;
    TileStore& operator=(const TileStore&) = delete;

    Values values() const { return values_; }
    const std::string& path() const { return path_; }
    // Whether the store was made by this open (rather than found).
    bool fresh() const { return fresh_; }

    // Tile `tile` (its vertex count w x h as the layout gives it) into `heights` (int16 or float as values()
    // says, row-major) and `valid` (1 or 0 per vertex). False when the store does not hold it intact.
    bool read(int64_t tile, int64_t w, int64_t h, void* heights, uint8_t* valid) const;
    // Keeps tile `tile`. Best effort: a failed write (a full disk) stops further writes and is not an error.
    void write(int64_t tile, int64_t w, int64_t h, const void* heights, const uint8_t* valid) const;

    // The bytes the store takes on disk now (it fills as tiles are written), and once every tile is written.
    int64_t diskBytes() const;
    int64_t fullBytes() const { return dataStart_ + tiles_ * recordBytes_; }

    int64_t reads() const { return reads_.load(std::memory_order_relaxed); }    // tiles read from the store
    int64_t writes() const { return writes_.load(std::memory_order_relaxed); }  // tiles written to it

private:
    TileStore(std::string path, int fd, bool writable, bool fresh, Values values, int64_t dataStart,
              int64_t recordBytes, int64_t tiles);
    size_t valueBytes() const { return values_ == Values::WholeMetres ? 2 : 4; }

    std::string path_;
    int fd_ = -1;
    mutable std::atomic<bool> writable_;
    bool fresh_ = false;
    Values values_;
    int64_t dataStart_ = 0;
    int64_t recordBytes_ = 0;
    int64_t tiles_ = 0;
    mutable std::atomic<int64_t> reads_{0};
    mutable std::atomic<int64_t> writes_{0};
};

}  // namespace terracast
