#include "heightfield/height_grid.h"

#include "heightfield/grid_summary.h"
#include "heightfield/height_tile.h"
#include "heightfield/large_buffer.h"
#include "heightfield/pyramid_build.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace terracast {

namespace {

// Runs f(first, last) over [0, n) split into contiguous ranges, one per array-pass thread; in the calling thread
// alone when the work (n * workPerItem, in rough element visits) is too small to pay for starting threads.
// f must not throw.
template <typename F>
void parallelRanges(int64_t n, int64_t workPerItem, F&& f) {
    // Threads only for work worth them (a tile's small pyramid levels come here thousands of times).
    if (n * workPerItem < (int64_t(1) << 20)) {
        f(int64_t(0), n);
        return;
    }
    runInSlices(n, std::min<int64_t>(n, arrayPassThreads()), f);
}

// One bit per flag, word by word in parallel (each word is written by one thread).
std::vector<uint64_t> packFlags(const std::vector<uint8_t>& flags) {
    const int64_t n = int64_t(flags.size());
    std::vector<uint64_t> bits(size_t((n + 63) / 64), 0);
    parallelRanges(int64_t(bits.size()), 64, [&](int64_t w0, int64_t w1) {
        for (int64_t w = w0; w < w1; ++w) {
            uint64_t word = 0;
            const int64_t k0 = w * 64, k1 = std::min(k0 + 64, n);
            for (int64_t k = k0; k < k1; ++k) word |= uint64_t(flags[size_t(k)] != 0) << (k - k0);
            bits[size_t(w)] = word;
        }
    });
    return bits;
}

// Bits p .. p + 63 of `bits` as one word (bit p lowest), zeros past the end.
uint64_t bitsFrom(const std::vector<uint64_t>& bits, int64_t p) {
    const size_t w = size_t(p) >> 6;
    const int s = int(p & 63);
    uint64_t word = bits[w] >> s;
    if (s != 0 && w + 1 < bits.size()) word |= bits[w + 1] << (64 - s);
    return word;
}

constexpr int32_t kLowestCode = std::numeric_limits<int16_t>::min();
constexpr int32_t kHighestCode = std::numeric_limits<int16_t>::max();

}  // namespace

// Checks the vertex counts and cell sizes, and derives the reciprocals rays use.
void HeightGrid::setLattice() {
    if (width_ < 2 || height_ < 2)
        throw GridError("a height grid needs at least 2 x 2 vertices (one cell), got " + std::to_string(width_) +
                        " x " + std::to_string(height_));
    if (!(cellSizeXM_ > 0.0) || !(cellSizeYM_ > 0.0) || !std::isfinite(cellSizeXM_) || !std::isfinite(cellSizeYM_))
        throw GridError("cell sizes must be positive and finite, got " + std::to_string(cellSizeXM_) + " x " +
                        std::to_string(cellSizeYM_) + " m");
    cellsPerMetreX_ = 1.0 / cellSizeXM_;
    cellsPerMetreY_ = 1.0 / cellSizeYM_;
}

HeightGrid::HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM,
                       std::vector<float> heightsM, std::vector<uint8_t> valid, StoragePolicy policy, double scaleHint)
    : width_(width), height_(height), cellSizeXM_(cellSizeXM), cellSizeYM_(cellSizeYM), policy_(policy),
      scaleHint_(scaleHint), heightsM_(std::move(heightsM)) {
    setLattice();
    const auto n = static_cast<size_t>(width_) * static_cast<size_t>(height_);
    if (heightsM_.size() != n)
        throw GridError("expected " + std::to_string(n) + " heights, got " + std::to_string(heightsM_.size()));
    if (!valid.empty() && valid.size() != n)
        throw GridError("expected " + std::to_string(n) + " validity flags, got " + std::to_string(valid.size()));
    if (std::find(valid.begin(), valid.end(), uint8_t(0)) != valid.end()) {
        // Pack the flags eight to a byte; the byte-per-vertex input is released right away.
        valid_ = packFlags(valid);
    }
    std::vector<uint8_t>().swap(valid);
    finish();
}

