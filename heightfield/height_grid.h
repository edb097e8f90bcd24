// The height grid: W x H vertices on a regular metric lattice, with a nodata mask. Heights are kept as float32,
// or as int16 codes with an integer offset and a scale when that reproduces every valid height exactly.
#pragma once

#include "heightfield/tile_cache.h"

#include <glm/glm.hpp>

#include <chrono>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace terracast {

// Thrown for grids that cannot be traced (too small, non-finite heights, inconsistent sizes).
class GridError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The height an int16 code stands for: float(double(code + offset) * scale), rounded to float here whatever the
// caller does with it next. The empty asm makes the float a value the compiler must produce: GCC 12, compiling
// the traversal kernels for AVX2, dropped the float rounding of vectorised decodes whose results went on in
// double (tests/heightfield/kernel_isa_test.cpp, the tenths grid).
inline float decodeHeightCode(int32_t code, int32_t offset, double scale) {
    float z = float(double(code + offset) * scale);
#if defined(__GNUC__) && defined(__x86_64__)
    asm("" : "+x"(z));
#endif
    return z;
}

// The int16 encoding of heights (HeightStorage::Int16), shared by whole grids and by grids read a band at a
// time: the code offset that gives the lowest height of [minM, maxM] the lowest code, or none when the range
// needs more than 65536 codes at `scale` metres per code; and whether height z decodes from its code (the nearest
// multiple of `scale`) to the same bits.
std::optional<int32_t> int16CodeOffset(float minM, float maxM, double scale);
bool int16RoundTrips(float z, double scale);
// The code of height z at `scale` and `offset`, when z round-trips and its code fits int16.
std::optional<int16_t> int16Code(float z, double scale, int32_t offset);
// The scales StoragePolicy::Auto tries, in order, given the source's unit (0 for none).
std::vector<double> int16CandidateScales(double scaleHint);

// The codes of the min/max pyramids (HeightGrid::pyramidView): int16 values decoding to
// float(double(code + offset) * scale). Shared by whole grids, their tiles and streamed summaries, so that each
// bound comes out the same bits whichever built it.
struct PyramidCoding {
    static constexpr int16_t kNoMax = std::numeric_limits<int16_t>::min();  // a block without a valid vertex
    static constexpr int16_t kNoMin = std::numeric_limits<int16_t>::max();
    int32_t offset = 0;
    double scale = 1.0;
    double codesPerMetre = 1.0;  // 1 / scale

    // Int16 heights lend the pyramid their own offset and scale, so a block's code is its highest (lowest)
    // vertex code; float32 heights in [minM, maxM] get a scale spreading the range over most of the codes.
    static PyramidCoding forHeights(bool int16Storage, int32_t codeOffset, double codeScale, float minM, float maxM);
    double decode(int32_t q) const { return double(decodeHeightCode(q, offset, scale)); }
    int16_t encodeUp(float z) const;    // the first code whose value is not below z (never kNoMax)
    int16_t encodeDown(float z) const;  // the last code whose value is not above z (never kNoMin)
};
// The next pyramid level from a level of px x py blocks: each block the highest (`highest`) or lowest code of
// its up to 2 x 2 children (kNoMax or kNoMin when all of them are). The second form writes the
// ceil(px / 2) x ceil(py / 2) blocks to `next`.
std::vector<int16_t> pyramidParentLevel(const std::vector<int16_t>& level, int64_t px, int64_t py, bool highest);
void pyramidParentLevel(const int16_t* level, int64_t px, int64_t py, bool highest, int16_t* next);
// Pyramid levels of a grid of cellsX x cellsY cells: halving until one block covers it (at least 1).
int pyramidLevelCount(int64_t cellsX, int64_t cellsY);

class HeightTile;
struct GridSummary;

