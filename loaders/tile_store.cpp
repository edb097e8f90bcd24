// The store's layout: a header of whole 4 KiB pages (a line naming the format, a line holding the raster's key, a
// line giving the layout and what a vertex holds, zeros to the page's end), then one record per tile of the
// layout at a fixed stride: the tile's heights row-major (zero-padded to 8 bytes), its validity bits (64 per
// word, vertex k at bit k % 64 of word k / 64), and a checksum of both. A record never written reads as zeros,
// whose checksum is never zero: it is missing, not wrong.
#include "loaders/tile_store.h"

#include "loaders/loader_support.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/uio.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

namespace terracast {
namespace {

namespace fs = std::filesystem;

// Raise whenever the layout above changes, so that older stores are made again.
constexpr char kFormatLine[] = "terracast tile store 1\n";
constexpr int64_t kPage = 4096;

int64_t roundUp(int64_t n, int64_t to) { return (n + to - 1) / to * to; }

// Bytes of a record's tail (padding after the heights, validity words, checksum) for w x h vertices.
int64_t heightsBytes(int64_t w, int64_t h, size_t valueBytes) { return w * h * int64_t(valueBytes); }
int64_t tailBytes(int64_t w, int64_t h, size_t valueBytes) {
    const int64_t pad = roundUp(heightsBytes(w, h, valueBytes), 8) - heightsBytes(w, h, valueBytes);
    return pad + (w * h + 63) / 64 * 8 + 8;
}

// A checksum for telling a record written whole from a torn or missing one (not against tampering): four lanes of
// multiply and rotate over 64-bit words, so that it runs at memory speed.
class Checksum {
public:
    // Adds `bytes` bytes; all but the last call must add a multiple of 32.
    void add(const unsigned char* p, size_t bytes) {
        size_t k = 0;
        for (; k + 32 <= bytes; k += 32) {
            uint64_t w[4];
            std::memcpy(w, p + k, 32);
            for (int l = 0; l < 4; ++l) lane_[l] = std::rotl((lane_[l] ^ w[l]) * kMul, 31);
        }
        for (; k < bytes; k += 8) {
            uint64_t w = 0;
            std::memcpy(&w, p + k, std::min<size_t>(8, bytes - k));
            lane_[0] = std::rotl((lane_[0] ^ w) * kMul, 31);
        }
        length_ += bytes;
    }
    uint64_t value() const {
        uint64_t h = length_ * kMul;
        for (const uint64_t l : lane_) {
            h ^= l;
            h = std::rotl(h * kMul, 27) + 0x52dce729u;
        }
        h ^= h >> 33;
        return h | 1u;  // never zero
    }

private:
    static constexpr uint64_t kMul = 0x9e3779b97f4a7c15ull;
    uint64_t lane_[4] = {0x243f6a8885a308d3ull, 0x13198a2e03707344ull, 0xa4093822299f31d0ull, 0x082efa98ec4e6c89ull};
    uint64_t length_ = 0;
};

// The checksum of a record: its heights then its tail up to the checksum itself.
uint64_t recordChecksum(const void* heights, int64_t heightsLength, const std::vector<unsigned char>& tail) {
    Checksum c;
    // The heights' bytes in whole 32-byte steps, the rest with the tail's padding so that the sum does not
    // depend on how the record was split.
    const size_t whole = size_t(heightsLength) / 32 * 32;
    c.add(static_cast<const unsigned char*>(heights), whole);
    thread_local std::vector<unsigned char> rest;  // kept: this runs for every tile read and written
    rest.assign(static_cast<const unsigned char*>(heights) + whole, static_cast<const unsigned char*>(heights) + heightsLength);
    rest.insert(rest.end(), tail.begin(), tail.end() - 8);
    c.add(rest.data(), rest.size());
    return c.value();
}

std::string headerFor(const std::string& key, const TileLayout& layout, TileStore::Values values, int64_t recordBytes) {
    std::string header = kFormatLine;
    header += key + "\n";
    header += fmt::format("layout {} x {} vertices, tiles of {} cells, {} per vertex, records of {} bytes\n",
                          layout.width, layout.height, kTileCells,
                          values == TileStore::Values::WholeMetres ? "int16 metres" : "float32 metres", recordBytes);
    header.resize(size_t(roundUp(int64_t(header.size()) + 1, kPage)), '\0');
    return header;
}

}  // namespace

std::string TileStore::pathFor(const std::string& demPath) { return demPath + ".terracast-tiles"; }

TileStore::TileStore(std::string path, int fd, bool writable, bool fresh, Values values, int64_t dataStart,
                     int64_t recordBytes, int64_t tiles)
    : path_(std::move(path)), fd_(fd), writable_(writable), fresh_(fresh), values_(values), dataStart_(dataStart),
      recordBytes_(recordBytes), tiles_(tiles) {}

TileStore::~TileStore() {
    if (fd_ >= 0) ::close(fd_);
}

std::unique_ptr<TileStore> TileStore::open(const std::string& path, const std::string& key, const TileLayout& layout,
                                           Values values, std::string& why) {
    why.clear();
    if (key.empty() || key.find('\n') != std::string::npos) {
        why = "the raster cannot be named by its files (an in-memory or network source, or a VRT of VRTs)";
        return nullptr;
    }
    const size_t valueBytes = values == Values::WholeMetres ? 2 : 4;
    const int64_t full = kTileCells + 1;
    const int64_t recordBytes = roundUp(heightsBytes(full, full, valueBytes) + tailBytes(full, full, valueBytes), kPage);
    const std::string header = headerFor(key, layout, values, recordBytes);
    const int64_t dataStart = int64_t(header.size());
    const int64_t tiles = layout.tileCount();
    const int64_t total = dataStart + tiles * recordBytes;

    // A store made for this raster as it is now.
    bool writable = true;
    int fd = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd < 0 && (errno == EACCES || errno == EROFS)) {
        writable = false;
        fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    }
    if (fd >= 0) {
        struct stat st {};
        std::string found(header.size(), '\0');
        if (::fstat(fd, &st) == 0 && st.st_size == total &&
            ::pread(fd, found.data(), found.size(), 0) == ssize_t(found.size()) && found == header)
            return std::unique_ptr<TileStore>(
                new TileStore(path, fd, writable, false, values, dataStart, recordBytes, tiles));
        ::close(fd);
    }