HeightGrid::HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM, std::vector<int16_t> codes,
                       int32_t codeOffset, double codeScale, double scaleHint, std::vector<uint8_t> valid)
    : width_(width), height_(height), cellSizeXM_(cellSizeXM), cellSizeYM_(cellSizeYM), storage_(HeightStorage::Int16),
      policy_(StoragePolicy::Auto), scaleHint_(scaleHint), codes_(std::move(codes)), codeOffset_(codeOffset),
      codeScale_(codeScale) {
    setLattice();
    const auto n = static_cast<size_t>(width_) * static_cast<size_t>(height_);
    if (codes_.size() != n)
        throw GridError("expected " + std::to_string(n) + " heights, got " + std::to_string(codes_.size()));
    if (!(codeScale > 0.0) || !std::isfinite(codeScale)) throw GridError("height codes need a positive, finite scale");
    if (!valid.empty() && valid.size() != n)
        throw GridError("expected " + std::to_string(n) + " validity flags, got " + std::to_string(valid.size()));
    const bool holes = std::find(valid.begin(), valid.end(), uint8_t(0)) != valid.end();
    if (holes) valid_ = packFlags(valid);
    std::vector<uint8_t>().swap(valid);
    // Which of the 65536 codes occur at valid vertices: the height range, and the only heights a re-basing must
    // carry over.
    std::vector<uint8_t> occurs(65536, 0);
    {
        std::mutex merge;
        parallelRanges(int64_t(n), 1, [&](int64_t k0, int64_t k1) {
            std::vector<uint8_t> mine(65536, 0);
            for (int64_t k = k0; k < k1; ++k)
                if (!holes || bit(valid_, k)) mine[size_t(int32_t(codes_[size_t(k)]) - kLowestCode)] = 1;
            const std::lock_guard<std::mutex> lock(merge);
            for (size_t c = 0; c < mine.size(); ++c) occurs[c] |= mine[c];
        });
    }
    int32_t lowCode = kHighestCode, highCode = kLowestCode;
    for (int32_t c = kLowestCode; c <= kHighestCode; ++c)
        if (occurs[size_t(c - kLowestCode)]) {
            lowCode = std::min(lowCode, c);
            highCode = std::max(highCode, c);
        }
    // As the float constructor: with no valid vertex the range is 0 m.
    minHeightM_ = lowCode <= highCode ? decodeHeightCode(lowCode, codeOffset_, codeScale_) : 0.0f;
    maxHeightM_ = lowCode <= highCode ? decodeHeightCode(highCode, codeOffset_, codeScale_) : 0.0f;
    if (!std::isfinite(minHeightM_) || !std::isfinite(maxHeightM_))
        throw GridError("heights decoded from the codes are not finite");
    nodataVertices_ = 0;
    if (holes) {
        nodataVertices_ = int64_t(n);
        for (const uint64_t word : valid_) nodataVertices_ -= std::popcount(word);
    }
    countValidCells();
    // The float constructor's choice (chooseStorage, tryInt16), made on the codes that occur: a table from each
    // code to the code the chosen offset and scale give its height.
    bool chosen = false;
    for (const double s : int16CandidateScales(scaleHint_)) {
        const auto offset = int16CodeOffset(minHeightM_, maxHeightM_, s);
        if (!offset) continue;
        std::vector<int16_t> table(65536, 0);
        bool lossless = true;
        for (int32_t c = lowCode; c <= highCode && lossless; ++c) {
            if (!occurs[size_t(c - kLowestCode)]) continue;
            const auto code = int16Code(decodeHeightCode(c, codeOffset_, codeScale_), s, *offset);
            if (code) table[size_t(c - kLowestCode)] = *code;
            lossless = code.has_value();
        }
        if (!lossless) continue;
        // A nodata vertex holds what the float constructor stores for its 0 m: that height's code, or the lowest.
        const auto zero = int16Code(0.0f, s, *offset);
        const int16_t hole = int16_t(zero ? *zero : kLowestCode);
        if (holes || s != codeScale_ || *offset != codeOffset_) {
            int16_t* q = codes_.data();
            parallelRanges(int64_t(n), 1, [&](int64_t k0, int64_t k1) {
                for (int64_t k = k0; k < k1; ++k)
                    q[k] = holes && !bit(valid_, k) ? hole : table[size_t(int32_t(q[k]) - kLowestCode)];
            });
        }
        codeOffset_ = *offset;
        codeScale_ = s;
        chosen = true;
        break;
    }
    if (!chosen) {
        // As the float constructor keeps heights no int16 code holds exactly: float32.
        heightsM_ = largeVector<float>(n);
        parallelRanges(int64_t(n), 1, [&](int64_t k0, int64_t k1) {
            for (int64_t k = k0; k < k1; ++k)
                heightsM_[size_t(k)] =
                    holes && !bit(valid_, k) ? 0.0f : decodeHeightCode(codes_[size_t(k)], codeOffset_, codeScale_);
        });
        std::vector<int16_t>().swap(codes_);
        storage_ = HeightStorage::Float32;
        codeOffset_ = 0;
        codeScale_ = 1.0;
    }
    buildPyramid();
}

