// The counter-based random stream: reproducible from its key alone, different for different keys, uniform.
#include "support/statistics.h"
#include "tracer/sampling/rng.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <set>

using namespace terracast;
using namespace terracast::testing;

TEST_CASE("A random stream is a function of its key and dimension only", "[tracer][sampling]") {
    // Two streams built apart, read in different orders, agree value for value.
    RandomStream sequential(42, 17, -3, 5);
    const RandomStream direct(42, 17, -3, 5);
    std::vector<double> forward;
    for (int d = 0; d < 64; ++d) forward.push_back(sequential.next());
    CHECK(sequential.position() == 64);
    for (int d = 63; d >= 0; --d) CHECK(direct.uniform(uint64_t(d)) == forward[size_t(d)]);
    CHECK(direct.uniform2(10) == glm::dvec2(forward[10], forward[11]));
    // float and double views of one dimension come from the same bits.
    CHECK(std::abs(double(direct.uniformFloat(7)) - direct.uniform(7)) < 0x1.0p-24);
}

TEST_CASE("Random streams with different seeds, pixels, samples or dimensions differ", "[tracer][sampling]") {
    // Values that change with every key component: all distinct among thousands.
    std::set<double> seen;
    int drawn = 0;
    for (uint64_t seed : {1ull, 2ull})
        for (int64_t px : {0, 1, -1})
            for (int64_t py : {0, 1, 1000})
                for (uint64_t k : {0ull, 1ull, 2ull, 1ull << 40})
                    for (uint64_t d = 0; d < 16; ++d, ++drawn) seen.insert(RandomStream(seed, px, py, k).uniform(d));
    CHECK(int(seen.size()) == drawn);

    // Seed 1 and seed 2 over the same pixels are uncorrelated: |r| within five standard errors of 0.
    const int n = 100000;
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (int i = 0; i < n; ++i) {
        const double a = RandomStream(1, i % 400, i / 400).uniform(0) - 0.5;
        const double b = RandomStream(2, i % 400, i / 400).uniform(0) - 0.5;
        sa += a, sb += b, saa += a * a, sbb += b * b, sab += a * b;
    }
    const double r = (sab - sa * sb / n) / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
    CHECK(std::abs(r) < 5.0 / std::sqrt(double(n)));
}

TEST_CASE("Random stream values are uniform over pixels and along dimensions", "[tracer][sampling]") {
    // One value per pixel of a 1000 x 1000 image, as a renderer draws them: chi-square over 100 bins.
    const int bins = 100;
    std::vector<int64_t> counts(bins, 0), countsFloat(bins, 0);
    for (int y = 0; y < 1000; ++y)
        for (int x = 0; x < 1000; ++x) {
            const RandomStream s(7, x, y, 0);
            const double u = s.uniform(0);
            const float f = s.uniformFloat(1);
            REQUIRE(u >= 0.0);
            REQUIRE(u < 1.0);
            REQUIRE(f >= 0.0f);
            REQUIRE(f < 1.0f);
            ++counts[size_t(u * bins)];
            ++countsFloat[size_t(f * bins)];
        }
    CHECK(chiSquare(counts, 1e6 / bins) < chiSquareLimit(bins - 1));
    CHECK(chiSquare(countsFloat, 1e6 / bins) < chiSquareLimit(bins - 1));

    // Pairs of consecutive dimensions fill the square evenly: chi-square over 32 x 32 cells.
    std::vector<int64_t> cells(32 * 32, 0);
    RandomStream stream(11, 3, 4, 5);
    for (int i = 0; i < 500000; ++i) {
        const glm::dvec2 p = stream.next2();
        ++cells[size_t(int(p.y * 32) * 32 + int(p.x * 32))];
    }
    CHECK(chiSquare(cells, 500000.0 / cells.size()) < chiSquareLimit(int(cells.size()) - 1));

    // Kolmogorov-Smirnov along the sample index.
    std::vector<double> values;
    for (uint64_t k = 0; k < 100000; ++k) values.push_back(RandomStream(3, 10, 20, k).uniform(2));
    CHECK(ksUniformDistance(values) * std::sqrt(double(values.size())) < 1.95);
}

TEST_CASE("Bits map to the unit interval without ever reaching 1", "[tracer][sampling]") {
    CHECK(unitDoubleFromBits(0) == 0.0);
    CHECK(unitFloatFromBits(0) == 0.0f);
    CHECK(unitDoubleFromBits(~0ull) == 1.0 - 0x1.0p-53);
    CHECK(unitFloatFromBits(~0ull) == 1.0f - 0x1.0p-24f);
    CHECK(unitDoubleFromBits(1ull << 63) == 0.5);
}

TEST_CASE("Random integers below n are uniform", "[tracer][sampling]") {
    RandomStream stream(5);
    const int n = 7, draws = 700000;
    std::vector<int64_t> counts(n, 0);
    for (int i = 0; i < draws; ++i) {
        const uint64_t k = stream.nextIndex(n);
        REQUIRE(k < uint64_t(n));
        ++counts[size_t(k)];
    }
    CHECK(chiSquare(counts, double(draws) / n) < chiSquareLimit(n - 1));
    CHECK(stream.nextIndex(1) == 0);
}
