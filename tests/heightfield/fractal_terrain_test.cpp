// The synthetic fractal terrain of the benchmark: the same options give the same heights, the grid has the
// size asked for, its relief and slopes look like mountains, and sizes the algorithm cannot make are refused.
#include "heightfield/fractal_terrain.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

using namespace terracast;

namespace {

// The mean slope over all cells, in degrees, from the height differences along each cell's south and west edges.
double meanSlopeDeg(const HeightGrid& g) {
    double sum = 0.0;
    for (int64_t j = 0; j < g.cellsY(); ++j)
        for (int64_t i = 0; i < g.cellsX(); ++i) {
            const double dx = (double(g.at(i + 1, j)) - g.at(i, j)) / g.cellSizeXM();
            const double dy = (double(g.at(i, j + 1)) - g.at(i, j)) / g.cellSizeYM();
            sum += std::atan(std::hypot(dx, dy)) * 180.0 / 3.14159265358979323846;
        }
    return sum / double(g.cellsX() * g.cellsY());
}

}  // namespace

TEST_CASE("fractal terrain: the same seed gives the same heights, another seed others", "[heightfield][fractal]") {
    FractalTerrainOptions o;
    o.size = 129;
    const HeightGrid a = fractalTerrain(o), b = fractalTerrain(o);
    CHECK(a.copyHeights() == b.copyHeights());
    o.seed = 2;
    const HeightGrid c = fractalTerrain(o);
    const std::vector<float> za = a.copyHeights(), zc = c.copyHeights();
    int64_t differ = 0;
    for (size_t k = 0; k < za.size(); ++k) differ += za[k] != zc[k];
    CHECK(differ > int64_t(za.size()) * 9 / 10);
}

TEST_CASE("fractal terrain: a few heights pinned, so a change to the generator is seen", "[heightfield][fractal]") {
    FractalTerrainOptions o;
    o.size = 9;
    const HeightGrid g = fractalTerrain(o);
    // The lowest vertex is moved to 0 m. The others are the values the generator gave when it was written;
    // they are computed in double from integer hashes, so only the last float rounding may vary.
    CHECK(g.minHeightM() == 0.0f);
    const double expected[] = {35.0780334, 35.921627, 85.8290024, 32.1896629, 18.294838, 23.6912918};
    for (size_t k = 0; k < 6; ++k) {
        INFO("vertex " << k * 13);
        CHECK(g.at(int64_t(k * 13) % 9, int64_t(k * 13) / 9) == Approx(expected[k]).epsilon(1e-6));
    }
}

TEST_CASE("fractal terrain: size, cell size and a mountain-like relief", "[heightfield][fractal]") {
    for (int64_t size : {65, 513}) {
        FractalTerrainOptions o;
        o.size = size;
        const HeightGrid g = fractalTerrain(o);
        INFO("size " << size);
        CHECK(g.width() == size);
        CHECK(g.height() == size);
        CHECK(g.cellSizeXM() == 30.0);
        CHECK(g.cellSizeYM() == 30.0);
        CHECK_FALSE(g.hasNodata());
        CHECK(g.minHeightM() == 0.0f);
        // Hills at 65 (1.9 km across), mountains at 513 (15 km across); never a spike field or a plain.
        CHECK(g.maxHeightM() > 100.0f);
        CHECK(g.maxHeightM() < 10000.0f);
        const double slope = meanSlopeDeg(g);
        CHECK(slope > 3.0);
        CHECK(slope < 45.0);
        for (float h : g.copyHeights()) REQUIRE(std::isfinite(h));
    }
}

TEST_CASE("fractal terrain: bigger grids have more relief but not without bound", "[heightfield][fractal]") {
    FractalTerrainOptions o;
    o.size = 65;
    const float small = fractalTerrain(o).maxHeightM();
    o.size = 1025;
    const float large = fractalTerrain(o).maxHeightM();
    CHECK(large > small);
    CHECK(large < 12000.0f);
}

TEST_CASE("fractal terrain: only 2^n + 1 sizes and positive options", "[heightfield][fractal]") {
    CHECK(isFractalTerrainSize(3));
    CHECK(isFractalTerrainSize(513));
    CHECK(isFractalTerrainSize(32769));
    CHECK_FALSE(isFractalTerrainSize(2));
    CHECK_FALSE(isFractalTerrainSize(512));
    CHECK_FALSE(isFractalTerrainSize(1000));
    FractalTerrainOptions o;
    o.size = 100;
    CHECK_THROWS_AS(fractalTerrain(o), GridError);
    o.size = 17;
    o.cellSizeM = 0.0;
    CHECK_THROWS_AS(fractalTerrain(o), GridError);
    o.cellSizeM = 30.0;
    o.roughness = std::nan("");
    CHECK_THROWS_AS(fractalTerrain(o), GridError);
}

TEST_CASE("fractal terrain: its memory is known before it is built", "[heightfield][fractal]") {
    for (int64_t size : {3, 5, 65, 257}) {
        FractalTerrainOptions o;
        o.size = size;
        INFO("size " << size);
        const HeightGrid g = fractalTerrain(o);
        CHECK(g.storage() == HeightStorage::Float32);
        CHECK(fractalTerrainBytes(size) == int64_t(g.memoryBytes()));
        o.integerHeights = true;
        const HeightGrid whole = fractalTerrain(o);
        CHECK(whole.storage() == HeightStorage::Int16);
        CHECK(fractalTerrainBytes(size, true) == int64_t(whole.memoryBytes()));
    }
    // 32769^2 float heights alone are 4 GiB; the int16 maximum pyramid adds a sixth of that (2 bytes per 4
    // cells, and a third more for the coarser levels), the minimum pyramid from level 2 a quarter as much
    // again. Integer heights halve the heights' share.
    const double gib = 1024.0 * 1024 * 1024;
    const double big = double(fractalTerrainBytes(32769));
    CHECK(big > 4.0 * gib * 1.205);
    CHECK(big < 4.0 * gib * 1.211);
    const double whole = double(fractalTerrainBytes(32769, true));
    CHECK(whole > 2.0 * gib * 1.413);
    CHECK(whole < 2.0 * gib * 1.42);
}
