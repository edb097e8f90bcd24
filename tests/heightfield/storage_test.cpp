// Compact storage: integer heights become int16 codes only when every valid height comes back bit for bit,
// the pyramid stays a conservative bound at 2 bytes per block, masks are bits, and the memory per cell meets
// its budget. Tracing the int16 grid gives exactly the float32 grid's hits.
#include "heightfield/fractal_terrain.h"
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"
#include "support/grid_compare.h"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <fstream>
#include <random>
#include <set>

using namespace terracast;
using namespace terracast::testing;

namespace {

std::string samplePath(const std::string& name) { return std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name; }

std::vector<uint8_t> validFlags(const HeightGrid& g) {
    std::vector<uint8_t> valid;
    if (!g.hasNodata()) return valid;
    valid.resize(size_t(g.width() * g.height()));
    for (int64_t j = 0; j < g.height(); ++j)
        for (int64_t i = 0; i < g.width(); ++i) valid[size_t(j * g.width() + i)] = g.vertexValid(i, j) ? 1 : 0;
    return valid;
}

// The same heights and mask, held as float32.
HeightGrid asFloat32(const HeightGrid& g) {
    return HeightGrid(g.width(), g.height(), g.cellSizeXM(), g.cellSizeYM(), g.copyHeights(), validFlags(g),
                      StoragePolicy::Float32);
}

bool sameBits(float a, float b) { return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b); }

// Every valid vertex of `g` holds exactly the float `z` gave it.
void requireSameValidHeights(const HeightGrid& g, const std::vector<float>& z) {
    for (int64_t j = 0; j < g.height(); ++j)
        for (int64_t i = 0; i < g.width(); ++i)
            if (g.vertexValid(i, j)) {
                INFO("vertex " << i << ", " << j);
                REQUIRE(sameBits(g.at(i, j), z[size_t(j * g.width() + i)]));
            }
}

double bytesPerCell(const HeightGrid& g) { return double(g.memoryBytes()) / double(g.cellsX() * g.cellsY()); }

// A w x h grid of whole-metre heights in [lo, hi], or of fractional ones, with every `holeEvery`-th vertex
// nodata (0 for none).
HeightGrid seededGrid(int64_t w, int64_t h, bool whole, float lo, float hi, int holeEvery, uint64_t seed,
                      StoragePolicy policy = StoragePolicy::Auto) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<float> U(lo, hi);
    std::vector<float> z(size_t(w * h));
    for (auto& v : z) v = whole ? std::round(U(rng)) + 0.0f : U(rng);  // + 0 turns -0 (not bit-exact in int16) into 0
    std::vector<uint8_t> valid;
    if (holeEvery > 0) {
        valid.assign(z.size(), 1);
        for (size_t k = 0; k < valid.size(); ++k)
            if (rng() % uint64_t(holeEvery) == 0) valid[k] = 0, z[k] = -9999.5f;
    }
    return HeightGrid(w, h, 10.0, 10.0, std::move(z), std::move(valid), policy);
}

}  // namespace

TEST_CASE("Storage: whole-metre heights are held as int16, bit for bit", "[heightfield][storage]") {
    std::vector<float> z(40 * 30);
    std::mt19937_64 rng(1);
    for (auto& v : z) v = float(int64_t(rng() % 9000) - 400);
    const HeightGrid g(40, 30, 5.0, 5.0, z);
    CHECK(g.storage() == HeightStorage::Int16);
    CHECK(g.codeScale() == 1.0);
    CHECK(g.int16Codes() != nullptr);
    CHECK(g.float32Heights() == nullptr);
    requireSameValidHeights(g, z);
    CHECK(g.copyHeights() == z);

    // The full span of 16-bit samples (a PNG height map at 1 m per unit) still fits.
    std::vector<float> wide(9, 0.0f);
    wide[4] = 65535.0f;
    const HeightGrid w(3, 3, 1.0, 1.0, wide);
    CHECK(w.storage() == HeightStorage::Int16);
    requireSameValidHeights(w, wide);
}

