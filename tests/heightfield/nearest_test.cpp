// The nearest-square method against its definition: each cell a flat square at the mean of its four corners,
// with vertical walls between squares (computed here from the corners, not by the method's own code).
#include "heightfield/traversal.h"

#include <catch2/catch.hpp>

#include <vector>

using namespace terracast;

TEST_CASE("Nearest squares: a cell's square lies at the mean of its corners, walled at its edges", "[heightfield]") {
    // Three cells in a row (4 x 2 vertices), their squares at 1.75, 3.5 and 8.5 m.
    const std::vector<float> z = {0.0f, 1.0f, 4.0f, 10.0f, 2.0f, 4.0f, 5.0f, 15.0f};
    const HeightGrid g(4, 2, 1.0, 1.0, z);
    auto meanOf = [&](int i) { return 0.25 * (z[size_t(i)] + z[size_t(i + 1)] + z[size_t(4 + i)] + z[size_t(5 + i)]); };
    for (int cell = 0; cell < 3; ++cell) {
        const double level = meanOf(cell);
        INFO("cell " << cell << " at " << level << " m");
        // Straight down from 100 m anywhere over the cell: the square, at t = 100 - level.
        for (const double u : {0.1, 0.5, 0.9}) {
            const auto hit = intersect(g, Ray{{cell + u, 0.37, 100.0}, {0.0, 0.0, -1.0}}, {0.0, 1e9}, CellMethod::Nearest);
            REQUIRE(hit);
            CHECK(hit->pointM.z == Approx(level).margin(1e-5));
            CHECK(hit->normal.z == Approx(1.0));
        }
    }
    // Along x, over the first square (1.75 m), just under and just over the middle one (3.5 m): the lower ray
    // meets the middle square's wall at x = 1; the higher passes over it and meets the third square's wall
    // (8.5 m) at x = 2.
    const double first = meanOf(0), middle = meanOf(1), third = meanOf(2);
    REQUIRE(first < middle - 0.2);
    REQUIRE(third > middle + 0.2);
    const auto low = intersect(g, Ray{{0.2, 0.5, middle - 0.1}, {1.0, 0.0, 0.0}}, {0.0, 1e9}, CellMethod::Nearest);
    REQUIRE(low);
    CHECK(low->pointM.x == Approx(1.0).margin(1e-6));
    CHECK(low->normal.x == Approx(-1.0));
    const auto high = intersect(g, Ray{{0.2, 0.5, middle + 0.1}, {1.0, 0.0, 0.0}}, {0.0, 1e9}, CellMethod::Nearest);
    REQUIRE(high);
    CHECK(high->pointM.x == Approx(2.0).margin(1e-6));
}
