// Costs of the sampling library: building precomputed patterns, drawing per-pixel samples, warping.
#include "tracer/sampling/rng.h"
#include "tracer/sampling/samplers.h"
#include "tracer/sampling/warps.h"

#include <benchmark/benchmark.h>

using namespace terracast;

namespace {

void BM_PoissonDisk(benchmark::State& state) {
    const int n = int(state.range(0));
    const bool toroidal = state.range(1) != 0;
    PoissonDiskOptions o;
    o.radius = poissonDiskRadiusForCount(n, toroidal);
    o.toroidal = toroidal;
    size_t points = 0;
    for (auto _ : state) {
        ++o.seed;
        const auto p = poissonDiskPattern(o);
        points += p.size();
        benchmark::DoNotOptimize(p.data());
    }
    state.counters["points"] = double(points) / double(state.iterations());
    state.SetItemsProcessed(int64_t(points));
}
BENCHMARK(BM_PoissonDisk)->Args({1024, 0})->Args({1024, 1})->Args({16384, 1})->Unit(benchmark::kMillisecond);

void BM_PoissonDiskExactCount(benchmark::State& state) {
    uint64_t seed = 0;
    for (auto _ : state) benchmark::DoNotOptimize(poissonDiskPatternWithCount(int(state.range(0)), ++seed, true).data());
}
BENCHMARK(BM_PoissonDiskExactCount)->Arg(64)->Arg(1024)->Unit(benchmark::kMillisecond);

void BM_BestCandidateDirections(benchmark::State& state) {
    uint64_t seed = 0;
    for (auto _ : state) benchmark::DoNotOptimize(bestCandidateDirections(int(state.range(0)), -1.0, ++seed).data());
}
BENCHMARK(BM_BestCandidateDirections)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);

// One value of a per-sample stream, keyed by pixel and sample as a renderer draws them.
void BM_RandomStreamDraw(benchmark::State& state) {
    int64_t i = 0;
    double sum = 0.0;
    for (auto _ : state) {
        sum += RandomStream(1, i & 1023, i >> 10, uint64_t(i & 15)).uniform(3);
        ++i;
    }
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RandomStreamDraw);

// Consecutive values from one stream.
void BM_RandomStreamNext(benchmark::State& state) {
    RandomStream s(1, 2, 3, 4);
    double sum = 0.0;
    for (auto _ : state) sum += s.next();
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RandomStreamNext);

void BM_PixelSample(benchmark::State& state) {
    const PixelSampler sampler(SamplePattern(state.range(0)), 16, 1);
    int64_t i = 0;
    glm::dvec2 sum{0.0};
    for (auto _ : state) {
        sum += sampler.sample(i & 1023, i >> 10, int(i & 15), 1);
        ++i;
    }
    benchmark::DoNotOptimize(sum);
    state.SetLabel(samplePatternName(SamplePattern(state.range(0))));
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PixelSample)->DenseRange(0, 4);

void BM_WarpConcentricDisk(benchmark::State& state) {
    RandomStream s(5);
    glm::dvec2 sum{0.0};
    for (auto _ : state) sum += squareToConcentricDisk(s.next2());
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_WarpConcentricDisk);

void BM_WarpPhongLobe(benchmark::State& state) {
    RandomStream s(6);
    glm::dvec3 sum{0.0};
    for (auto _ : state) sum += squareToPhongLobe(s.next2(), 50.0);
    benchmark::DoNotOptimize(sum);
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_WarpPhongLobe);

}  // namespace
