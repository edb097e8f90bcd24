// A grid held as tiles behind a cache a few tiles large traces exactly as the same grid held whole: the same
// pyramid bounds at every level, and for every ray the same hit bits, the same occlusion verdict and the same
// walk (cells visited and tested, blocks skipped), across tile edges, nodata holes that straddle them and rays
// running along the grid lines between tiles.
#include "heightfield/coarser_grid.h"
#include "heightfield/fractal_terrain.h"
#include "heightfield/grid_summary.h"
#include "heightfield/height_tile.h"
#include "heightfield/shading_normals.h"
#include "heightfield/tile_cache.h"
#include "heightfield/traversal.h"
#include "support/cut_tiles.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <memory>
#include <random>

using namespace terracast;
using terracast::testing::CutTiles;
using terracast::testing::kSweepDivisor;

namespace {

enum class Heights { Float, WholeMetres, Tenths };

// A 700 x 600 vertex fractal grid (3 x 3 tiles, the last ones part-filled) with holes across tile edges: a
// square straddling the corner of four tiles, a strip along the column x = 256 and a nodata border row.
HeightGrid testGrid(Heights kind) {
    FractalTerrainOptions o;
    o.size = 1025;
    o.cellSizeM = 10.0;
    o.seed = 7;
    const HeightGrid big = fractalTerrain(o);
    const int64_t w = 700, h = 600;
    std::vector<float> z(size_t(w * h));
    std::vector<uint8_t> valid(z.size(), 1);
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) {
            float v = big.at(i, j) + 1234.567f;
            if (kind == Heights::WholeMetres) v = std::round(v);
            if (kind == Heights::Tenths) v = float(std::round(double(v) * 10.0) * 0.1);
            z[size_t(j * w + i)] = v;
            const bool corner = std::abs(i - 256) < 9 && std::abs(j - 256) < 6;
            const bool strip = i == 256 && j > 300 && j < 420;
            const bool border = j == h - 1 && i > 100;
            if (corner || strip || border) valid[size_t(j * w + i)] = 0;
        }
    return HeightGrid(w, h, 10.0, 10.0, z, valid, StoragePolicy::Auto, 0.1);
}

uint64_t bits(double x) { return std::bit_cast<uint64_t>(x); }

}  // namespace

TEST_CASE("Tiled grid: pyramid bounds at every level equal the whole grid's", "[heightfield][tiles]") {
    for (auto [kind, wholeMetres] : {std::pair{Heights::Float, false}, std::pair{Heights::WholeMetres, false},
                                     std::pair{Heights::WholeMetres, true}, std::pair{Heights::Tenths, false}}) {
        const HeightGrid whole = testGrid(kind);
        auto tiles = std::make_shared<CutTiles>(whole, size_t(1) << 30, wholeMetres);
        if (wholeMetres) REQUIRE(HeightTile::takesWholeMetres(tiles->summary()));
        const HeightGrid tiled(tiles->summary(), 10.0, 10.0, tiles);
        INFO("storage " << int(whole.storage()) << " scale " << whole.codeScale() << " from 16-bit metres "
                        << wholeMetres);
        REQUIRE(tiled.tiled());
        REQUIRE(tiled.storage() == whole.storage());
        REQUIRE(tiled.pyramidLevels() == whole.pyramidLevels());
        CHECK(tiled.tileLevels() == kTileLevels);
        CHECK(tiled.minHeightM() == whole.minHeightM());
        CHECK(tiled.maxHeightM() == whole.maxHeightM());
        CHECK(tiled.validCellCount() == whole.validCellCount());
        int64_t differ = 0, blocks = 0;
        for (int k = 1; k <= whole.pyramidLevels(); ++k)
            for (int64_t bj = 0; bj < whole.pyramidBlocksY(k); ++bj)
                for (int64_t bi = 0; bi < whole.pyramidBlocksX(k); ++bi) {
                    ++blocks;
                    differ += bits(tiled.blockMaxM(k, bi, bj)) != bits(whole.blockMaxM(k, bi, bj));
                    differ += bits(tiled.blockMinM(k, bi, bj)) != bits(whole.blockMinM(k, bi, bj));
                }
        CHECK(blocks > 140000);
        CHECK(differ == 0);
        // The grid itself holds only the levels above the tiles' (and counts its source's cache).
        CHECK(tiled.memoryBytes() - tiles->cacheBudgetBytes() < 1024);
    }
}