TEST_CASE("Storage: float32 is kept when int16 would lose anything, or when asked", "[heightfield][storage]") {
    std::vector<float> z(20 * 20, 100.0f);
    for (size_t k = 0; k < z.size(); ++k) z[k] = float(k % 37);
    CHECK(HeightGrid(20, 20, 1.0, 1.0, z).storage() == HeightStorage::Int16);
    // One height off the metre.
    std::vector<float> one = z;
    one[123] = 12.25f;
    const HeightGrid fractional(20, 20, 1.0, 1.0, one);
    CHECK(fractional.storage() == HeightStorage::Float32);
    CHECK(fractional.float32Heights() != nullptr);
    CHECK(fractional.int16Codes() == nullptr);
    requireSameValidHeights(fractional, one);
    // Whole metres, but a range of more than 65535 steps.
    std::vector<float> tall = z;
    tall[7] = 70000.0f;
    CHECK(HeightGrid(20, 20, 1.0, 1.0, tall).storage() == HeightStorage::Float32);
    // ... unless a hint of 2 m per unit covers it exactly.
    const HeightGrid hinted(20, 20, 1.0, 1.0, [&] {
        std::vector<float> even = tall;
        for (auto& v : even) v = 2.0f * std::round(v / 2.0f);
        return even;
    }(), {}, StoragePolicy::Auto, 2.0);
    CHECK(hinted.storage() == HeightStorage::Int16);
    CHECK(hinted.codeScale() == 2.0);
    // Asked for float32.
    const HeightGrid forced(20, 20, 1.0, 1.0, z, {}, StoragePolicy::Float32);
    CHECK(forced.storage() == HeightStorage::Float32);
    requireSameValidHeights(forced, z);
    // A fractional value at a nodata vertex does not matter.
    std::vector<uint8_t> valid(z.size(), 1);
    valid[123] = 0;
    const HeightGrid holed(20, 20, 1.0, 1.0, one, valid);
    CHECK(holed.storage() == HeightStorage::Int16);
    requireSameValidHeights(holed, one);
}

