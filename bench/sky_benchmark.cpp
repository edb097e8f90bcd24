// Costs of the sky: table builds, a sky and an aerial-perspective lookup, and a terrain render under the
// physical sky against the same render under a flat one (same rays, same sky-visibility samples).
#include "loaders/dem_loader.h"
#include "tracer/sky/atmosphere.h"
#include "tracer/terrain/camera.h"
#include "tracer/sky/sky.h"
#include "tracer/terrain/surface.h"
#include "tracer/terrain/terrain_renderer.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace terracast;

namespace {

std::vector<glm::dvec3> randomDirections(size_t n) {
    std::mt19937_64 rng(7);
    std::normal_distribution<double> g;
    std::vector<glm::dvec3> dirs(n);
    for (auto& d : dirs) d = glm::normalize(glm::dvec3(g(rng), g(rng), g(rng)));
    return dirs;
}

const glm::dvec3 kSun = glm::normalize(glm::dvec3(0.3, -0.6, 0.4));

void BM_TransmittanceTableBuild(benchmark::State& state) {
    for (auto _ : state) {
        TransmittanceTable t{AtmosphereParameters{}};
        benchmark::DoNotOptimize(&t);
    }
}
BENCHMARK(BM_TransmittanceTableBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SkyTablesBuild(benchmark::State& state) {
    const auto t = sharedTransmittanceTable(AtmosphereParameters{});
    for (auto _ : state) {
        SkyTables sky(t, 1500.0, kSun);
        benchmark::DoNotOptimize(&sky);
    }
}
BENCHMARK(BM_SkyTablesBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SkyLookup(benchmark::State& state) {
    const SkyTables sky(sharedTransmittanceTable(AtmosphereParameters{}), 1500.0, kSun);
    const auto dirs = randomDirections(4096);
    size_t k = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(sky.radiance(dirs[k]));
        k = (k + 1) & 4095;
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_SkyLookup);

void BM_AerialLookup(benchmark::State& state) {
    const SkyTables sky(sharedTransmittanceTable(AtmosphereParameters{}), 1500.0, kSun);
    const auto dirs = randomDirections(4096);
    size_t k = 0;
    glm::vec3 t, in;
    for (auto _ : state) {
        sky.aerial(dirs[k], 1000.0 + 20.0 * double(k), t, in);
        benchmark::DoNotOptimize(t);
        benchmark::DoNotOptimize(in);
        k = (k + 1) & 4095;
    }
    state.SetItemsProcessed(int64_t(state.iterations()));
}
BENCHMARK(BM_AerialLookup);

// St Helens at 1024x768 from the automatic view, 2 threads, 4 sky-visibility rays per hit: the flat sky then
// the physical one in each iteration, timed separately; the counter `physical_over_flat` is their ratio. The
// physical render's time includes building its sky tables (the transmittance table is built once per process,
// see BM_TransmittanceTableBuild).
void BM_RenderPhysicalOverFlat(benchmark::State& state) {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    const TerrainSurface surface(dem.grid, SurfaceMethod::Bilinear, 2);
    TerrainRenderSettings s;
    s.width = 1024;
    s.height = 768;
    s.threads = 2;
    s.camera = autoCamera(dem.grid, 1024.0 / 768.0);
    s.sky.samples = 4;
    sharedTransmittanceTable(AtmosphereParameters{});
    double flatS = 0.0, physicalS = 0.0;
    for (auto _ : state) {
        for (const SkyKind kind : {SkyKind::Flat, SkyKind::Physical}) {
            s.sky.kind = kind;
            const auto start = std::chrono::steady_clock::now();
            benchmark::DoNotOptimize(renderTerrain(dem.grid, surface, s).rgb.data());
            (kind == SkyKind::Flat ? flatS : physicalS) +=
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        }
    }
    state.counters["flat_s"] = flatS / double(state.iterations());
    state.counters["physical_s"] = physicalS / double(state.iterations());
    state.counters["physical_over_flat"] = physicalS / flatS;
}
BENCHMARK(BM_RenderPhysicalOverFlat)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(5);

}  // namespace
