// Direct versus Embree on the same rays, and the compare command's outputs.
#include "loaders/dem_loader.h"
#include "loaders/image_io.h"
#include "support/run_command.h"
#include "tracer/measure/compare.h"

#include <catch2/catch.hpp>
#include <expat.h>

#include <cmath>
#include <filesystem>
#include <random>

using namespace terracast;
namespace fs = std::filesystem;

namespace {

// Random rays from above and around a grid, aimed at its footprint.
std::vector<Ray> raysOver(const HeightGrid& g, int n, uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    std::vector<Ray> rays;
    for (int k = 0; k < n; ++k) {
        const glm::dvec3 target{g.extentXM() * U(rng), g.extentYM() * U(rng), g.minHeightM()};
        const double az = 2.0 * M_PI * U(rng), el = (5.0 + 80.0 * U(rng)) * M_PI / 180.0;
        const glm::dvec3 d{std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), -std::sin(el)};
        const double back = (g.maxHeightM() - g.minHeightM() + 100.0) / std::sin(el) + 50.0 * U(rng);
        rays.push_back({target - back * d, d});
    }
    return rays;
}

bool parsesAsXml(const std::string& text) {
    XML_Parser p = XML_ParserCreate(nullptr);
    const bool ok = XML_Parse(p, text.data(), int(text.size()), 1) == XML_STATUS_OK;
    XML_ParserFree(p);
    return ok;
}

}  // namespace

TEST_CASE("Planar DEM: bilinear, triangles, embree and embree-grid give the same hits", "[tracer][embree]") {
    // An inclined plane: every cell's twist is 0, so every surface is the same plane.
    const int64_t w = 40, h = 30;
    std::vector<float> z(size_t(w * h));
    for (int64_t j = 0; j < h; ++j)
        for (int64_t i = 0; i < w; ++i) z[size_t(j * w + i)] = float(500.0 + 3.0 * double(i) - 2.0 * double(j));
    const HeightGrid g(w, h, 25.0, 25.0, z);
    const TerrainSurface bilinear(g, SurfaceMethod::Bilinear), triangles(g, SurfaceMethod::Triangles),
        embree(g, SurfaceMethod::Embree), grid(g, SurfaceMethod::EmbreeGrid);
    int hits = 0;
    for (const Ray& ray : raysOver(g, 20000, 5)) {
        const auto a = bilinear.intersect(ray, {0, kInfinity});
        for (const TerrainSurface* other : {&triangles, &embree, &grid}) {
            const auto b = other->intersect(ray, {0, kInfinity});
            INFO(surfaceMethodName(other->method()));
            REQUIRE(a.has_value() == b.has_value());
            if (a) CHECK(b->t == Approx(a->t).epsilon(1e-5));
        }
        hits += a.has_value();
    }
    CHECK(hits > 15000);
}

TEST_CASE("Real DEM: triangles and Embree agree on hit/miss for 99.99% of rays and on t", "[tracer][embree]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif");
    const HeightGrid& g = dem.grid;
    const TerrainSurface triangles(g, SurfaceMethod::Triangles), embree(g, SurfaceMethod::Embree),
        grid(g, SurfaceMethod::EmbreeGrid);
    CHECK(embree.memoryBytes() > 0);
    CHECK(grid.memoryBytes() > 0);
    for (const TerrainSurface* other : {&embree, &grid}) {
        int64_t rays = 0, disagree = 0, tOff = 0, hits = 0;
        double worst = 0.0;
        for (const Ray& ray : raysOver(g, 100000, 6)) {
            const auto a = triangles.intersect(ray, {0, kInfinity});
            const auto b = other->intersect(ray, {0, kInfinity});
            ++rays;
            if (a.has_value() != b.has_value()) {
                ++disagree;
                continue;
            }
            if (!a) continue;
            ++hits;
            const double rel = std::abs(a->t - b->t) / a->t;
            worst = std::max(worst, rel);
            tOff += rel > 1e-5;
        }
        INFO(surfaceMethodName(other->method()) << ": " << disagree << " of " << rays << " disagree, worst t " << worst);
        CHECK(hits > 50000);
        CHECK(double(disagree) <= 1e-4 * double(rays));
        CHECK(double(tOff) <= 1e-4 * double(hits));
    }
}

TEST_CASE("compareSurfaces: the reference agrees with itself and Embree ratios are measured", "[tracer][compare]") {
    const LoadedDem dem = loadDem(std::string(TERRACAST_SOURCE_DIR) +
                                  "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif");
    CompareSettings cs;
    cs.render.width = 80;
    cs.render.height = 60;
    cs.render.camera = autoCamera(dem.grid, 80.0 / 60.0);
    const CompareReport r = compareSurfaces(dem.grid, cs);
    REQUIRE(r.methods.size() == compareMethods().size());
    for (const auto& m : r.methods) {
        INFO(surfaceMethodName(m.method));
        CHECK(m.primaryRays == 4800);
        CHECK(m.primaryRaysPerSecond > 0.0);
        CHECK(m.ratioToEmbreePrimary > 0.0);
        CHECK(m.hitAgreement > 0.9);
        if (m.method == SurfaceMethod::BilinearDouble) {
            CHECK(m.tErrorM.max == 0.0);
            CHECK(m.imageRmse == 0.0);
        }
        if (m.method == SurfaceMethod::Bilinear) CHECK(m.tErrorRel.max < 1e-4);
        if (m.method == SurfaceMethod::Embree) CHECK(m.ratioToEmbreePrimary == 1.0);
    }
}