void HeightGrid::finish() {
    // The height range and the holes, in parallel; the first vertex (in row order) whose height is not finite is
    // the one reported.
    struct Part {
        float lo = std::numeric_limits<float>::infinity();
        float hi = -std::numeric_limits<float>::infinity();
        int64_t holes = 0;
        int64_t bad = -1;
    };
    std::vector<Part> parts;
    std::mutex merge;
    parallelRanges(height_, width_, [&](int64_t j0, int64_t j1) {
        Part p;
        for (int64_t j = j0; j < j1 && p.bad < 0; ++j)
            for (int64_t i = 0; i < width_; ++i) {
                if (!vertexValid(i, j)) {
                    ++p.holes;
                    continue;
                }
                const float h = at(i, j);
                if (!std::isfinite(h)) {
                    p.bad = j * width_ + i;
                    break;
                }
                p.lo = std::min(p.lo, h);
                p.hi = std::max(p.hi, h);
            }
        const std::lock_guard<std::mutex> lock(merge);
        parts.push_back(p);
    });
    Part all;
    for (const Part& p : parts) {
        if (p.bad >= 0 && (all.bad < 0 || p.bad < all.bad)) all.bad = p.bad;
        all.lo = std::min(all.lo, p.lo);
        all.hi = std::max(all.hi, p.hi);
        all.holes += p.holes;
    }
    if (all.bad >= 0) {
        const int64_t i = all.bad % width_, j = all.bad / width_;
        throw GridError("height at vertex (" + std::to_string(i) + ", " + std::to_string(j) + ") is not finite (" +
                        std::to_string(at(i, j)) + ")");
    }
    nodataVertices_ = all.holes;
    float lo = all.lo, hi = all.hi;
    if (nodataVertices_ == 0) std::vector<uint64_t>().swap(valid_);
    countValidCells();
    // Heights of vertices that belong to no valid cell still bound the box; harmless and conservative.
    if (lo > hi) lo = hi = 0.0f;
    minHeightM_ = lo;
    maxHeightM_ = hi;
    if (policy_ == StoragePolicy::Auto && storage_ == HeightStorage::Float32) chooseStorage();
    buildPyramid();
}

void HeightGrid::countValidCells() {
    std::vector<uint64_t>().swap(cellValid_);
    validCells_ = cellsX() * cellsY();
    if (valid_.empty()) return;
    // Cell c = j * cellsX + i is valid when its four corners are: 64 cells at a time, each run of them within one
    // row the AND of four shifted words of vertex bits. Each thread writes whole words of its own.
    const int64_t cells = cellsX() * cellsY();
    cellValid_.assign(size_t((cells + 63) / 64), 0);
    std::atomic<int64_t> count{0};
    parallelRanges(int64_t(cellValid_.size()), 64, [&](int64_t w0, int64_t w1) {
        int64_t mine = 0;
        for (int64_t w = w0; w < w1; ++w) {
            const int64_t c0 = w * 64, c1 = std::min(c0 + 64, cells);
            uint64_t word = 0;
            for (int64_t c = c0; c < c1;) {
                const int64_t j = c / cellsX(), i = c - j * cellsX();
                const int64_t run = std::min(c1 - c, cellsX() - i);
                const int64_t v = j * width_ + i;
                uint64_t ok = bitsFrom(valid_, v) & bitsFrom(valid_, v + 1) & bitsFrom(valid_, v + width_) &
                              bitsFrom(valid_, v + width_ + 1);
                if (run < 64) ok &= (uint64_t(1) << run) - 1;
                word |= ok << (c - c0);
                c += run;
            }
            cellValid_[size_t(w)] = word;
            mine += std::popcount(word);
        }
        count += mine;
    });
    validCells_ = count.load();
}

std::vector<double> int16CandidateScales(double scaleHint) {
    // Whole metres first (SRTM, USGS and most integer DEMs), then the source's own unit if we were told it.
    std::vector<double> scales{1.0};
    if (scaleHint > 0.0 && std::isfinite(scaleHint) && scaleHint != 1.0) scales.push_back(scaleHint);
    return scales;
}

