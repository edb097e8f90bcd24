// Smooth shading normals against a paraboloid's analytic normals (exact for a surface whose gradient is linear),
// continuity across cell edges where each cell's own normal jumps, and one-sided differences beside holes.
#include "heightfield/fractal_terrain.h"
#include "heightfield/shading_normals.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace terracast;

namespace {

// The unit normal of a bilinear cell at (u, v) from its corners: what shading read before smooth normals.
glm::dvec3 cellNormal(const HeightGrid& g, int64_t i, int64_t j, double u, double v) {
    const double h00 = g.at(i, j), h10 = g.at(i + 1, j), h01 = g.at(i, j + 1), h11 = g.at(i + 1, j + 1);
    const double dhdu = (h10 - h00) * (1.0 - v) + (h11 - h01) * v, dhdv = (h01 - h00) * (1.0 - u) + (h11 - h10) * u;
    return glm::normalize(glm::dvec3(-dhdu / g.cellSizeXM(), -dhdv / g.cellSizeYM(), 1.0));
}

double angleDeg(const glm::dvec3& a, const glm::dvec3& b) {
    return std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * 180.0 / M_PI;
}

}  // namespace

TEST_CASE("Smooth normals are a paraboloid's exact normals inside the grid, where each cell's own are not",
          "[heightfield][normals]") {
    // z = a (x - 20)^2 + b (y - 30)^2 on 41 x 31 vertices, cells 1 m by 2 m (x, y in metres).
    const int w = 41, h = 31;
    const double dx = 1.0, dy = 2.0, a = 0.02, b = -0.01;
    std::vector<float> heights(size_t(w) * h);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double x = i * dx, y = j * dy;
            heights[size_t(j) * w + size_t(i)] = float(a * (x - 20.0) * (x - 20.0) + b * (y - 30.0) * (y - 30.0));
        }
    const HeightGrid g(w, h, dx, dy, heights, {}, StoragePolicy::Float32);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double worstSmooth = 0.0, worstCell = 0.0;
    for (int k = 0; k < 2000; ++k) {
        // Cells whose corners all have both neighbours: central differences everywhere.
        const int64_t i = 1 + int64_t(unit(rng) * (w - 3)), j = 1 + int64_t(unit(rng) * (h - 3));
        const double u = unit(rng), v = unit(rng);
        const double x = (double(i) + u) * dx, y = (double(j) + v) * dy;
        const glm::dvec3 exact = glm::normalize(glm::dvec3(-2.0 * a * (x - 20.0), -2.0 * b * (y - 30.0), 1.0));
        worstSmooth = std::max(worstSmooth, angleDeg(smoothNormal(g, i, j, u, v), exact));
        worstCell = std::max(worstCell, angleDeg(cellNormal(g, i, j, u, v), exact));
    }
    INFO("worst error: smooth " << worstSmooth << " degrees, each cell's own " << worstCell << " degrees");
    // The heights are floats: their rounding leaves about 1e-5 degrees.
    CHECK(worstSmooth < 1e-4);
    CHECK(worstCell > 0.5);
}

TEST_CASE("Smooth normals are continuous across cell edges and equal the vertices' own at corners",
          "[heightfield][normals]") {
    FractalTerrainOptions o;
    o.size = 33;
    o.seed = 9;
    o.cellSizeM = 10.0;
    const HeightGrid g = fractalTerrain(o);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double edgeGap = 0.0, cellGap = 0.0;
    for (int k = 0; k < 500; ++k) {
        const int64_t i = int64_t(unit(rng) * double(g.cellsX() - 1)), j = int64_t(unit(rng) * double(g.cellsY() - 1));
        const double s = unit(rng);
        // The edge x = i + 1 seen from the cell on its west and the one on its east; y = j + 1 from south and north.
        edgeGap = std::max({edgeGap, glm::length(smoothNormal(g, i, j, 1.0, s) - smoothNormal(g, i + 1, j, 0.0, s)),
                            glm::length(smoothNormal(g, i, j, s, 1.0) - smoothNormal(g, i, j + 1, s, 0.0))});
        cellGap = std::max(cellGap, glm::length(cellNormal(g, i, j, 1.0, s) - cellNormal(g, i + 1, j, 0.0, s)));
        // At a corner: the vertex's normal from its central differences, written out here.
        const int64_t ci = i + 1, cj = j + 1;
        const double gx = (double(g.at(ci + 1, cj)) - double(g.at(ci - 1, cj))) / (2.0 * g.cellSizeXM());
        const double gy = (double(g.at(ci, cj + 1)) - double(g.at(ci, cj - 1))) / (2.0 * g.cellSizeYM());
        const glm::dvec3 vertex = glm::normalize(glm::dvec3(-gx, -gy, 1.0));
        CHECK(glm::length(smoothNormal(g, i, j, 1.0, 1.0) - vertex) < 1e-12);
        CHECK(glm::length(smoothNormal(g, ci, cj, 0.0, 0.0) - vertex) < 1e-12);
    }
    INFO("largest jump across an edge: smooth " << edgeGap << ", each cell's own " << cellGap);
    CHECK(edgeGap < 1e-12);
    CHECK(cellGap > 0.05);
}

TEST_CASE("Beside a hole and at the grid's edge, a vertex's gradient is one-sided", "[heightfield][normals]") {
    // Heights 3x + 5y on 6 x 5 vertices of 1 m, with vertex (3, 2) missing.
    const int w = 6, h = 5;
    std::vector<float> heights(size_t(w) * h);
    std::vector<uint8_t> valid(size_t(w) * h, 1);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) heights[size_t(j) * w + size_t(i)] = float(3 * i + 5 * j);
    valid[size_t(2) * w + 3] = 0;
    heights[size_t(2) * w + 3] = 1e6f;  // whatever a hole holds must not be read
    const HeightGrid g(w, h, 1.0, 1.0, heights, valid, StoragePolicy::Float32);
    for (const auto& [i, j] : {std::pair{2, 2}, std::pair{4, 2}, std::pair{3, 1}, std::pair{3, 3}, std::pair{0, 0},
                              std::pair{5, 4}, std::pair{0, 3}}) {
        INFO("vertex " << i << "," << j);
        const glm::dvec2 gradient = vertexGradient(g, i, j);
        CHECK(gradient.x == Approx(3.0));
        CHECK(gradient.y == Approx(5.0));
    }
}
