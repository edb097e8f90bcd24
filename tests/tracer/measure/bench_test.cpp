// The bench library: denormals are flushed on every thread that traces, the grazing camera stands just above
// the highest peak looking 8 degrees down, a grid's report holds every method, refused ones as skipped, and
// each pass's traces go round the methods in turn, band by band, in alternating order.
#include "heightfield/fractal_terrain.h"
#include "tracer/measure/bench.h"

#include <catch2/catch.hpp>

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <cmath>
#include <vector>

using namespace terracast;

TEST_CASE("bench: FTZ and DAZ hold on every thread inside the scope, and the caller's modes come back", "[tracer][bench]") {
    const bool before = denormalsFlushed();
    std::atomic<int> unflushed{0}, tasks{0};
    std::mutex lock;
    std::set<std::thread::id> threads;
    {
        FlushDenormalsScope scope;
        CHECK(denormalsFlushed());
        const tbb::global_control two(tbb::global_control::max_allowed_parallelism, 2);
        scope.run([&] { tbb::parallel_for(0, 2000, [&](int) {
            volatile double spin = 0.0;
            for (int k = 0; k < 2000; ++k) spin = spin + 1.0;  // long enough for a worker to join
            unflushed += denormalsFlushed() ? 0 : 1;
            ++tasks;
            const std::lock_guard<std::mutex> hold(lock);
            threads.insert(std::this_thread::get_id());
        }); });
        // A denormal operand reads as zero under DAZ.
        volatile float tiny = 1e-40f;
        CHECK(tiny * 1.0f == 0.0f);
    }
    CHECK(tasks == 2000);
    // The check means something only if a worker took part.
    CHECK(threads.size() >= std::min<size_t>(2, std::thread::hardware_concurrency()));
    CHECK(unflushed == 0);
    CHECK(denormalsFlushed() == before);
}

TEST_CASE("bench: the grazing camera stands just above the highest peak and looks 8 degrees down", "[tracer][bench]") {
    FractalTerrainOptions o;
    o.size = 65;
    const HeightGrid g = fractalTerrain(o);
    const PinholeCamera cam = benchCamera(g, BenchCamera::Grazing, 4.0 / 3.0);
    const double relief = double(g.maxHeightM()) - g.minHeightM();
    CHECK(cam.eyeM.z > g.maxHeightM());
    CHECK(cam.eyeM.z < g.maxHeightM() + 0.05 * relief);
    // The eye is over a vertex holding the maximum height.
    const double fi = cam.eyeM.x / g.cellSizeXM(), fj = cam.eyeM.y / g.cellSizeYM();
    REQUIRE(fi == std::round(fi));
    REQUIRE(fj == std::round(fj));
    CHECK(g.at(int64_t(fi), int64_t(fj)) == g.maxHeightM());
    const glm::dvec3 forward = glm::normalize(cam.lookAtM - cam.eyeM);
    CHECK(std::asin(-forward.z) * 180.0 / 3.14159265358979323846 == Approx(8.0));
    // Heading into the grid: towards its centre.
    const glm::dvec2 toCentre{0.5 * g.extentXM() - cam.eyeM.x, 0.5 * g.extentYM() - cam.eyeM.y};
    CHECK(glm::dot(glm::dvec2(forward), toCentre) > 0.0);
}