void HeightGrid::chooseStorage() {
    for (const double s : int16CandidateScales(scaleHint_))
        if (tryInt16(s)) return;
}

std::optional<int32_t> int16CodeOffset(float minM, float maxM, double scale) {
    // The lowest valid height gets code -32768, so a range of 65536 codes starts there.
    const double qlo = std::round(double(minM) / scale), qhi = std::round(double(maxM) / scale);
    if (!(qhi - qlo <= 65535.0) || !(std::abs(qlo) < 2.0e9) || !(std::abs(qhi) < 2.0e9)) return std::nullopt;
    return static_cast<int32_t>(int64_t(qlo) - kLowestCode);
}

// Lossless means the same bits: a valid -0 height (which decodes as +0) keeps the grid in float32.
bool int16RoundTrips(float z, double scale) {
    if (!std::isfinite(z)) return false;
    const double r = std::round(double(z) / scale);
    if (!(std::abs(r) < 2.0e9)) return false;
    return std::bit_cast<uint32_t>(float(r * scale)) == std::bit_cast<uint32_t>(z);
}

std::optional<int16_t> int16Code(float z, double scale, int32_t offset) {
    if (!int16RoundTrips(z, scale)) return std::nullopt;
    const int64_t c = int64_t(std::round(double(z) / scale)) - offset;
    if (c < kLowestCode || c > std::numeric_limits<int16_t>::max()) return std::nullopt;
    return int16_t(c);
}

bool HeightGrid::tryInt16(double s) {
    const auto codeOffset = int16CodeOffset(minHeightM_, maxHeightM_, s);
    if (!codeOffset) return false;
    const int32_t offset = *codeOffset;
    const auto n = static_cast<size_t>(width_ * height_);
    std::atomic<bool> lossless{true};
    const float* h = heightsM_.data();
    // The code for height z, or false when no code in range decodes to exactly z's bits.
    auto encode = [&](float z, int32_t& code) {
        const auto c = int16Code(z, s, offset);
        if (c) code = *c;
        return c.has_value();
    };
    // First only check (stopping at the first valid height that does not round-trip, so float data costs
    // little), then encode.
    parallelRanges(height_, width_, [&](int64_t j0, int64_t j1) {
        for (int64_t j = j0; j < j1 && lossless.load(std::memory_order_relaxed); ++j)
            for (int64_t i = 0; i < width_; ++i) {
                int32_t code = 0;
                if (!encode(h[j * width_ + i], code) && vertexValid(i, j)) {
                    lossless.store(false, std::memory_order_relaxed);
                    return;
                }
            }
    });
    if (!lossless.load()) return false;
    std::vector<int16_t> codes = largeVector<int16_t>(n);
    parallelRanges(int64_t(n), 1, [&](int64_t k0, int64_t k1) {
        for (int64_t k = k0; k < k1; ++k) {
            int32_t code = kLowestCode;
            // A nodata vertex whose value has no code gets the lowest: its value is never used.
            codes[size_t(k)] = int16_t(encode(h[k], code) ? code : kLowestCode);
        }
    });
    codes_ = std::move(codes);
    codeOffset_ = offset;
    codeScale_ = s;
    storage_ = HeightStorage::Int16;
    std::vector<float>().swap(heightsM_);
    return true;
}

HeightGrid HeightGrid::transformed(const HeightTransform& t) const {
    if (tiles_) {
        GridSummary summary;
        std::shared_ptr<const TileSource> source = tiles_->transformed(t, summary);
        if (!source) throw GridError("this tiled grid's source cannot make a transformed copy of its heights");
        return HeightGrid(summary, cellSizeXM_, cellSizeYM_, std::move(source));
    }
    // The heights transformed straight from the storage, row bands in parallel; which vertices and cells are
    // valid carries over.
    std::vector<float> z = largeVector<float>(size_t(width_ * height_));
    parallelRanges(height_, width_, [&](int64_t j0, int64_t j1) {
        for (int64_t j = j0; j < j1; ++j)
            for (int64_t i = 0; i < width_; ++i) {
                z[static_cast<size_t>(j * width_ + i)] = t.apply(at(i, j), i, j, cellSizeXM_, cellSizeYM_);
            }
    });
    return HeightGrid(*this, std::move(z));
}