TEST_CASE("Storage: real integer DEMs load as int16 with their exact heights", "[heightfield][storage][loaders]") {
    // SRTM .hgt: 1201 x 1201 big-endian int16, north row first; compare against the file's own samples.
    const LoadedDem hgt = loadDem(samplePath("N44W072.srtm3-white-mountains-nh.hgt"));
    REQUIRE(hgt.grid.width() == 1201);
    CHECK(hgt.grid.storage() == HeightStorage::Int16);
    std::ifstream in(samplePath("N44W072.srtm3-white-mountains-nh.hgt"), std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    REQUIRE(bytes.size() == 1201u * 1201u * 2u);
    for (int64_t row = 0; row < 1201; ++row)
        for (int64_t i = 0; i < 1201; ++i) {
            const size_t k = size_t(row * 1201 + i) * 2;
            const auto raw = int16_t(uint16_t(bytes[k] << 8 | bytes[k + 1]));
            const int64_t j = 1200 - row;
            if (raw == -32768) continue;
            REQUIRE(hgt.grid.vertexValid(i, j));
            REQUIRE(sameBits(hgt.grid.at(i, j), float(raw)));
        }
    // Int16 GeoTIFFs with nodata, and a 16-bit PNG at 0.1 m per unit (the loader passes that scale on).
    for (const char* name : {"srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif",
                             "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif"}) {
        INFO(name);
        const LoadedDem dem = loadDem(samplePath(name));
        CHECK(dem.grid.hasNodata());
        CHECK(dem.grid.storage() == HeightStorage::Int16);
    }
    DemLoadOptions png;
    png.imageCellSizeM = 160.0;
    png.imageHeightScale = 0.1;
    const LoadedDem puget = loadDem(samplePath("puget-sound-usgs-1025x1025-16bit-heightmap.png"), png);
    CHECK(puget.grid.storage() == HeightStorage::Int16);
    CHECK(puget.grid.codeScale() == 0.1);
    png.imageHeightScale = 1.0;
    const LoadedDem metres = loadDem(samplePath("puget-sound-usgs-1025x1025-16bit-heightmap.png"), png);
    CHECK(metres.grid.storage() == HeightStorage::Int16);
    CHECK(metres.grid.codeScale() == 1.0);
    // The 0.1 m grid's heights are those of the 1 m grid times 0.1, rounded once to float, as the loader does.
    for (int64_t j = 0; j < 1025; j += 7)
        for (int64_t i = 0; i < 1025; i += 5)
            REQUIRE(sameBits(puget.grid.at(i, j), float(double(metres.grid.at(i, j)) * 0.1)));
}

TEST_CASE("Storage: bytes per cell within budget, with and without nodata", "[heightfield][storage]") {
    for (int holes : {0, 50}) {
        INFO("one vertex in " << holes << " is nodata");
        const HeightGrid whole = seededGrid(513, 513, true, 0.0f, 4000.0f, holes, 1);
        const HeightGrid fractional = seededGrid(513, 513, false, 0.0f, 4000.0f, holes, 2);
        REQUIRE(whole.storage() == HeightStorage::Int16);
        REQUIRE(fractional.storage() == HeightStorage::Float32);
        CHECK(whole.hasNodata() == (holes > 0));
        CHECK(bytesPerCell(whole) <= 3.5);
        CHECK(bytesPerCell(fractional) <= 6.0);
        // Float32 forced on the integer grid costs the float budget.
        const HeightGrid forced = seededGrid(513, 513, true, 0.0f, 4000.0f, holes, 1, StoragePolicy::Float32);
        CHECK(bytesPerCell(forced) <= 6.0);
        CHECK(bytesPerCell(forced) > bytesPerCell(whole) + 1.9);
    }
}

TEST_CASE("Storage: the int16 pyramids bound every block, exactly over int16 heights", "[heightfield][storage]") {
    for (uint64_t seed = 1; seed <= 6; ++seed) {
        const bool whole = seed % 2 == 0;
        const int holes = seed > 4 ? 0 : 7;
        // Odd sizes, so the last blocks are partial; one grid with a huge offset and a tiny relief.
        const HeightGrid g = seed == 3 ? seededGrid(61, 45, false, 8000.0f, 8000.01f, holes, seed)
                                       : seededGrid(77, 53, whole, -300.0f, 2500.0f, holes, seed);
        INFO("seed " << seed);
        REQUIRE(g.storage() == (whole ? HeightStorage::Int16 : HeightStorage::Float32));
        for (int k = 1; k <= g.pyramidLevels(); ++k)
            for (int64_t bj = 0; bj < g.pyramidBlocksY(k); ++bj)
                for (int64_t bi = 0; bi < g.pyramidBlocksX(k); ++bi) {
                    // The highest and lowest valid vertices of the block's cells.
                    float m = -INFINITY, lo = INFINITY;
                    for (int64_t j = bj << k; j <= std::min((bj + 1) << k, g.cellsY()); ++j)
                        for (int64_t i = bi << k; i <= std::min((bi + 1) << k, g.cellsX()); ++i)
                            if (g.vertexValid(i, j)) {
                                m = std::max(m, g.at(i, j));
                                lo = std::min(lo, g.at(i, j));
                            }
                    if (m == -INFINITY) continue;
                    INFO("level " << k << " block " << bi << ", " << bj);
                    REQUIRE(g.blockMaxM(k, bi, bj) >= double(m));
                    if (whole) REQUIRE(g.blockMaxM(k, bi, bj) == double(m));
                    if (k < 2) continue;  // the minimum pyramid starts at level 2
                    REQUIRE(g.blockMinM(k, bi, bj) <= double(lo));
                    if (whole) REQUIRE(g.blockMinM(k, bi, bj) == double(lo));
                }
    }
}

TEST_CASE("Storage: int16 and float32 grids of the same DEM give identical hits", "[heightfield][storage]") {
    for (const char* name : {"N44W072.srtm3-white-mountains-nh.hgt",
                             "srtm3-n43e007-nice-maritime-alps-coast-geographic-int16.tif"}) {
        INFO(name);
        const HeightGrid a = loadDem(samplePath(name)).grid;
        REQUIRE(a.storage() == HeightStorage::Int16);
        const HeightGrid b = asFloat32(a);
        REQUIRE(b.storage() == HeightStorage::Float32);
        REQUIRE(b.memoryBytes() > a.memoryBytes());
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        int hits = 0;
        for (int k = 0; k < 10000; ++k) {
            glm::dvec3 o, d;
            const double az = 2.0 * M_PI * U(rng);
            if (k % 2 == 0) {  // from above
                const double el = (1.0 + 60.0 * U(rng)) * M_PI / 180.0;
                d = {std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el)};
                o = glm::dvec3(a.extentXM() * U(rng), a.extentYM() * U(rng), a.minHeightM()) -
                    ((a.maxHeightM() - a.minHeightM() + 50.0) / std::sin(el)) * d;
            } else {  // nearly level, from inside the box
                d = {std::cos(az), std::sin(az), 0.05 * (U(rng) - 0.5)};
                o = {a.extentXM() * U(rng), a.extentYM() * U(rng),
                     a.minHeightM() + (a.maxHeightM() - a.minHeightM()) * U(rng)};
            }
            const Ray ray{o, d};
            const CellMethod m = k % 4 < 2 ? CellMethod::Bilinear : CellMethod::Triangles;
            const auto ha = intersect(a, ray, {0, kInfinity}, m);
            const auto hb = intersect(b, ray, {0, kInfinity}, m);
            INFO("ray " << k);
            REQUIRE(ha.has_value() == hb.has_value());
            REQUIRE(occluded(a, ray, {0, kInfinity}, m) == occluded(b, ray, {0, kInfinity}, m));
            if (!ha) continue;
            ++hits;
            REQUIRE(ha->t == hb->t);
            REQUIRE(ha->cellX == hb->cellX);
            REQUIRE(ha->cellY == hb->cellY);
            REQUIRE(ha->normal.x == hb->normal.x);
            REQUIRE(ha->normal.y == hb->normal.y);
            REQUIRE(ha->normal.z == hb->normal.z);
        }
        CHECK(hits > 5000);
    }
}