TEST_CASE("Tiled grid: rays through a cache of two tiles trace exactly as through the whole grid",
          "[heightfield][tiles]") {
    for (Heights kind : {Heights::Float, Heights::WholeMetres, Heights::Tenths}) {
        const HeightGrid whole = testGrid(kind);
        // Room for two tiles: every tile change past the second evicts one.
        const size_t tileBytes = CutTiles(whole, size_t(1) << 30).tile(0, 0)->bytes();
        auto tiles = std::make_shared<CutTiles>(whole, 2 * tileBytes + tileBytes / 2, kind == Heights::WholeMetres);
        const HeightGrid tiled(tiles->summary(), 10.0, 10.0, tiles);
        std::mt19937_64 rng(11);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const double lo = whole.minHeightM(), hi = whole.maxHeightM();
        std::vector<Ray> rays;
        for (int k = 0; k < 700 / kSweepDivisor; ++k) {
            // From above the terrain inside the footprint, looking down and across.
            const glm::dvec3 o{u(rng) * 6990.0, u(rng) * 5990.0, lo + (hi - lo) * (0.3 + 1.2 * u(rng))};
            const double az = 2.0 * M_PI * u(rng), el = -0.5 + 0.6 * u(rng);
            rays.push_back({o, {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)}});
        }
        for (int k = 0; k < 150 / kSweepDivisor; ++k) {
            // Cameras outside the footprint, high above it.
            const glm::dvec3 o{-3000.0 + 13000.0 * u(rng), -4000.0, hi + 2000.0 * u(rng)};
            const glm::dvec3 target{u(rng) * 6990.0, u(rng) * 5990.0, lo};
            rays.push_back({o, glm::normalize(target - o)});
        }
        for (int k = 0; k < 100 / kSweepDivisor; ++k) {
            // Along the grid lines between tiles and beside the holes: x = 2560 m and y = 2560 m, both ways.
            const double level = lo + (hi - lo) * u(rng);
            const double sign = k % 2 == 0 ? 1.0 : -1.0;
            if (k % 4 < 2) rays.push_back({{2560.0, k % 2 == 0 ? 1.0 : 5989.0, level}, {0.0, sign, -0.01 * u(rng)}});
            else rays.push_back({{k % 2 == 0 ? 1.0 : 6989.0, 2560.0, level}, {sign, 0.0, -0.01 * u(rng)}});
        }
        for (CellMethod method : allCellMethods()) {
            INFO("storage " << int(whole.storage()) << " scale " << whole.codeScale() << " " << cellMethodName(method));
            int64_t hits = 0, hitsDiffer = 0, occlusionDiffer = 0, walksDiffer = 0;
            for (const Ray& ray : rays) {
                TraceCounters cw, ct;
                const auto a = intersect(whole, ray, {0.0, kInfinity}, method, &cw);
                const auto b = intersect(tiled, ray, {0.0, kInfinity}, method, &ct);
                hits += a.has_value();
                if (a.has_value() != b.has_value()) ++hitsDiffer;
                else if (a && (bits(a->t) != bits(b->t) || bits(a->normal.x) != bits(b->normal.x) ||
                               bits(a->normal.y) != bits(b->normal.y) || a->cellX != b->cellX || a->cellY != b->cellY))
                    ++hitsDiffer;
                walksDiffer += cw.cellsVisited != ct.cellsVisited || cw.cellsTested != ct.cellsTested ||
                               cw.blocksSkipped != ct.blocksSkipped;
                occlusionDiffer += occluded(whole, ray, {0.0, 5000.0}, method) != occluded(tiled, ray, {0.0, 5000.0}, method);
            }
            CHECK(hits > 300 / kSweepDivisor);
            CHECK(hitsDiffer == 0);
            CHECK(walksDiffer == 0);
            CHECK(occlusionDiffer == 0);
        }
        const TileCacheStats stats = tiles->cacheStats();
        INFO(stats.loads << " tile loads, " << stats.evictions << " evictions");
        CHECK(stats.evictions > 50 / kSweepDivisor);
        CHECK(stats.peakBytes <= tiles->cacheBudgetBytes());
        // Bundles of rays from one point (the renderer's camera path) prove their free stretch on the tiles.
        std::vector<Ray> bundle;
        for (int k = 0; k < 64; ++k) bundle.push_back({{-500.0, -700.0, hi + 300.0}, glm::normalize(glm::dvec3{
                                                           1.0, 0.6 + 0.01 * k, -0.25 + 0.002 * k})});
        std::vector<std::optional<HeightFieldHit>> ha(bundle.size()), hb(bundle.size());
        intersectBundle(whole, bundle, {0.0, kInfinity}, CellMethod::Bilinear, ha);
        intersectBundle(tiled, bundle, {0.0, kInfinity}, CellMethod::Bilinear, hb);
        int64_t bundleDiffer = 0, bundleHits = 0;
        for (size_t k = 0; k < bundle.size(); ++k) {
            bundleHits += ha[k].has_value();
            bundleDiffer += ha[k].has_value() != hb[k].has_value() || (ha[k] && bits(ha[k]->t) != bits(hb[k]->t));
        }
        CHECK(bundleHits > 20);
        CHECK(bundleDiffer == 0);
    }
}

