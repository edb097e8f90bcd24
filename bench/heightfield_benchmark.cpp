// Costs of the height-field core: each cell intersector on random cells and segments, one step of the DDA walk,
// whole rays through the maximum pyramid against the flat walk on a fractal grid, and camera rays in bundles
// against ray by ray. Run as
//   build/bench/terracast-microbench --benchmark_filter=Cell   (or Dda, Pyramid, CameraBundle)
#include "heightfield/cell_intersectors.h"

#include "tracer/core/angles.h"
#include "heightfield/fractal_terrain.h"
#include "heightfield/traversal.h"
#include "tracer/measure/bench.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <optional>
#include <random>
#include <span>
#include <string>
#include <vector>

using namespace terracast;

namespace {

constexpr size_t kSamples = 4096;  // a power of two: cycled through with a mask

// Random cells (corners within 100 m) with random segments crossing them from one edge to another, the ray's
// height at entry and exit drawn over the cell's height range widened by 20 m, so about half the segments hit.
template <class Real>
struct CellSamples {
    std::vector<CellCorners<Real>> corners;
    std::vector<CellSegment<Real>> segments;

    CellSamples() {
        std::mt19937_64 rng(7);
        std::uniform_real_distribution<double> U(0.0, 1.0);
        for (size_t k = 0; k < kSamples; ++k) {
            const double h[4] = {100 * U(rng), 100 * U(rng), 100 * U(rng), 100 * U(rng)};
            const auto height = [&](double u, double v) {
                return h[0] * (1 - u) * (1 - v) + h[1] * u * (1 - v) + h[2] * (1 - u) * v + h[3] * u * v;
            };
            // Entry and exit points on two different edges of the unit square.
            const auto edgePoint = [&](int edge, double f) -> glm::dvec2 {
                switch (edge) {
                case 0: return {f, 0.0};
                case 1: return {1.0, f};
                case 2: return {f, 1.0};
                default: return {0.0, f};
                }
            };
            const int e0 = int(4 * U(rng)) & 3, e1 = (e0 + 1 + (int(3 * U(rng)) % 3)) & 3;
            const glm::dvec2 p0 = edgePoint(e0, U(rng)), p1 = edgePoint(e1, U(rng));
            const double lo = std::min({h[0], h[1], h[2], h[3]}) - 20.0, hi = std::max({h[0], h[1], h[2], h[3]}) + 20.0;
            const double z0 = lo + (hi - lo) * U(rng), z1 = lo + (hi - lo) * U(rng);
            // Parameterised by the horizontal distance in cells.
            const double length = std::max(glm::length(p1 - p0), 1e-3);
            CellSegment<Real> s;
            s.u0 = Real(p0.x);
            s.v0 = Real(p0.y);
            s.z0 = Real(z0);
            s.du = Real((p1.x - p0.x) / length);
            s.dv = Real((p1.y - p0.y) / length);
            s.dz = Real((z1 - z0) / length);
            s.length = Real(length);
            s.gEntry = Real(height(p0.x, p0.y) - z0);
            s.gExit = Real(height(p1.x, p1.y) - z1);
            segments.push_back(s);
            corners.push_back({Real(h[0]), Real(h[1]), Real(h[2]), Real(h[3])});
        }
    }
};

template <class Real, class Intersect>
void runCells(benchmark::State& state, Intersect intersect) {
    static const CellSamples<Real> samples;
    size_t k = 0, hits = 0;
    for (auto _ : state) {
        const auto s = intersect(samples.corners[k], samples.segments[k]);
        hits += s.has_value();
        benchmark::DoNotOptimize(s);
        k = (k + 1) & (kSamples - 1);
    }
    state.counters["hit_share"] = double(hits) / double(state.iterations());
    state.SetItemsProcessed(state.iterations());
}

void BM_CellBilinearFloat(benchmark::State& state) { runCells<float>(state, intersectBilinearCell<float>); }
void BM_CellBilinearDouble(benchmark::State& state) { runCells<double>(state, intersectBilinearCell<double>); }
void BM_CellBilinearLongDouble(benchmark::State& state) {
    runCells<long double>(state, intersectBilinearCell<long double>);
}
void BM_CellTrianglesFloat(benchmark::State& state) { runCells<float>(state, intersectTrianglesCell<float>); }
void BM_CellNearestFloat(benchmark::State& state) { runCells<float>(state, intersectNearestCell<float>); }
BENCHMARK(BM_CellBilinearFloat);
BENCHMARK(BM_CellBilinearDouble);
BENCHMARK(BM_CellBilinearLongDouble);
BENCHMARK(BM_CellTrianglesFloat);
BENCHMARK(BM_CellNearestFloat);

// One step of the tracer's cell walk: the flat traversal (no pyramid) of a horizontal ray 1 m above a flat grid
// of 4097 x 4097 cells, in a random direction from the centre, for 2048 cells' length; every cell is visited
// and passed over, so the time per item is the cost of one DDA step with its per-cell height test. (One corner
// vertex stands 2 m high so that the ray lies inside the grid's height range; no ray comes near it.)
void BM_DdaStep(benchmark::State& state) {
    constexpr int64_t kSize = 4097;
    static const HeightGrid grid = [] {
        std::vector<float> z(size_t(kSize * kSize), 0.0f);
        z.back() = 2.0f;
        return HeightGrid(kSize, kSize, 1.0, 1.0, std::move(z));
    }();
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Ray> rays(kSamples);
    for (auto& r : rays) {
        const double a = 2.0 * kPi * U(rng);
        r.origin = {0.5 * double(kSize - 1) + 0.3, 0.5 * double(kSize - 1) + 0.7, 1.0};
        r.dir = {std::cos(a), std::sin(a), 0.0};
    }
    TraceCounters counters;
    for (const Ray& r : rays) intersect(grid, r, {0.0, 2048.0}, CellMethod::Bilinear, &counters, Traversal::Flat);
    size_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(intersect(grid, rays[k], {0.0, 2048.0}, CellMethod::Bilinear, nullptr, Traversal::Flat));
        k = (k + 1) & (kSamples - 1);
    }
    // Items: cells walked (the same for every pass over the sample rays).
    state.SetItemsProcessed(int64_t(double(state.iterations()) * double(counters.cellsVisited) / double(kSamples)));
}
BENCHMARK(BM_DdaStep);