TEST_CASE("CLI: compare writes the table, the JSON, images, heat maps and the SVG chart", "[cli][compare]") {
    const fs::path dir = fs::temp_directory_path() / ("terracast-compare-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    const fs::path json = dir / "report.json";
    fs::create_directories(dir);
    const auto r = terracast::testing::runTerracast(
        "compare '" + std::string(TERRACAST_SOURCE_DIR) +
        "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif' --size 96x72 --json '" + json.string() +
        "' --out-dir '" + (dir / "out").string() + "'");
    REQUIRE(r.exitCode == 0);
    const std::string text = terracast::testing::slurp(json);
    for (const char* method : {"bilinear", "bilinear-double", "triangles", "nearest", "embree", "embree-grid"}) {
        CHECK(text.find("\"name\": \"" + std::string(method) + "\"") != std::string::npos);
        CHECK(r.out.find(method) != std::string::npos);
        const RgbImage image = readImage((dir / "out" / (std::string(method) + ".png")).string());
        CHECK(image.width == 96);
        if (std::string(method) != "bilinear-double") {
            const RgbImage heat = readImage((dir / "out" / ("diff-" + std::string(method) + ".png")).string());
            CHECK(heat.width == 96);
            CHECK(heat.height > 72);  // the legend strip
        }
    }
    for (const char* key : {"\"dem\"", "\"width\"", "\"height\"", "\"rays\"", "\"reference\"", "\"build_s\"",
                            "\"memory_bytes\"", "\"primary_rays_per_s\"", "\"shadow_rays_per_s\"", "\"hit_agreement\"",
                            "\"t_error_m\"", "\"t_error_rel\"", "\"mean\"", "\"p99\"", "\"max\"", "\"image_rmse\"",
                            "\"image_psnr_db\"", "\"ratio_to_embree\"", "\"primary\"", "\"shadow\""})
        CHECK(text.find(key) != std::string::npos);
    CHECK(text.find("null") == std::string::npos);  // every number finite
    CHECK(text.find("nan") == std::string::npos);
    const std::string svg = terracast::testing::slurp(dir / "out" / "tradeoff.svg");
    CHECK(parsesAsXml(svg));
    CHECK(svg.find(">embree-grid<") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("traceSurface: a band of rows traces those rows' pixels as the whole picture does", "[tracer][compare]") {
    std::vector<float> z(33 * 33);
    for (int j = 0; j < 33; ++j)
        for (int i = 0; i < 33; ++i) z[size_t(j * 33 + i)] = float(200.0 + 60.0 * std::sin(0.4 * i) * std::cos(0.3 * j));
    const HeightGrid g(33, 33, 30.0, 30.0, z);
    TerrainRenderSettings s;
    s.width = 40;
    s.height = 30;
    s.threads = 2;
    s.camera = autoCamera(g, double(s.width) / s.height);
    for (SurfaceMethod method : {SurfaceMethod::Bilinear, SurfaceMethod::Embree}) {
        INFO(surfaceMethodName(method));
        const TerrainSurface surface(g, method);
        const MethodComparison whole = traceSurface(g, surface, s);
        REQUIRE(whole.hitT.size() == size_t(s.width * s.height));
        int64_t shadowRays = 0, primaryRays = 0;
        // Three bands covering the picture, the last one given as "to the end".
        const int cuts[4] = {0, 7, 19, -1};
        for (int b = 0; b < 3; ++b) {
            const MethodComparison band = traceSurface(g, surface, s, true, cuts[b], cuts[b + 1]);
            const int y1 = cuts[b + 1] < 0 ? s.height : cuts[b + 1];
            CHECK(band.primaryRays == int64_t(s.width) * (y1 - cuts[b]));
            CHECK(band.primarySeconds > 0.0);
            REQUIRE(band.hitT.size() == whole.hitT.size());
            for (int y = 0; y < s.height; ++y)
                for (int x = 0; x < s.width; ++x) {
                    const size_t k = size_t(y * s.width + x);
                    if (y < cuts[b] || y >= y1) {  // not traced, not shaded
                        CHECK(std::isnan(band.hitT[k]));
                        CHECK(band.image.get(x, y) == glm::vec3(0.0f));
                        continue;
                    }
                    CHECK(std::isnan(band.hitT[k]) == std::isnan(whole.hitT[k]));
                    if (!std::isnan(whole.hitT[k])) CHECK(band.hitT[k] == whole.hitT[k]);
                    CHECK(band.image.get(x, y) == whole.image.get(x, y));
                }
            shadowRays += band.shadowRays;
            primaryRays += band.primaryRays;
        }
        CHECK(primaryRays == whole.primaryRays);
        CHECK(shadowRays == whole.shadowRays);
        CHECK(whole.shadowRays > 0);
    }
}