TEST_CASE("Tiled grid: smooth shading normals equal the whole grid's, inside tiles, along their borders and "
          "beside holes",
          "[heightfield][tiles]") {
    const HeightGrid whole = testGrid(Heights::WholeMetres);
    const size_t tileBytes = CutTiles(whole, size_t(1) << 30).tile(0, 0)->bytes();
    auto tiles = std::make_shared<CutTiles>(whole, 2 * tileBytes + tileBytes / 2, true);
    const HeightGrid tiled(tiles->summary(), 10.0, 10.0, tiles);
    // Every cell of the columns and rows around the tile borders (x, y = 256 and 512) and the holes there, and a
    // sparse sample elsewhere, at a few positions inside each cell.
    auto near = [](int64_t c) { return std::abs(c - 256) < 12 || std::abs(c - 512) < 4 || c < 3; };
    int64_t cells = 0, differ = 0;
    for (int64_t j = 0; j < whole.cellsY(); ++j)
        for (int64_t i = 0; i < whole.cellsX(); ++i) {
            // Rays hit valid cells only, whose corners are all valid (at a nodata vertex the grids hold different
            // placeholders).
            if ((!near(i) && !near(j) && (i * 7 + j * 3) % 61 != 0) || !whole.cellValid(i, j)) continue;
            ++cells;
            for (auto [u, v] : {std::pair{0.0, 0.0}, std::pair{0.25, 0.8}, std::pair{1.0, 0.5}}) {
                const glm::dvec3 a = smoothNormal(whole, i, j, u, v), b = smoothNormal(tiled, i, j, u, v);
                differ += bits(a.x) != bits(b.x) || bits(a.y) != bits(b.y) || bits(a.z) != bits(b.z);
            }
        }
    CHECK(cells > 40000);
    CHECK(differ == 0);
}