HeightGrid::HeightGrid(const HeightGrid& lattice, std::vector<float> heightsM)
    : width_(lattice.width_), height_(lattice.height_), cellSizeXM_(lattice.cellSizeXM_),
      cellSizeYM_(lattice.cellSizeYM_), heightsM_(std::move(heightsM)), valid_(lattice.valid_) {
    setLattice();
    finish();
}

std::vector<float> HeightGrid::copyHeights() const {
    if (tiles_)
        throw GridError("this needs the whole DEM in memory, and it is held as tiles (it does not fit in "
                        "--max-memory, or --tile-cache asked for tiles)");
    if (storage_ == HeightStorage::Float32) return heightsM_;
    std::vector<float> out = largeVector<float>(codes_.size());
    parallelRanges(int64_t(codes_.size()), 1, [&](int64_t k0, int64_t k1) {
        for (int64_t k = k0; k < k1; ++k) out[size_t(k)] = decode(codes_[size_t(k)]);
    });
    return out;
}

void HeightGrid::buildPyramid() {
    const auto start = std::chrono::steady_clock::now();

    const PyramidCoding coding = PyramidCoding::forHeights(storage_ == HeightStorage::Int16, codeOffset_, codeScale_,
                                                           minHeightM_, maxHeightM_);
    pyramidOffset_ = coding.offset;
    pyramidScale_ = coding.scale;
    pyramidCodesPerMetre_ = coding.codesPerMetre;

    // The levels are made where they are kept (the layout storePyramid gives), so that building them holds no
    // more than the pyramid itself: level 1's maxima straight from the vertices (pyramid_build.h), its minima
    // two block rows at a time, each pair reduced at once to a row of level 2's minima (the minimum pyramid
    // keeps no level 1), then each level above from the one below.
    const int levels = pyramidLevelCount(cellsX(), cellsY());
    levelStart_.clear();
    levelBlocksX_.clear();
    levelStart_.reserve(size_t(levels));
    levelBlocksX_.reserve(size_t(levels));
    int64_t total = 0;
    for (int k = 1; k <= levels; ++k) {
        levelStart_.push_back(total);
        levelBlocksX_.push_back(pyramidBlocksX(k));
        total += pyramidBlocksX(k) * pyramidBlocksY(k);
    }
    const int64_t minStart = levels >= 2 ? levelStart_[1] : total;
    pyramidCodes_ = largeVector<int16_t>(static_cast<size_t>(total));
    pyramidMinCodes_ = largeVector<int16_t>(static_cast<size_t>(total - minStart));
    const int64_t bx1 = pyramidBlocksX(1), by1 = pyramidBlocksY(1);
    const int64_t by2 = levels >= 2 ? pyramidBlocksY(2) : by1;
    const int64_t rowsPerItem = levels >= 2 ? 2 : 1;
    auto levelOne = [&](auto get, auto none, auto highCode, auto lowCode) {
        parallelRanges(by2, 3 * rowsPerItem * width_, [&](int64_t r0, int64_t r1) {
            std::vector<int16_t> lows(static_cast<size_t>(2 * bx1));
            for (int64_t r = r0; r < r1; ++r) {
                const int64_t b0 = r * rowsPerItem, b1 = std::min(b0 + rowsPerItem, by1);
                pyramidLevelOneRows(width_, cellsX(), cellsY(), valid_, b0, b1, get, none.first, none.second,
                                    highCode, lowCode, pyramidCodes_.data() + b0 * bx1, lows.data());
                if (levels >= 2)
                    pyramidParentLevel(lows.data(), bx1, b1 - b0, false,
                                       pyramidMinCodes_.data() + r * levelBlocksX_[1]);
            }
        });
    };
    if (storage_ == HeightStorage::Int16) {
        const int16_t* codes = codes_.data();
        auto same = [](int16_t q) { return q; };
        levelOne([codes](int64_t k) { return codes[k]; }, std::pair<int16_t, int16_t>(kLowestCode, kHighestCode), same,
                 same);
    } else {
        const float* h = heightsM_.data();
        constexpr float kInf = std::numeric_limits<float>::infinity();
        levelOne([h](int64_t k) { return h[k]; }, std::pair<float, float>(-kInf, kInf),
                 [&](float z) { return z == -kInf ? PyramidCoding::kNoMax : coding.encodeUp(z); },
                 [&](float z) { return z == kInf ? PyramidCoding::kNoMin : coding.encodeDown(z); });
    }
    for (int k = 2; k <= levels; ++k) {
        const int64_t px = pyramidBlocksX(k - 1), py = pyramidBlocksY(k - 1);
        pyramidParentLevel(pyramidCodes_.data() + levelStart_[size_t(k - 2)], px, py, true,
                           pyramidCodes_.data() + levelStart_[size_t(k - 1)]);
        if (k >= 3)
            pyramidParentLevel(pyramidMinCodes_.data() + (levelStart_[size_t(k - 2)] - minStart), px, py, false,
                               pyramidMinCodes_.data() + (levelStart_[size_t(k - 1)] - minStart));
    }
    const auto end = std::chrono::steady_clock::now();
    pyramidBuildSeconds_ = std::chrono::duration<double>(end - start).count();
    buildSeconds_ = std::chrono::duration<double>(end - constructed_).count();
}