TEST_CASE("Storage: vertical exaggeration of an int16 grid matches the float32 path", "[heightfield][storage]") {
    const HeightGrid base = seededGrid(65, 65, true, 0.0f, 3000.0f, 11, 9);
    REQUIRE(base.storage() == HeightStorage::Int16);
    for (float k : {2.0f, 1.5f, 0.3f}) {
        INFO("k = " << k);
        HeightGrid a = base, b = asFloat32(base);
        a.scaleHeights(k);
        b.scaleHeights(k);
        CHECK(b.storage() == HeightStorage::Float32);
        requireSameValidHeights(a, b.copyHeights());
        CHECK(a.maxHeightM() == b.maxHeightM());
        // Doubling and 1.5 keep exact codes (at 1 and 1.5 m per code); 0.3 does not round-trip through a
        // multiple of 0.3 m in every case, so either storage is fine there as long as the heights agree.
        if (k != 0.3f) CHECK(a.storage() == HeightStorage::Int16);
    }
}

TEST_CASE("Storage: integer fractal terrain is int16 and matches the float terrain rounded", "[heightfield][storage]") {
    FractalTerrainOptions o;
    o.size = 257;
    const HeightGrid f = fractalTerrain(o);
    o.integerHeights = true;
    const HeightGrid n = fractalTerrain(o);
    CHECK(f.storage() == HeightStorage::Float32);
    CHECK(n.storage() == HeightStorage::Int16);
    for (int64_t j = 0; j < 257; ++j)
        for (int64_t i = 0; i < 257; ++i) REQUIRE(n.at(i, j) == std::round(f.at(i, j)));
    CHECK(bytesPerCell(n) <= 3.5);
    CHECK(bytesPerCell(f) <= 6.0);
}