TEST_CASE("Tiled grid: a tile whose heights the summary cannot code is refused from floats and from 16-bit metres",
          "[heightfield][tiles]") {
    const int64_t w = 9, h = 7;
    std::vector<float> z(size_t(w * h));
    for (size_t k = 0; k < z.size(); ++k) z[k] = float(20000 + int(k % 11));
    GridSummaryBuilder builder(w, h, 1.0);
    builder.addRows(0, h, z.data(), nullptr);
    const GridSummary summary = builder.finish();
    REQUIRE(HeightTile::takesWholeMetres(summary));
    std::vector<int16_t> metres(z.begin(), z.end());
    std::vector<uint8_t> valid(z.size(), 1);
    // As summarised: the same codes either way.
    const HeightTile a(summary, 0, 0, w, h, z.data(), valid.data()), b(summary, 0, 0, w, h, metres.data(), valid.data());
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) CHECK(a.at(i, j) == b.at(i, j));
    // A height 50 km below the summary's range has no code: refused, naming the vertex.
    z[size_t(2 * w + 3)] = -30000.0f;
    metres[size_t(2 * w + 3)] = -30000;
    CHECK_THROWS_WITH(HeightTile(summary, 0, 0, w, h, z.data(), valid.data()),
                      Catch::Contains("vertex (3, 2): height -30000") && Catch::Contains("no int16 code"));
    CHECK_THROWS_WITH(HeightTile(summary, 0, 0, w, h, metres.data(), valid.data()),
                      Catch::Contains("vertex (3, 2): height -30000") && Catch::Contains("no int16 code"));
    // The same value at a nodata vertex is no height: the lowest code, and no error.
    valid[size_t(2 * w + 3)] = 0;
    CHECK_NOTHROW(HeightTile(summary, 0, 0, w, h, metres.data(), valid.data()));
    CHECK_FALSE(HeightTile(summary, 0, 0, w, h, metres.data(), valid.data()).vertexValid(3, 2));
}

TEST_CASE("Tiled grid: what needs the whole grid is refused", "[heightfield][tiles]") {
    const HeightGrid whole = testGrid(Heights::WholeMetres);
    auto tiles = std::make_shared<CutTiles>(whole, size_t(1) << 24);
    HeightGrid tiled(tiles->summary(), 10.0, 10.0, tiles);
    CHECK(tiled.int16Codes() == nullptr);
    CHECK(tiled.float32Heights() == nullptr);
    CHECK_THROWS_AS(tiled.copyHeights(), GridError);
    CHECK_THROWS_AS(tiled.scaleHeights(2.0f), GridError);
    // Single values through the tiles are the whole grid's.
    CHECK(tiled.at(256, 100) == whole.at(256, 100));
    CHECK(tiled.vertexValid(256, 256) == whole.vertexValid(256, 256));
    CHECK(tiled.cellValid(255, 250) == whole.cellValid(255, 250));
    CHECK(tiled.at(699, 599) == whole.at(699, 599));
}