// Whole rays on a 2049 x 2049 fractal grid, aimed from 45 to 80 degrees above the horizon at random points of
// the surface, starting above the highest peak: the walk down to the hit, through the maximum pyramid
// (argument 0) or cell by cell (argument 1). The counters say how many cells were walked, how many pyramid
// blocks skipped and how many cells reached the intersector, per ray; with the pyramid, each skip is one
// climb through the levels above the cell where it starts.
void BM_PyramidDescent(benchmark::State& state) {
    static const HeightGrid grid = [] {
        FractalTerrainOptions o;
        o.size = 2049;
        return fractalTerrain(o);
    }();
    const Traversal traversal = state.range(0) == 0 ? Traversal::Pyramid : Traversal::Flat;
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Ray> rays(kSamples);
    const double top = grid.maxHeightM() + 10.0;
    for (auto& r : rays) {
        const double x = grid.extentXM() * (0.1 + 0.8 * U(rng)), y = grid.extentYM() * (0.1 + 0.8 * U(rng));
        const int64_t i = int64_t(x / grid.cellSizeXM()), j = int64_t(y / grid.cellSizeYM());
        const double az = 2.0 * kPi * U(rng);
        const double el = radians(45.0 + 35.0 * U(rng));
        const glm::dvec3 down{std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el)};
        const glm::dvec3 target{x, y, double(grid.at(i, j))};
        r.dir = down;
        r.origin = target - down * ((top - target.z) / std::sin(el));
    }
    TraceCounters counters;
    int64_t hits = 0;
    for (const Ray& r : rays) hits += intersect(grid, r, {0.0, kInfinity}, CellMethod::Bilinear, &counters, traversal).has_value();
    size_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(intersect(grid, rays[k], {0.0, kInfinity}, CellMethod::Bilinear, nullptr, traversal));
        k = (k + 1) & (kSamples - 1);
    }
    state.SetLabel(traversal == Traversal::Pyramid ? "pyramid" : "flat");
    state.counters["cells_walked"] = double(counters.cellsVisited) / double(kSamples);
    state.counters["blocks_skipped"] = double(counters.blocksSkipped) / double(kSamples);
    state.counters["cells_tested"] = double(counters.cellsTested) / double(kSamples);
    state.counters["hit_share"] = double(hits) / double(kSamples);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PyramidDescent)->Arg(0)->Arg(1);

// The camera rays of `terracast bench` on its 2049 x 2049 fractal grid (1024 x 768 pixels, corner camera for
// the first argument 0, grazing camera for 1), one 8 x 8 tile of pixels per iteration: traced as one bundle
// through intersectBundle (second argument 1) or ray by ray through intersect (0). Same rays, same hits;
// items are rays.
void BM_CameraBundle(benchmark::State& state) {
    static const HeightGrid grid = [] {
        FractalTerrainOptions o;
        o.size = 2049;
        return fractalTerrain(o);
    }();
    constexpr int kWidth = 1024, kHeight = 768, kSide = 8, kBundle = kSide * kSide;
    const PinholeCamera camera =
        benchCamera(grid, state.range(0) == 0 ? BenchCamera::Corner : BenchCamera::Grazing, double(kWidth) / kHeight);
    const bool bundled = state.range(1) == 1;
    std::vector<Ray> rays;  // tile after tile
    for (int ty = 0; ty < kHeight; ty += kSide)
        for (int tx = 0; tx < kWidth; tx += kSide)
            for (int y = ty; y < ty + kSide; ++y)
                for (int x = tx; x < tx + kSide; ++x)
                    rays.push_back(camera.generate((x + 0.5) / kWidth, (y + 0.5) / kHeight, double(kWidth) / kHeight));
    std::vector<std::optional<HeightFieldHit>> hits(kBundle);
    const size_t tiles = rays.size() / kBundle;
    size_t k = 0;
    for (auto _ : state) {
        const std::span<const Ray> tile(rays.data() + k * kBundle, kBundle);
        if (bundled) {
            intersectBundle(grid, tile, {0.0, kInfinity}, CellMethod::Bilinear, hits);
        } else {
            for (size_t r = 0; r < tile.size(); ++r)
                hits[r] = intersect(grid, tile[r], {0.0, kInfinity}, CellMethod::Bilinear);
        }
        benchmark::DoNotOptimize(hits.data());
        k = k + 1 == tiles ? 0 : k + 1;
    }
    state.SetLabel(std::string(state.range(0) == 0 ? "corner" : "grazing") + (bundled ? ", bundles" : ", ray by ray"));
    state.SetItemsProcessed(state.iterations() * kBundle);
}
BENCHMARK(BM_CameraBundle)->Args({0, 0})->Args({0, 1})->Args({1, 0})->Args({1, 1});

}  // namespace