// A change of every height, made vertex by vertex in float, for a job that traces a surface derived from the
// terrain: upside down (the negative openness of sky view), or lowered by the earth's curvature (less refraction)
// as seen from an observer (viewshed). HeightGrid::transformed makes the derived grid.
struct HeightTransform {
    bool upsideDown = false;      // z becomes -z
    double curvatureCoeff = 0.0;  // then z loses float(coeff * d^2 / (2 R)), d the horizontal distance from the
    double earthRadiusM = 0.0;    // observer (local metres) to the vertex
    double observerXM = 0.0;
    double observerYM = 0.0;

    bool identity() const { return !upsideDown && curvatureCoeff == 0.0; }
    // Vertex (i, j)'s height z under the transform, on a grid of the given cell sizes.
    float apply(float z, int64_t i, int64_t j, double cellSizeXM, double cellSizeYM) const {
        if (upsideDown) z = -z;
        if (curvatureCoeff != 0.0) {
            const double dx = double(i) * cellSizeXM - observerXM, dy = double(j) * cellSizeYM - observerYM;
            z -= float(curvatureCoeff * (dx * dx + dy * dy) / (2.0 * earthRadiusM));
        }
        return z;
    }
};

// The heights and validity of a coarser grid (heightfield/coarser_grid.h), row-major, as a tile source may keep
// them between runs.
struct CoarseHeights {
    int64_t width = 0;
    int64_t height = 0;
    std::vector<float> heightsM;  // 0 at nodata vertices
    std::vector<uint8_t> valid;   // one flag per vertex
};

// Where a tiled grid's tiles come from (docs/architecture.md, "Tiled grids"): tile (ti, tj) holds cells
// [ti * kTileCells, (ti + 1) * kTileCells) x .. (height_tile.h). Must be safe to call from several threads.
class TileSource {
public:
    TileSource();
    virtual ~TileSource() = default;
    // Unique in the process, never reused: what a memo of a source's tiles is keyed by (an address can be).
    uint64_t serial() const { return serial_; }
    virtual std::shared_ptr<const HeightTile> tile(int64_t ti, int64_t tj) const = 0;
    // What the source's cache holds and did so far, and the bytes it may hold.
    virtual TileCacheStats cacheStats() const = 0;
    virtual size_t cacheBudgetBytes() const = 0;
    // The same heights under `t`, as a source of its own with a cache as large, its summary written to
    // `summary`; nullptr when this source cannot make one.
    virtual std::shared_ptr<const TileSource> transformed(const HeightTransform&, GridSummary&) const {
        return nullptr;
    }
    // The grid `levels` steps coarser (`width` x `height` vertices) as kept from an earlier run (a sidecar beside
    // the DEM), when this source keeps one that describes its heights as they are now; and the offer of one just
    // made, to keep. A source that keeps nothing answers nothing and ignores the offer.
    virtual std::optional<CoarseHeights> keptCoarseHeights(int /*levels*/, int64_t /*width*/, int64_t /*height*/) const {
        return std::nullopt;
    }
    virtual void keepCoarseHeights(int /*levels*/, const CoarseHeights& /*heights*/) const {}

private:
    uint64_t serial_;
};

// How the heights are held in memory.
enum class HeightStorage {
    Float32,  // 4 bytes per vertex, the heights as given
    Int16,    // 2 bytes per vertex: height = float(double(int32_t(code) + codeOffset()) * codeScale())
};

// What the constructor may choose.
enum class StoragePolicy {
    Auto,     // int16 codes when every valid height round-trips bit for bit, float32 otherwise
    Float32,  // always float32
};

// Vertex (i, j) sits at local position (i * cellSizeXM, j * cellSizeYM, height(i, j)); j grows northward.
// Cell (i, j) spans vertices i..i+1 and j..j+1. A cell touching a nodata vertex is a hole.
class HeightGrid {
public:
    HeightGrid() = default;