// One array for all levels, so the traversal finds a level's blocks from two small tables; the minimum pyramid
// keeps levels 2..n only, indexed like the maximum pyramid from level 2's start. highs[k] and lows[k] are level
// first + k, for levels first..levels; a tiled grid stores the levels above its tiles' (first > 1), and the levels below get no blocks.
void HeightGrid::storePyramid(std::vector<std::vector<int16_t>>& highs, std::vector<std::vector<int16_t>>& lows,
                              int first, int levels) {
    pyramidCodes_.clear();
    pyramidMinCodes_.clear();
    levelStart_.clear();
    levelBlocksX_.clear();
    int64_t total = 0, minTotal = 0;
    for (int k = first; k <= levels; ++k) {
        total += int64_t(highs[size_t(k - first)].size());
        if (k >= 2) minTotal += int64_t(lows[size_t(k - first)].size());
    }
    pyramidCodes_.reserve(size_t(total));
    pyramidMinCodes_.reserve(size_t(minTotal));
    levelStart_.reserve(size_t(levels));
    levelBlocksX_.reserve(size_t(levels));
    for (int k = 1; k <= levels; ++k) {
        levelStart_.push_back(int64_t(pyramidCodes_.size()));
        levelBlocksX_.push_back(pyramidBlocksX(k));
        if (k < first) continue;
        auto& high = highs[size_t(k - first)];
        auto& low = lows[size_t(k - first)];
        pyramidCodes_.insert(pyramidCodes_.end(), high.begin(), high.end());
        if (k >= 2) pyramidMinCodes_.insert(pyramidMinCodes_.end(), low.begin(), low.end());
        std::vector<int16_t>().swap(high);
        std::vector<int16_t>().swap(low);
    }
}

HeightGrid::HeightGrid(const GridSummary& summary, double cellSizeXM, double cellSizeYM,
                       std::shared_ptr<const TileSource> tiles)
    : width_(summary.width), height_(summary.height), cellSizeXM_(cellSizeXM), cellSizeYM_(cellSizeYM),
      storage_(summary.storage), codeOffset_(summary.codeOffset), codeScale_(summary.codeScale),
      nodataVertices_(summary.nodataVertices), validCells_(summary.validCells), minHeightM_(summary.minHeightM),
      maxHeightM_(summary.maxHeightM), tiles_(std::move(tiles)) {
    setLattice();
    if (!tiles_) throw GridError("a tiled grid needs a tile source");
    pyramidOffset_ = summary.pyramid.offset;
    pyramidScale_ = summary.pyramid.scale;
    pyramidCodesPerMetre_ = summary.pyramid.codesPerMetre;
    const int levels = pyramidLevelCount(cellsX(), cellsY());
    tileLevels_ = std::min(levels, kTileLevels);
    std::vector<std::vector<int16_t>> highs, lows;
    if (levels > kTileLevels) {
        // The level whose blocks are the tiles, from the summary; those above, from it.
        const TileLayout layout{width_, height_};
        if (summary.tileMaxCodes.size() != size_t(layout.tileCount()) ||
            summary.tileMinCodes.size() != size_t(layout.tileCount()))
            throw GridError("a tiled grid's summary holds no bounds for its tiles");
        highs.push_back(summary.tileMaxCodes);
        lows.push_back(summary.tileMinCodes);
        int64_t bx = layout.tilesX(), by = layout.tilesY();
        while (bx > 1 || by > 1) {
            highs.push_back(pyramidParentLevel(highs.back(), bx, by, true));
            lows.push_back(pyramidParentLevel(lows.back(), bx, by, false));
            bx = (bx + 1) / 2;
            by = (by + 1) / 2;
        }
    }
    storePyramid(highs, lows, kTileLevels + 1, levels);
    if (pyramidLevels() != levels) throw GridError("a tiled grid's pyramid has the wrong number of levels");
}

