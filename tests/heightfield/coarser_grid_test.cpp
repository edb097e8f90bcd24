// Coarser grids of a level of detail: vertex (i, j) is the source's vertex (2i, 2j), clamped to its last row and
// column, with its height and validity, cells twice as wide, for int16 and float storage and odd cell counts.
#include "heightfield/coarser_grid.h"

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace terracast;

namespace {

// A w x h grid of distinct heights (whole metres when `whole`, so that it stores int16 codes), with a hole.
HeightGrid sample(int64_t w, int64_t h, bool whole) {
    std::vector<float> z(size_t(w * h));
    std::vector<uint8_t> valid(z.size(), 1);
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i)
            z[size_t(j * w + i)] = float(100 + 3 * i + 7 * j) + (whole ? 0.0f : 0.25f * float((i * j) % 3));
    if (w >= 6 && h >= 4) {
        valid[size_t(2 * w + 4)] = 0;  // vertex (4, 2): kept by the coarse grid as its (2, 1)
        valid[size_t(3 * w + 5)] = 0;  // vertex (5, 3): dropped
    }
    return HeightGrid(w, h, 10.0, 12.5, std::move(z), std::move(valid));
}

}  // namespace

TEST_CASE("Coarser grid: every other vertex, clamped to the last, with heights and holes", "[heightfield][lod]") {
    for (const bool whole : {true, false})
        for (const auto& [w, h] : {std::pair<int64_t, int64_t>{9, 7}, {10, 8}, {3, 3}}) {
            INFO(w << " x " << h << (whole ? " whole metres" : " floats"));
            const HeightGrid g = sample(w, h, whole);
            CHECK(g.storage() == (whole ? HeightStorage::Int16 : HeightStorage::Float32));
            const HeightGrid c = coarserGrid(g);
            // Cells: half as many, rounded up (an odd count's last coarse cell reaches past the edge).
            CHECK(c.cellsX() == (g.cellsX() + 1) / 2);
            CHECK(c.cellsY() == (g.cellsY() + 1) / 2);
            CHECK(c.cellSizeXM() == 20.0);
            CHECK(c.cellSizeYM() == 25.0);
            int64_t differ = 0;
            for (int64_t j = 0; j < c.height(); ++j)
                for (int64_t i = 0; i < c.width(); ++i) {
                    const int64_t si = std::min(2 * i, w - 1), sj = std::min(2 * j, h - 1);
                    differ += c.vertexValid(i, j) != g.vertexValid(si, sj);
                    if (g.vertexValid(si, sj))
                        differ += std::bit_cast<uint32_t>(c.at(i, j)) != std::bit_cast<uint32_t>(g.at(si, sj));
                }
            CHECK(differ == 0);
            if (w >= 9) {
                CHECK_FALSE(c.vertexValid(2, 1));
                CHECK_FALSE(c.cellValid(1, 0));
            }
        }
    CHECK_THROWS_AS(coarserGrid(sample(2, 5, true)), GridError);
}