    // Builds a grid from row-major heights (row j = southmost first). `valid` is empty (every vertex valid)
    // or holds one flag per vertex. Throws GridError on a size mismatch, fewer than 2 x 2 vertices,
    // non-positive cell sizes or a non-finite height at a valid vertex.
    // With StoragePolicy::Auto the heights are stored as int16 codes when that is lossless, trying a scale of
    // 1 m per code first and then `scaleHint` (metres per stored unit of the source, e.g. a PNG height scale or
    // a GDAL band scale; 0 for none). The float array is then released.
    HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM, std::vector<float> heightsM,
               std::vector<uint8_t> valid = {}, StoragePolicy policy = StoragePolicy::Auto, double scaleHint = 0.0);

    // A grid of integer samples decoded straight into int16 codes, without a float copy of the raster: vertex k's
    // height is decodeHeightCode(codes[k], codeOffset, codeScale); `valid` as above (a nodata vertex's code is not
    // read). The grid then holds exactly what the constructor above holds for those heights, with 0 m at the
    // nodata vertices, StoragePolicy::Auto and `scaleHint` (the same storage, codes, validity and pyramid): the
    // codes are re-based in place to the offset and scale it chooses, or decoded to float32 when it would choose
    // that. Throws GridError as the constructor above does.
    HeightGrid(int64_t width, int64_t height, double cellSizeXM, double cellSizeYM, std::vector<int16_t> codes,
               int32_t codeOffset, double codeScale, double scaleHint = 0.0, std::vector<uint8_t> valid = {});

    // A tiled grid: the heights stay in `tiles`, read as rays need them; the grid keeps the summary's range,
    // counts and storage, and the pyramid levels above those the tiles hold. `summary` must describe the tiles.
    HeightGrid(const GridSummary& summary, double cellSizeXM, double cellSizeYM, std::shared_ptr<const TileSource> tiles);

    // Tiled grids: the source, and the pyramid levels each tile holds (1..tileLevels(); the grid holds the rest).
    bool tiled() const { return tiles_ != nullptr; }
    const TileSource* tileSource() const { return tiles_.get(); }
    const std::shared_ptr<const TileSource>& sharedTileSource() const { return tiles_; }
    int tileLevels() const { return tileLevels_; }
    // For hot loops over a tiled grid: the tile holding cell (i, j), from this thread's memo of its last few
    // tiles. The reference stays valid until this thread reads another tile of the grid.
    const HeightTile& tileOfCell(int64_t i, int64_t j) const;

    int64_t width() const { return width_; }    // vertices along x
    int64_t height() const { return height_; }  // vertices along y
    int64_t cellsX() const { return width_ - 1; }
    int64_t cellsY() const { return height_ - 1; }
    double cellSizeXM() const { return cellSizeXM_; }
    double cellSizeYM() const { return cellSizeYM_; }
    double cellsPerMetreX() const { return cellsPerMetreX_; }  // 1 / cellSizeXM(), kept so rays need no division
    double cellsPerMetreY() const { return cellsPerMetreY_; }

    float at(int64_t i, int64_t j) const {
        if (tiles_) [[unlikely]]
            return tiledAt(i, j);
        const auto k = static_cast<size_t>(j * width_ + i);
        return storage_ == HeightStorage::Int16 ? decode(codes_[k]) : heightsM_[k];
    }
    bool vertexValid(int64_t i, int64_t j) const {
        if (tiles_) [[unlikely]]
            return tiledVertexValid(i, j);
        return valid_.empty() || bit(valid_, j * width_ + i);
    }
    // True when all four corners of cell (i, j) are valid.
    bool cellValid(int64_t i, int64_t j) const {
        if (tiles_) [[unlikely]]
            return tiledCellValid(i, j);
        return wholeCellValid(i, j);
    }
    // cellValid of a grid that is not tiled, for hot loops.
    bool wholeCellValid(int64_t i, int64_t j) const { return cellValid_.empty() || bit(cellValid_, j * cellsX() + i); }

    // The storage chosen, and raw access for hot loops (row-major, row j = southmost first); null for a tiled
    // grid.
    HeightStorage storage() const { return storage_; }
    const float* float32Heights() const {
        return storage_ == HeightStorage::Float32 && !tiles_ ? heightsM_.data() : nullptr;
    }
    const int16_t* int16Codes() const { return storage_ == HeightStorage::Int16 && !tiles_ ? codes_.data() : nullptr; }
    int32_t codeOffset() const { return codeOffset_; }  // meaningful for Int16 storage only
    double codeScale() const { return codeScale_; }     // metres per code step; Int16 storage only
    // Every vertex's height as float (nodata vertices hold an unspecified finite or given value). Throws
    // GridError for a tiled grid, which is never held whole.
    std::vector<float> copyHeights() const;
    // The grid under `t`: a whole grid's copy (its storage chosen again), or for a tiled grid one over its source
    // made transformed (TileSource::transformed; GridError when the source cannot).
    HeightGrid transformed(const HeightTransform& t) const;
    bool hasNodata() const { return !valid_.empty(); }
    int64_t nodataVertexCount() const { return nodataVertices_; }
    int64_t validCellCount() const { return validCells_; }

    // Height range over valid vertices (metres); both 0 for a grid without valid cells.
    float minHeightM() const { return minHeightM_; }
    float maxHeightM() const { return maxHeightM_; }

    // Extent of the vertex lattice in local metres.
    double extentXM() const { return static_cast<double>(cellsX()) * cellSizeXM_; }
    double extentYM() const { return static_cast<double>(cellsY()) * cellSizeYM_; }

    // Multiplies every height by k (vertical exaggeration). Throws GridError for a tiled grid.
    void scaleHeights(float k);

    // Bytes held by the grid's own arrays (heights, masks and the pyramids), by capacity; for a tiled grid, its
    // resident pyramid levels and the most its source's tile cache may hold.
    size_t memoryBytes() const;

    // The maximum pyramid (Tevs, Ihrke, Seidel 2008, "Maximum mipmaps for fast, accurate, and scalable
    // dynamic height field rendering"): level k >= 1 holds, for each block of 2^k x 2^k cells, the highest
    // valid vertex of its cells. Level 0 is not stored: it is the cells. Each level is stored as int16 codes,
    // rounded up so that the decoded value never lies below a height it covers; for Int16 height storage the
    // codes are the heights' own, so the bound is exact. A block without a valid vertex gets the lowest code.
    int pyramidLevels() const { return int(levelStart_.size()); }
    // Seconds the last pyramid build took.
    double pyramidBuildSeconds() const { return pyramidBuildSeconds_; }
    // Seconds the grid took to make from its samples, from its constructor's start to its pyramid's end (codes,
    // validity, height range and the pyramid); 0 for a tiled grid.
    double buildSeconds() const { return buildSeconds_; }
    // Blocks along x and y at level k.
    int64_t pyramidBlocksX(int k) const { return (cellsX() + (int64_t(1) << k) - 1) >> k; }
    int64_t pyramidBlocksY(int k) const { return (cellsY() + (int64_t(1) << k) - 1) >> k; }
    // An upper bound on the valid heights in block (bi, bj) of level k (1 <= k <= pyramidLevels()).
    double blockMaxM(int k, int64_t bi, int64_t bj) const;
    // The minimum pyramid, from level 2 up (level 1 would cost half a byte per cell and save little): a
    // lower bound on the valid heights in block (bi, bj) of level k (2 <= k <= pyramidLevels()), in the same
    // codes rounded down; a block without a valid vertex gets the highest code. It lets a ray that runs under
    // the surface (one entering the grid through a side, below the terrain) pass whole blocks.
    // Below level 2 the bound is -infinity.
    double blockMinM(int k, int64_t bi, int64_t bj) const;

    // The pyramid's arrays, for hot loops. A tiled grid's view holds the levels above tileLevels() only.
    struct PyramidView {
        const int16_t* codes;     // all levels, level 1 first
        const int16_t* minCodes;  // the minimum pyramid, levels 2..n: level k's blocks from start[k - 1] - start[1]
        const int64_t* start;     // start[k - 1]: index of level k's first block
        const int64_t* blocksX;   // blocksX[k - 1]: blocks per row of level k
        int32_t offset;
        double scale;
        double codesPerMetre;  // 1 / scale
        int16_t code(int k, int64_t bi, int64_t bj) const { return codes[start[k - 1] + bj * blocksX[k - 1] + bi]; }
        int16_t minCode(int k, int64_t bi, int64_t bj) const {
            return minCodes[start[k - 1] - start[1] + bj * blocksX[k - 1] + bi];
        }
        double blockMaxM(int k, int64_t bi, int64_t bj) const { return decode(code(k, bi, bj)); }
        double blockMinM(int k, int64_t bi, int64_t bj) const { return decode(minCode(k, bi, bj)); }
        double decode(int16_t q) const { return double(decodeHeightCode(q, offset, scale)); }
    };
    PyramidView pyramidView() const {
        return {pyramidCodes_.data(), pyramidMinCodes_.data(), levelStart_.data(), levelBlocksX_.data(),
                pyramidOffset_, pyramidScale_, pyramidCodesPerMetre_};
    }