// A tile holding vertex (i, j): the one of the cell it is the lower corner of, or of the last cell.
TileSource::TileSource() {
    static std::atomic<uint64_t> next{1};
    serial_ = next++;
}

// Every read of a tiled grid (single values, and the walks' readers through tileOfCell) mostly stays in a few
// neighbouring tiles: a per-thread memo of four tiles, one for each parity of the tile's column and row, spares
// them the source's lookup and the shared pointer's reference counting; a walk along a tile border, or a run of
// walks from one tile that end in its neighbours, asks the source only when it first meets a tile. It holds
// those four tiles per thread beyond the cache's budget.
const HeightTile& HeightGrid::memoTile(int64_t ti, int64_t tj) const {
    struct Memo {
        uint64_t source = 0;
        int64_t ti = -1, tj = -1;
        std::shared_ptr<const HeightTile> tile;
    };
    thread_local std::array<Memo, 4> memos;
    Memo& memo = memos[size_t((ti & 1) | ((tj & 1) << 1))];
    const uint64_t source = tiles_->serial();
    if (memo.source != source || memo.ti != ti || memo.tj != tj) {
        memo.tile = tiles_->tile(ti, tj);
        memo.source = source;
        memo.ti = ti;
        memo.tj = tj;
    }
    return *memo.tile;
}

const HeightTile& HeightGrid::tileOfCell(int64_t i, int64_t j) const { return memoTile(i / kTileCells, j / kTileCells); }

const HeightTile& HeightGrid::vertexTile(int64_t i, int64_t j) const {
    return memoTile(std::min(i, cellsX() - 1) / kTileCells, std::min(j, cellsY() - 1) / kTileCells);
}

float HeightGrid::tiledAt(int64_t i, int64_t j) const { return vertexTile(i, j).at(i, j); }

bool HeightGrid::tiledVertexValid(int64_t i, int64_t j) const { return vertexTile(i, j).vertexValid(i, j); }

bool HeightGrid::tiledCellValid(int64_t i, int64_t j) const { return memoTile(i / kTileCells, j / kTileCells).cellValid(i, j); }

double HeightGrid::blockMaxM(int k, int64_t bi, int64_t bj) const {
    const PyramidView view = pyramidView();
    if (tiles_ && k <= tileLevels_)
        return view.decode(memoTile((bi << k) / kTileCells, (bj << k) / kTileCells).maxCode(k, bi, bj));
    return view.blockMaxM(k, bi, bj);
}

double HeightGrid::blockMinM(int k, int64_t bi, int64_t bj) const {
    if (k < 2) return -std::numeric_limits<double>::infinity();
    const PyramidView view = pyramidView();
    if (tiles_ && k <= tileLevels_)
        return view.decode(memoTile((bi << k) / kTileCells, (bj << k) / kTileCells).minCode(k, bi, bj));
    return view.blockMinM(k, bi, bj);
}

void HeightGrid::scaleHeights(float k) {
    if (tiles_)
        throw GridError("vertical exaggeration needs the whole DEM in memory, and it is held as tiles (it does not "
                        "fit in --max-memory, or --tile-cache asked for tiles)");
    if (!std::isfinite(k) || k <= 0.0f)
        throw GridError("vertical exaggeration must be positive and finite, got " + std::to_string(k));
    // Scale in float exactly as a Float32 grid would, then let the storage be chosen again; the scaled source
    // unit is the natural candidate scale.
    if (storage_ == HeightStorage::Int16) {
        heightsM_ = copyHeights();
        scaleHint_ = codeScale_;
        std::vector<int16_t>().swap(codes_);
        storage_ = HeightStorage::Float32;
        codeOffset_ = 0;
        codeScale_ = 1.0;
    }
    scaleHint_ *= double(k);
    for (float& h : heightsM_) h *= k;
    finish();
}

