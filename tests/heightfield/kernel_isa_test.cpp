// The traversal kernels compiled for baseline x86-64 and for AVX2 return the same bits: nearest hits (every
// field), occlusion verdicts, counters and bundles, for every cell method and both traversals.
#include "heightfield/fractal_terrain.h"
#include "heightfield/traversal.h"
#include "loaders/dem_loader.h"
#include "support/brute_force.h"

#include <catch2/catch.hpp>

#include <random>
#include <vector>

using namespace terracast;
using namespace terracast::testing;

namespace {

// Everything one instruction set gives for a set of rays.
struct Results {
    std::vector<std::optional<HeightFieldHit>> hits, countedHits, bundleHits;
    std::vector<char> blocked;
    std::vector<TraceCounters> counters;
};

// Restores automatic choice when a test ends, whatever it chose.
struct IsaGuard {
    KernelIsa saved = kernelIsa();
    ~IsaGuard() { setKernelIsa(saved); }
};

std::vector<Ray> mixedRays(const HeightGrid& g, int n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    const double relief = std::max(1.0, double(g.maxHeightM()) - g.minHeightM());
    std::vector<Ray> rays;
    // Bundles of 16 from one origin above and outside the grid (camera tiles), then single rays of all kinds.
    for (int b = 0; b < n / 32; ++b) {
        const glm::dvec3 eye{g.extentXM() * (1.4 * U(rng) - 0.2), g.extentYM() * (1.4 * U(rng) - 0.2),
                             g.maxHeightM() + relief * (0.02 + U(rng))};
        for (int k = 0; k < 16; ++k) {
            const glm::dvec3 target{g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + relief * U(rng)};
            rays.push_back(Ray{eye, glm::normalize(target - eye)});
        }
    }
    while (int(rays.size()) < n) {
        const glm::dvec3 o{g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM() + relief * (1.2 * U(rng))};
        const double az = 2.0 * M_PI * U(rng), el = (U(rng) - 0.6) * M_PI / 2.0;
        const glm::dvec3 d = rays.size() % 7 == 0 ? glm::dvec3(std::cos(az), std::sin(az), 0.0)
                                                  : glm::dvec3(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el),
                                                               std::sin(el));
        rays.push_back(Ray{o, d});
    }
    return rays;
}

Results traceAll(const HeightGrid& g, const std::vector<Ray>& rays, CellMethod m, Traversal tr) {
    Results r;
    const size_t n = rays.size();
    r.hits.resize(n);
    r.countedHits.resize(n);
    r.bundleHits.resize(n);
    r.blocked.resize(n);
    r.counters.resize(n);
    for (size_t k = 0; k < n; ++k) {
        r.hits[k] = intersect(g, rays[k], {0.0, kInfinity}, m, nullptr, tr);
        r.countedHits[k] = intersect(g, rays[k], {0.0, kInfinity}, m, &r.counters[k], tr);
        r.blocked[k] = occluded(g, rays[k], {0.0, kInfinity}, m, nullptr, tr);
    }
    for (size_t k = 0; k < n; k += 16) {
        const size_t len = std::min<size_t>(16, n - k);
        intersectBundle(g, std::span<const Ray>(rays.data() + k, len), {0.0, kInfinity}, m,
                        std::span<std::optional<HeightFieldHit>>(r.bundleHits.data() + k, len), nullptr, tr);
    }
    return r;
}

void requireSameHit(const std::optional<HeightFieldHit>& a, const std::optional<HeightFieldHit>& b) {
    REQUIRE(a.has_value() == b.has_value());
    if (!a) return;
    REQUIRE(a->t == b->t);
    REQUIRE(a->pointM == b->pointM);
    REQUIRE(a->normal == b->normal);
    REQUIRE(a->cellX == b->cellX);
    REQUIRE(a->cellY == b->cellY);
    REQUIRE(a->u == b->u);
    REQUIRE(a->v == b->v);
    REQUIRE(a->errorM == b->errorM);
}