TEST_CASE("bench: one grid, every method, refused methods skipped, ratios to Embree's own passes", "[tracer][bench]") {
    FractalTerrainOptions o;
    o.size = 33;
    const HeightGrid g = fractalTerrain(o);
    BenchSettings s;
    s.width = 64;
    s.height = 48;
    s.threadCounts = {1, 2};
    s.refuse = [](BenchMethod m) -> std::optional<double> {
        if (m == BenchMethod::EmbreeGrid) return 1e12;
        return std::nullopt;
    };
    const BenchGridResult r = benchGrid(g, s);
    CHECK(r.cells == 32 * 32);
    REQUIRE(r.methods.size() == benchMethods().size());
    for (size_t k = 0; k < r.methods.size(); ++k) {
        const auto& m = r.methods[k];
        INFO(benchMethodName(m.method));
        CHECK(m.method == benchMethods()[k]);
        if (m.method == BenchMethod::EmbreeGrid) {
            CHECK(m.skipped);
            CHECK(m.neededBytes == 1e12);
            CHECK(m.passes.empty());
            continue;
        }
        CHECK_FALSE(m.skipped);
        REQUIRE(m.passes.size() == 4);  // two cameras by two thread counts
        CHECK(m.passes[0].camera == BenchCamera::Corner);
        CHECK(m.passes[1].threads == 2);
        CHECK(m.passes[2].camera == BenchCamera::Grazing);
        for (const auto& p : m.passes) {
            CHECK(p.primaryRays == 64 * 48);
            CHECK(p.primaryRaysPerSecond > 0.0);
            CHECK(std::isfinite(p.ratioToEmbreePrimary));
            if (m.method == BenchMethod::Embree) CHECK(p.ratioToEmbreePrimary == 1.0);
        }
        if (m.method == BenchMethod::BilinearFlat) CHECK(m.hitAgreement == 1.0);
        if (m.method == BenchMethod::Embree) CHECK(m.bytesPerCell > 50.0);
        else CHECK(m.bytesPerCell < 10.0);
    }
    // The flat walk and the pyramid hit the same cells, so they cast the same shadow rays.
    for (size_t q = 0; q < 4; ++q) CHECK(r.methods[0].passes[q].shadowRays == r.methods[1].passes[q].shadowRays);
    // Traced in 8 bands of 6 rows (the default), in 5 bands of 9 or 10 rows, or as whole pictures, a pass counts
    // the same rays.
    REQUIRE(s.bands == 8);
    s.methods = {BenchMethod::Bilinear, BenchMethod::Embree};
    s.bands = 5;
    const BenchGridResult uneven = benchGrid(g, s);
    s.bands = 1;
    const BenchGridResult whole = benchGrid(g, s);
    for (size_t k = 0; k < 2; ++k)
        for (size_t q = 0; q < 4; ++q) {
            const BenchPass& banded = r.methods[k == 0 ? 0 : 3].passes[q];
            for (const BenchGridResult* other : {&uneven, &whole}) {
                CHECK(other->methods[k].passes[q].primaryRays == banded.primaryRays);
                CHECK(other->methods[k].passes[q].shadowRays == banded.shadowRays);
            }
            CHECK(banded.shadowRays > 0);
        }
}

TEST_CASE("bench: a pass traced in bands takes the sum of each band's fastest repetition", "[tracer][bench]") {
    // Repetition r's seconds for bands 0, 1, 2: the fastest are 1.0 (r = 1), 2.0 (r = 0) and 0.5 (r = 2).
    CHECK(bandedSeconds({{3.0, 2.0, 4.0}, {1.0, 6.0, 0.75}, {1.5, 2.5, 0.5}}) == 3.5);
    CHECK(bandedSeconds({{0.25, 0.5}}) == 0.75);  // one repetition: its own sum
    CHECK(bandedSeconds({{2.0}, {1.0}, {3.0}}) == 1.0);  // one band: the fastest repetition
    CHECK(bandedSeconds({}) == 0.0);
}