size_t HeightGrid::memoryBytes() const {
    const size_t tileCache = tiles_ ? tiles_->cacheBudgetBytes() : 0;
    const size_t pyramid = (pyramidCodes_.capacity() + pyramidMinCodes_.capacity()) * sizeof(int16_t) +
                           (levelStart_.capacity() + levelBlocksX_.capacity()) * sizeof(int64_t);
    return heightsM_.capacity() * sizeof(float) + codes_.capacity() * sizeof(int16_t) +
           (valid_.capacity() + cellValid_.capacity()) * sizeof(uint64_t) + pyramid + tileCache;
}

PyramidCoding PyramidCoding::forHeights(bool int16Storage, int32_t codeOffset, double codeScale, float minM,
                                        float maxM) {
    PyramidCoding c;
    if (int16Storage) {
        c.offset = codeOffset;
        c.scale = codeScale;
    } else {
        // A scale small enough in relative terms that the integer offset fits an int32; a height is rounded to
        // the first code not below it (above it, for the minimum pyramid).
        const double lo = minM, hi = maxM;
        double s = std::max((hi - lo) / 65000.0, std::max(std::abs(lo), std::abs(hi)) * 0x1p-30);
        if (!(s > 0.0) || !std::isfinite(s)) s = 1.0;
        c.scale = s;
        c.offset = static_cast<int32_t>(int64_t(std::floor(lo / s)) + 32766);  // lo lands near -32766
    }
    c.codesPerMetre = 1.0 / c.scale;
    return c;
}

int16_t PyramidCoding::encodeUp(float z) const {
    auto value = [&](int32_t q) { return float(double(q + offset) * scale); };
    // Only a first guess: the loops settle the code.
    const double guess = std::ceil(double(z) * codesPerMetre) - double(offset);
    auto q = static_cast<int32_t>(std::clamp(guess, double(kLowestCode + 1), double(kHighestCode)));
    while (q < kHighestCode && value(q) < z) ++q;
    while (q > kLowestCode + 1 && value(q - 1) >= z) --q;
    return int16_t(q);
}

int16_t PyramidCoding::encodeDown(float z) const {
    auto value = [&](int32_t q) { return float(double(q + offset) * scale); };
    const double guess = std::floor(double(z) * codesPerMetre) - double(offset);
    auto q = static_cast<int32_t>(std::clamp(guess, double(kLowestCode), double(kHighestCode - 1)));
    while (q > kLowestCode && value(q) > z) --q;
    while (q < kHighestCode - 1 && value(q + 1) <= z) ++q;
    return int16_t(q);
}

void pyramidParentLevel(const int16_t* level, int64_t px, int64_t py, bool highest, int16_t* next) {
    const int64_t bx = (px + 1) / 2, by = (py + 1) / 2;
    // Codes order as heights do, so the extreme code is the bound. Every block has at least one child; a last
    // row (column) without a partner is paired with itself, which leaves its extremes unchanged.
    auto reduce = [&](auto pick) {
        // Each block row: the extremes of its two child rows, column by column, then of adjacent columns (loops
        // over contiguous values that the compiler vectorises).
        parallelRanges(by, 4 * bx, [&](int64_t b0, int64_t b1) {
            std::vector<int16_t> columns(static_cast<size_t>(2 * bx));
            for (int64_t bj = b0; bj < b1; ++bj) {
                const int16_t* r0 = level + 2 * bj * px;
                const int16_t* r1 = 2 * bj + 1 < py ? r0 + px : r0;
                for (int64_t i = 0; i < px; ++i) columns[size_t(i)] = pick(r0[i], r1[i]);
                if (px % 2 != 0) columns[size_t(px)] = columns[size_t(px - 1)];
                pairExtremes(columns.data(), bx, highest, next + bj * bx);
            }
        });
    };
    if (highest)
        reduce([](int16_t a, int16_t b) { return std::max(a, b); });
    else
        reduce([](int16_t a, int16_t b) { return std::min(a, b); });
}

std::vector<int16_t> pyramidParentLevel(const std::vector<int16_t>& level, int64_t px, int64_t py, bool highest) {
    std::vector<int16_t> next = largeVector<int16_t>(static_cast<size_t>(((px + 1) / 2) * ((py + 1) / 2)));
    pyramidParentLevel(level.data(), px, py, highest, next.data());
    return next;
}

int pyramidLevelCount(int64_t cellsX, int64_t cellsY) {
    int levels = 1;
    while (((cellsX + (int64_t(1) << levels) - 1) >> levels) > 1 || ((cellsY + (int64_t(1) << levels) - 1) >> levels) > 1)
        ++levels;
    return levels;
}

}  // namespace terracast