// Returns the number of nearest hits, so callers can require that the rays meet the terrain.
int64_t requireSameOnBothIsas(const HeightGrid& g, int n, uint64_t seed) {
    const std::vector<Ray> rays = mixedRays(g, n, seed);
    int64_t hits = 0;
    for (CellMethod m : allCellMethods())
        for (Traversal tr : {Traversal::Pyramid, Traversal::Flat}) {
            REQUIRE(setKernelIsa(KernelIsa::Baseline));
            const Results base = traceAll(g, rays, m, tr);
            REQUIRE(setKernelIsa(KernelIsa::Avx2));
            const Results wide = traceAll(g, rays, m, tr);
            for (size_t k = 0; k < rays.size(); ++k) {
                INFO("ray " << k << ", method " << cellMethodName(m) << (tr == Traversal::Flat ? ", flat" : ""));
                requireSameHit(base.hits[k], wide.hits[k]);
                requireSameHit(base.countedHits[k], wide.countedHits[k]);
                requireSameHit(base.bundleHits[k], wide.bundleHits[k]);
                REQUIRE(base.blocked[k] == wide.blocked[k]);
                REQUIRE(base.counters[k].cellsVisited == wide.counters[k].cellsVisited);
                REQUIRE(base.counters[k].cellsTested == wide.counters[k].cellsTested);
                REQUIRE(base.counters[k].blocksSkipped == wide.counters[k].blocksSkipped);
                REQUIRE(base.counters[k].ambiguous == wide.counters[k].ambiguous);
                hits += base.hits[k].has_value();
            }
        }
    return hits;
}

}  // namespace

TEST_CASE("Only instruction sets the processor has can be chosen", "[heightfield][isa]") {
    IsaGuard guard;
    CHECK(setKernelIsa(KernelIsa::Baseline));
    CHECK(kernelIsa() == KernelIsa::Baseline);
    if (setKernelIsa(KernelIsa::Avx2)) {
        CHECK(kernelIsa() == KernelIsa::Avx2);
    } else {
        CHECK(kernelIsa() == KernelIsa::Baseline);  // refused, nothing changed
    }
    CHECK(std::string(kernelIsaName(KernelIsa::Avx2)) == "avx2");
}

TEST_CASE("The AVX2 kernels return the baseline kernels' bits", "[heightfield][isa]") {
    IsaGuard guard;
    if (!setKernelIsa(KernelIsa::Avx2)) {
        WARN("this build or processor has no AVX2 kernels; only the baseline ones run");
        return;
    }
    std::vector<HeightGrid> grids;
    FractalTerrainOptions fractal;
    fractal.size = 129;
    grids.push_back(fractalTerrain(fractal));
    fractal.integerHeights = true;
    fractal.seed = 5;
    grids.push_back(fractalTerrain(fractal));
    REQUIRE(grids.back().storage() == HeightStorage::Int16);
    {
        // Heights in tenths of a metre, held as int16 codes of 0.1 m: decoded through a product that must round
        // to float as HeightGrid::at rounds it.
        const HeightGrid base = fractalTerrain(fractal);
        std::vector<float> z = base.copyHeights();
        for (float& h : z) h = float(std::round((double(h) + 1234.56) * 10.0) * 0.1);
        grids.emplace_back(base.width(), base.height(), 10.0, 10.0, z, std::vector<uint8_t>{}, StoragePolicy::Auto, 0.1);
        REQUIRE(grids.back().storage() == HeightStorage::Int16);
        REQUIRE(grids.back().codeScale() == 0.1);
    }
    grids.push_back(loadDem(std::string(TERRACAST_SOURCE_DIR) +
                            "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif")
                        .grid);
    for (HeightGrid& g : extremeGrids()) grids.push_back(std::move(g));
    uint64_t seed = 70;
    for (const HeightGrid& g : grids) {
        INFO("grid " << g.width() << " x " << g.height() << ", seed " << seed);
        const int64_t hits = requireSameOnBothIsas(g, 320, seed++);
        CHECK(hits > 0);
    }
}