TEST_CASE("bench: a pass's traces go round the methods in turn, in alternating order, Embree's grid geometry in a "
          "group of its own",
          "[tracer][bench]") {
    FractalTerrainOptions o;
    o.size = 17;
    const HeightGrid g = fractalTerrain(o);
    BenchSettings s;
    s.width = 16;
    s.height = 12;
    s.threadCounts = {1};
    s.cameras = {BenchCamera::Corner};
    s.repeat = 3;
    s.bands = 2;
    s.methods = {BenchMethod::Bilinear, BenchMethod::EmbreeGrid, BenchMethod::Embree};
    std::vector<std::string> steps;
    s.onStep = [&](const std::string& step) { steps.push_back(step); };
    const BenchGridResult r = benchGrid(g, s);
    const std::string pass = ", corner camera, 1 thread";
    const std::string top = pass + ", rows 0 to 5", bottom = pass + ", rows 6 to 11";
    // The order alternates from band to band and from one repetition to the next.
    const std::vector<std::string> expected{
        "building bilinear", "building embree",
        "bilinear" + pass + ", warm-up", "embree" + pass + ", warm-up",
        "bilinear" + top, "embree" + top, "embree" + bottom, "bilinear" + bottom,       // repetition 1
        "embree" + top, "bilinear" + top, "bilinear" + bottom, "embree" + bottom,       // repetition 2
        "bilinear" + top, "embree" + top, "embree" + bottom, "bilinear" + bottom,       // repetition 3
        "building embree-grid", "embree-grid" + pass + ", warm-up",
        "embree-grid" + top, "embree-grid" + bottom, "embree-grid" + top, "embree-grid" + bottom,
        "embree-grid" + top, "embree-grid" + bottom};
    CHECK(steps == expected);
    // Results stay in the settings' order, each with its one pass.
    REQUIRE(r.methods.size() == 3);
    CHECK(r.methods[0].method == BenchMethod::Bilinear);
    CHECK(r.methods[1].method == BenchMethod::EmbreeGrid);
    CHECK(r.methods[2].method == BenchMethod::Embree);
    for (const auto& m : r.methods) {
        INFO(benchMethodName(m.method));
        REQUIRE(m.passes.size() == 1);
        CHECK(m.passes[0].primaryRays == 16 * 12);
        CHECK(m.passes[0].primaryRaysPerSecond > 0.0);
        CHECK(m.hitAgreement > 0.9);
    }
    CHECK(r.methods[0].hitAgreement == 1.0);  // the reference: measured first
    CHECK(r.methods[2].passes[0].ratioToEmbreePrimary == 1.0);

    // With Embree's mesh refused the other methods are still measured in turn, and every ratio is NaN.
    s.refuse = [](BenchMethod m) -> std::optional<double> {
        if (m == BenchMethod::Embree) return 1e12;
        return std::nullopt;
    };
    s.methods = {BenchMethod::Bilinear, BenchMethod::Triangles, BenchMethod::Embree};
    s.bands = 1;  // one band: the whole picture, named by the pass alone
    steps.clear();
    const BenchGridResult refused = benchGrid(g, s);
    CHECK(steps == std::vector<std::string>{"building bilinear", "building triangles", "bilinear" + pass + ", warm-up",
                                            "triangles" + pass + ", warm-up", "bilinear" + pass, "triangles" + pass,
                                            "triangles" + pass, "bilinear" + pass, "bilinear" + pass,
                                            "triangles" + pass});
    REQUIRE(refused.methods.size() == 3);
    CHECK(refused.methods[2].skipped);
    for (size_t k = 0; k < 2; ++k) {
        REQUIRE(refused.methods[k].passes.size() == 1);
        CHECK(std::isnan(refused.methods[k].passes[0].ratioToEmbreePrimary));
        CHECK(std::isnan(refused.methods[k].passes[0].ratioToEmbreeShadow));
    }
}

TEST_CASE("bench: method names round-trip and map to their surfaces", "[tracer][bench]") {
    for (BenchMethod m : benchMethods()) CHECK(parseBenchMethod(benchMethodName(m)) == m);
    CHECK_FALSE(parseBenchMethod("nearest"));
    CHECK(benchTraversal(BenchMethod::BilinearFlat) == Traversal::Flat);
    CHECK(benchTraversal(BenchMethod::Bilinear) == Traversal::Pyramid);
    CHECK(benchSurfaceMethod(BenchMethod::BilinearFlat) == SurfaceMethod::Bilinear);
    CHECK(benchSurfaceMethod(BenchMethod::EmbreeGrid) == SurfaceMethod::EmbreeGrid);
}