    // Else a new one, sparse, renamed over whatever was there.
    std::error_code ec;
    const fs::path target(path);
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const fs::path temporary = loader_support::temporaryPathFor(folder, ".tiles");
    fd = ::open(temporary.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) {
        why = fmt::format("cannot create a file in {} ({})", folder.string(), std::strerror(errno));
        return nullptr;
    }
    const bool made = ::pwrite(fd, header.data(), header.size(), 0) == ssize_t(header.size()) &&
                      ::ftruncate(fd, off_t(total)) == 0 && ::rename(temporary.c_str(), target.c_str()) == 0;
    if (!made) {
        why = fmt::format("cannot write {} ({})", path, std::strerror(errno));
        ::close(fd);
        fs::remove(temporary, ec);
        return nullptr;
    }
    return std::unique_ptr<TileStore>(new TileStore(path, fd, true, true, values, dataStart, recordBytes, tiles));
}

int64_t TileStore::diskBytes() const {
    struct stat st {};
    return ::fstat(fd_, &st) == 0 ? int64_t(st.st_blocks) * 512 : 0;
}

bool TileStore::read(int64_t tile, int64_t w, int64_t h, void* heights, uint8_t* valid) const {
    if (tile < 0 || tile >= tiles_ || w < 1 || h < 1 || w > kTileCells + 1 || h > kTileCells + 1) return false;
    const int64_t length = heightsBytes(w, h, valueBytes());
    thread_local std::vector<unsigned char> tail;
    tail.resize(size_t(tailBytes(w, h, valueBytes())));
    iovec parts[2] = {{heights, size_t(length)}, {tail.data(), tail.size()}};
    const ssize_t want = ssize_t(length) + ssize_t(tail.size());
    if (::preadv(fd_, parts, 2, off_t(dataStart_ + tile * recordBytes_)) != want) return false;
    uint64_t stored = 0;
    std::memcpy(&stored, tail.data() + tail.size() - 8, 8);
    if (stored != recordChecksum(heights, length, tail)) return false;
    const unsigned char* bits = tail.data() + (roundUp(length, 8) - length);
    const int64_t n = w * h;
    for (int64_t k0 = 0; k0 < n; k0 += 64) {
        uint64_t word = 0;
        std::memcpy(&word, bits + k0 / 8, 8);
        const int64_t k1 = std::min(n, k0 + 64);
        if (word == ~uint64_t{0} && k1 - k0 == 64) {
            std::memset(valid + k0, 1, 64);  // the common case: 64 valid vertices
        } else {
            for (int64_t k = k0; k < k1; ++k) valid[k] = uint8_t((word >> (k - k0)) & 1u);
        }
    }
    reads_.fetch_add(1, std::memory_order_relaxed);
    return true;
}

void TileStore::write(int64_t tile, int64_t w, int64_t h, const void* heights, const uint8_t* valid) const {
    if (!writable_.load(std::memory_order_relaxed) || tile < 0 || tile >= tiles_ || w < 1 || h < 1 ||
        w > kTileCells + 1 || h > kTileCells + 1)
        return;
    const int64_t length = heightsBytes(w, h, valueBytes());
    thread_local std::vector<unsigned char> tail;
    tail.assign(size_t(tailBytes(w, h, valueBytes())), 0);
    unsigned char* bits = tail.data() + (roundUp(length, 8) - length);
    for (int64_t k = 0; k < w * h; ++k)
        if (valid == nullptr || valid[k] != 0) bits[k >> 3] = static_cast<unsigned char>(bits[k >> 3] | (1u << (k & 7)));
    const uint64_t sum = recordChecksum(heights, length, tail);
    std::memcpy(tail.data() + tail.size() - 8, &sum, 8);
    iovec parts[2] = {{const_cast<void*>(heights), size_t(length)}, {tail.data(), tail.size()}};
    const ssize_t want = ssize_t(length) + ssize_t(tail.size());
    if (::pwritev(fd_, parts, 2, off_t(dataStart_ + tile * recordBytes_)) != want) {
        writable_.store(false, std::memory_order_relaxed);
        return;
    }
    writes_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace terracast