TEST_CASE("Tiled grid: a level of detail's coarser grids read from a cache of one tile are the whole grid's",
          "[heightfield][tiles][lod]") {
    for (Heights kind : {Heights::Float, Heights::WholeMetres, Heights::Tenths}) {
        const HeightGrid whole = testGrid(kind);
        const size_t tileBytes = CutTiles(whole, size_t(1) << 30).tile(0, 0)->bytes();
        auto tiles = std::make_shared<CutTiles>(whole, tileBytes + tileBytes / 2, kind == Heights::WholeMetres);
        const HeightGrid tiled(tiles->summary(), 10.0, 10.0, tiles);
        // The whole grid's levels, one step at a time (coarserGrid, tested on its own), against each level made
        // in one pass from the tiles, on two threads sharing the one-tile cache.
        HeightGrid step = coarserGrid(whole);
        for (int level = 1; level <= 4; ++level) {
            INFO("storage " << int(whole.storage()) << ", level " << level);
            const int64_t loadsBefore = tiles->cacheStats().loads;
            const HeightGrid coarse = coarserGrid(tiled, level, 2);
            // Each of the 3 x 3 tiles read once (one may still be in the cache from the pass before).
            CHECK(tiles->cacheStats().loads - loadsBefore <= 9);
            CHECK(tiles->cacheStats().loads - loadsBefore >= 8);
            REQUIRE(coarse.width() == step.width());
            REQUIRE(coarse.height() == step.height());
            CHECK(coarse.cellSizeXM() == step.cellSizeXM());
            CHECK(coarse.cellSizeYM() == step.cellSizeYM());
            int64_t differ = 0, holes = 0;
            for (int64_t j = 0; j < step.height(); ++j)
                for (int64_t i = 0; i < step.width(); ++i) {
                    differ += coarse.vertexValid(i, j) != step.vertexValid(i, j);
                    holes += !step.vertexValid(i, j);
                    if (step.vertexValid(i, j)) differ += bits(coarse.at(i, j)) != bits(step.at(i, j));
                }
            CHECK(differ == 0);
            // The holes straddling tile edges leave some coarse vertices out at the finer levels.
            if (level <= 2) CHECK(holes > 0);
            // The same in one pass from the whole grid.
            const HeightGrid direct = coarserGrid(whole, level);
            int64_t directDiffer = 0;
            for (int64_t j = 0; j < step.height(); ++j)
                for (int64_t i = 0; i < step.width(); ++i)
                    if (step.vertexValid(i, j)) directDiffer += bits(direct.at(i, j)) != bits(step.at(i, j));
            CHECK(directDiffer == 0);
            step = coarserGrid(step);
        }
    }
    // The vertices kept along an axis: every other one, the last clamped, then again.
    CHECK(coarseVertexIndices(10, 1) == std::vector<int64_t>{0, 2, 4, 6, 8, 9});
    CHECK(coarseVertexIndices(10, 2) == std::vector<int64_t>{0, 4, 8, 9});
    CHECK(coarseVertexIndices(10, 3) == std::vector<int64_t>{0, 8, 9});
    CHECK(coarseVertexIndices(10, 4) == std::vector<int64_t>{0, 9});
    CHECK_THROWS_AS(coarseVertexIndices(10, 5), GridError);
}

namespace {

// The tiles of CutTiles, but tile (1, 2) cannot be read.
class FailingTiles : public TileSource {
public:
    explicit FailingTiles(std::shared_ptr<CutTiles> tiles) : tiles_(std::move(tiles)) {}
    std::shared_ptr<const HeightTile> tile(int64_t ti, int64_t tj) const override {
        if (ti == 1 && tj == 2) throw std::runtime_error("tile 1, 2: cannot read");
        return tiles_->tile(ti, tj);
    }
    TileCacheStats cacheStats() const override { return tiles_->cacheStats(); }
    size_t cacheBudgetBytes() const override { return tiles_->cacheBudgetBytes(); }

private:
    std::shared_ptr<CutTiles> tiles_;
};

}  // namespace

TEST_CASE("Tiled grid: a coarser grid's pass passes on a tile's failure to read, and a thin grid has no coarser one",
          "[heightfield][tiles][lod]") {
    const HeightGrid whole = testGrid(Heights::Float);
    auto tiles = std::make_shared<CutTiles>(whole, size_t(1) << 24);
    const HeightGrid failing(tiles->summary(), 10.0, 10.0, std::make_shared<FailingTiles>(tiles));
    for (const int threads : {1, 2}) CHECK_THROWS_WITH(coarserGrid(failing, 2, threads), "tile 1, 2: cannot read");
    // A grid two vertices wide (one cell) has no coarser grid, from memory or from tiles.
    std::vector<float> z(2 * 300, 5.0f);
    const HeightGrid thin(2, 300, 10.0, 10.0, z);
    auto thinTiles = std::make_shared<CutTiles>(thin, size_t(1) << 24);
    const HeightGrid thinTiled(thinTiles->summary(), 10.0, 10.0, thinTiles);
    CHECK_THROWS_AS(coarserGrid(thin), GridError);
    CHECK_THROWS_AS(coarserGrid(thinTiled, 1), GridError);
}