private:
    static bool bit(const std::vector<uint64_t>& bits, int64_t k) {
        return (bits[static_cast<size_t>(k) >> 6] >> (k & 63)) & 1u;
    }
    float decode(int16_t q) const { return decodeHeightCode(q, codeOffset_, codeScale_); }
    void setLattice();
    const HeightTile& memoTile(int64_t ti, int64_t tj) const;
    const HeightTile& vertexTile(int64_t i, int64_t j) const;
    float tiledAt(int64_t i, int64_t j) const;
    bool tiledVertexValid(int64_t i, int64_t j) const;
    bool tiledCellValid(int64_t i, int64_t j) const;
    void storePyramid(std::vector<std::vector<int16_t>>& highs, std::vector<std::vector<int16_t>>& lows, int first,
                      int levels);
    // `lattice`'s vertices, cell sizes and valid vertices with new heights (float, its storage chosen again).
    HeightGrid(const HeightGrid& lattice, std::vector<float> heightsM);
    void finish();
    // cellValid_ and validCells_ from the vertex flags (every cell valid when there are none).
    void countValidCells();
    bool tryInt16(double scale);
    void chooseStorage();
    void buildPyramid();

    int64_t width_ = 0;
    int64_t height_ = 0;
    double cellSizeXM_ = 1.0;
    double cellSizeYM_ = 1.0;
    double cellsPerMetreX_ = 1.0;
    double cellsPerMetreY_ = 1.0;
    HeightStorage storage_ = HeightStorage::Float32;
    StoragePolicy policy_ = StoragePolicy::Auto;
    double scaleHint_ = 0.0;
    std::vector<float> heightsM_;     // Float32 storage; empty otherwise
    std::vector<int16_t> codes_;      // Int16 storage; empty otherwise
    int32_t codeOffset_ = 0;
    double codeScale_ = 1.0;
    std::vector<uint64_t> valid_;      // one bit per vertex; empty when all valid
    std::vector<uint64_t> cellValid_;  // one bit per cell; empty when all valid
    int64_t nodataVertices_ = 0;
    int64_t validCells_ = 0;
    float minHeightM_ = 0.0f;
    float maxHeightM_ = 0.0f;
    std::vector<int16_t> pyramidCodes_;          // levels 1..n, each row-major, one after the other
    std::vector<int16_t> pyramidMinCodes_;       // the minimum pyramid's levels 2..n, laid out alike
    std::vector<int64_t> levelStart_;            // per level: index of its first block in pyramidCodes_
    std::vector<int64_t> levelBlocksX_;          // per level: blocks per row
    int32_t pyramidOffset_ = 0;
    double pyramidScale_ = 1.0;
    double pyramidCodesPerMetre_ = 1.0;  // 1 / pyramidScale_
    double pyramidBuildSeconds_ = 0.0;
    std::chrono::steady_clock::time_point constructed_ = std::chrono::steady_clock::now();
    double buildSeconds_ = 0.0;
    std::shared_ptr<const TileSource> tiles_;  // tiled grids only
    int tileLevels_ = 0;
};

}  // namespace terracast