TEST_CASE("Storage: a grid made from codes holds what the float constructor holds for their heights",
          "[heightfield][storage]") {
    // Samples as a PNG height map holds them (8 or 16 bits), under the height scales users give; the float
    // constructor is the reference: the same storage, offset, scale, heights and pyramid, bit for bit.
    const int64_t w = 97, h = 83;
    std::mt19937 rng(5);
    std::set<int> storages;
    for (const int bits : {8, 16}) {
        for (const double scale : {1.0, 0.1, 0.5, 2.0, 3.0, 0.3, 1e-7}) {
            for (const bool narrow : {false, true}) {
              for (const bool holes : {false, true}) {
                INFO(bits << "-bit samples, " << scale << " m per unit, " << (narrow ? "narrow" : "full") << " range"
                          << (holes ? ", with nodata" : ""));
                const int32_t top = bits == 8 ? 255 : 65535;
                std::uniform_int_distribution<int32_t> sample(narrow ? top / 3 : 0, narrow ? top / 3 + 200 : top);
                std::vector<int32_t> raw(size_t(w * h));
                for (auto& r : raw) r = sample(rng);
                if (!narrow) raw[0] = 0, raw[1] = top;  // both ends of the range
                std::vector<float> heights(raw.size());
                std::vector<int16_t> codes(raw.size());
                const int32_t offset = bits == 16 ? 32768 : 0;
                for (size_t k = 0; k < raw.size(); ++k) {
                    heights[k] = float(double(raw[k]) * scale);
                    codes[k] = int16_t(raw[k] - offset);
                }
                // Nodata: about one vertex in twelve and a whole row; the float reference holds 0 m there (as the
                // loader gives it), the codes anything, here the far end of the 16-bit range, which must widen
                // neither the range nor the pyramid.
                std::vector<uint8_t> valid;
                if (holes) {
                    valid.assign(raw.size(), 1);
                    std::bernoulli_distribution hole(1.0 / 12.0);
                    for (size_t k = 2; k < raw.size(); ++k)
                        if (hole(rng) || k / size_t(w) == 40) {
                            valid[k] = 0;
                            heights[k] = 0.0f;
                            codes[k] = int16_t(32767);
                        }
                }
                // Without the scale as a hint, heights off whole metres stay float32.
                const double hint = narrow ? 0.0 : scale;
                const HeightGrid a(w, h, 10.0, 10.0, heights, valid, StoragePolicy::Auto, hint);
                const HeightGrid b(w, h, 10.0, 10.0, codes, offset, scale, hint, valid);
                CHECK(b.nodataVertexCount() == a.nodataVertexCount());
                CHECK((a.nodataVertexCount() > w) == holes);
                storages.insert(int(a.storage()));
                CHECK(b.storage() == a.storage());
                CHECK(b.codeOffset() == a.codeOffset());
                CHECK(b.codeScale() == a.codeScale());
                CHECK(std::bit_cast<uint32_t>(b.minHeightM()) == std::bit_cast<uint32_t>(a.minHeightM()));
                CHECK(std::bit_cast<uint32_t>(b.maxHeightM()) == std::bit_cast<uint32_t>(a.maxHeightM()));
                CHECK(b.validCellCount() == a.validCellCount());
                int64_t differ = 0;
                for (int64_t j = 0; j < h; ++j)
                    for (int64_t i = 0; i < w; ++i)
                        differ += std::bit_cast<uint32_t>(a.at(i, j)) != std::bit_cast<uint32_t>(b.at(i, j)) ||
                                  a.vertexValid(i, j) != b.vertexValid(i, j) ||
                                  (i + 1 < w && j + 1 < h && a.cellValid(i, j) != b.cellValid(i, j));
                REQUIRE(a.pyramidLevels() == b.pyramidLevels());
                differ += pyramidDifferences(a, b);
                CHECK(differ == 0);
              }
            }
        }
    }
    CHECK(storages.size() == 2);  // both storages were made
}
