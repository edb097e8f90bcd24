// The terrain renderer: camera framing, analytic shading of simple grids, and a golden image of a real DEM.
#include "loaders/dem_loader.h"
#include "loaders/image_io.h"
#include "tracer/core/angles.h"
#include "tracer/core/ranks.h"
#include "tracer/terrain/terrain_renderer.h"
#include "support/golden.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>
#include <cmath>
#include <cstdlib>
#include <filesystem>

using namespace terracast;

namespace {

HeightGrid flatGrid(int64_t n, double cell, float h) {
    return HeightGrid(n, n, cell, cell, std::vector<float>(size_t(n * n), h));
}

// Film coordinates of a world point seen by a pinhole camera ((0,0) top-left, (1,1) bottom-right).
glm::dvec2 project(const PinholeCamera& cam, const glm::dvec3& p, double aspect) {
    const glm::dvec3 f = glm::normalize(cam.lookAtM - cam.eyeM);
    const glm::dvec3 r = glm::normalize(glm::cross(f, cam.up));
    const glm::dvec3 u = glm::cross(r, f);
    const glm::dvec3 q = p - cam.eyeM;
    const double depth = glm::dot(q, f);
    const double tanV = std::tan(cam.fovYDeg * M_PI / 360.0);
    const double sx = glm::dot(q, r) / depth / (tanV * aspect), sy = glm::dot(q, u) / depth / tanV;
    return {0.5 * (sx + 1.0), 0.5 * (1.0 - sy)};
}

}  // namespace

TEST_CASE("Sun direction follows the compass and the elevation", "[tracer]") {
    Sun east{90.0, 0.0};
    CHECK(east.direction().x == Approx(1.0));
    CHECK(east.direction().y == Approx(0.0).margin(1e-12));
    Sun nw{315.0, 35.0};
    const auto d = nw.direction();
    CHECK(d.x < 0.0);
    CHECK(d.y > 0.0);
    CHECK(d.z == Approx(std::sin(35.0 * M_PI / 180.0)));
    CHECK(glm::length(d) == Approx(1.0));
}

TEST_CASE("The automatic camera frames the whole grid from the south-west", "[tracer]") {
    const std::vector<float> z{0, 100, 50, 900, 10, 20, 30, 40, 500};
    HeightGrid g(3, 3, 1000, 700, z);
    const double aspect = 16.0 / 9.0;
    const PinholeCamera cam = autoCamera(g, aspect);
    CHECK(cam.eyeM.x < 0.0);
    CHECK(cam.eyeM.y < 0.0);
    CHECK(cam.eyeM.z > g.maxHeightM());
    for (int k = 0; k < 8; ++k) {
        const glm::dvec3 corner{k & 1 ? g.extentXM() : 0.0, k & 2 ? g.extentYM() : 0.0,
                                k & 4 ? g.maxHeightM() : g.minHeightM()};
        const glm::dvec2 f = project(cam, corner, aspect);
        CHECK(f.x >= 0.0);
        CHECK(f.x <= 1.0);
        CHECK(f.y >= 0.0);
        CHECK(f.y <= 1.0);
    }
}

TEST_CASE("Flat terrain is lit by Lambert's cosine law plus ambient", "[tracer]") {
    const HeightGrid g = flatGrid(9, 10.0, 100.0f);
    TerrainRenderSettings s;
    s.width = 8;
    s.height = 8;
    s.threads = 1;
    s.camera.eyeM = {40, 40, 1000};
    s.camera.lookAtM = {40, 40, 100};
    s.camera.up = {0, 1, 0};
    s.camera.fovYDeg = 2.0;
    s.sky.kind = SkyKind::Flat;  // sky light independent of the sun
    RenderStats low, high;
    s.sun = Sun{200.0, 20.0};
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    const Film a = renderTerrain(g, surface, s, &low);
    s.sun = Sun{200.0, 60.0};
    const Film b = renderTerrain(g, surface, s, &high);
    CHECK(low.primaryRays == 64);
    CHECK(low.hits == 64);
    CHECK(low.shadowRays == 64);
    // Colour = albedo * (cos(zenith angle) * sun + ambient * sky): the difference between two sun heights
    // is albedo * sun * (sin 60 - sin 20) for every pixel, in every channel.
    const glm::vec3 albedo = elevationAlbedo(100.0, 100.0, 100.0);
    const glm::vec3 sunColour{1.0f, 0.96f, 0.90f};
    const float dSin = float(std::sin(60.0 * M_PI / 180.0) - std::sin(20.0 * M_PI / 180.0));
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            for (int c = 0; c < 3; ++c)
                CHECK(b.get(x, y)[c] - a.get(x, y)[c] == Approx(albedo[c] * sunColour[c] * dSin).epsilon(1e-4));
}

TEST_CASE("A dome shaded with smooth normals follows Lambert's law with its exact normals, where facets do not",
          "[tracer][normals]") {
    // A paraboloid dome z = 200 - 0.004 ((x - 200)^2 + (y - 200)^2) on 10 m cells, seen from high above, lit by
    // the sun alone (no sky): a pixel is albedo x sun x cos, with the cosine of the dome's own normal. The
    // expected value of each pixel is worked out from the analytic normal at the point its camera ray hits.
    const int n = 41;
    std::vector<float> heights(size_t(n) * n);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = 10.0 * i - 200.0, y = 10.0 * j - 200.0;
            heights[size_t(j) * n + size_t(i)] = float(200.0 - 0.004 * (x * x + y * y));
        }
    const HeightGrid g(n, n, 10.0, 10.0, heights, {}, StoragePolicy::Float32);
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    TerrainRenderSettings s;
    s.width = s.height = 48;
    s.threads = 1;
    s.camera.eyeM = {200, 200, 5000};
    s.camera.lookAtM = {200, 200, 0};
    s.camera.up = {0, 1, 0};
    s.camera.fovYDeg = 3.0;
    s.sky.kind = SkyKind::None;
    s.sun = Sun{250.0, 40.0};
    const glm::vec3 sunColour{1.0f, 0.96f, 0.90f};
    double error[2] = {0.0, 0.0};
    RenderStats stats[2];
    Film films[2] = {Film(1, 1), Film(1, 1)};
    for (const bool smooth : {true, false}) {
        s.smoothNormals = smooth;
        films[smooth] = renderTerrain(g, surface, s, &stats[smooth]);
    }
    int lit = 0;
    for (int y = 0; y < s.height; ++y)
        for (int x = 0; x < s.width; ++x) {
            const Ray ray = s.camera.generate((x + 0.5) / s.width, (y + 0.5) / s.height, 1.0);
            const auto hit = surface.intersect(ray, {0.0, kInfinity});
            if (!hit) continue;
            const glm::dvec3 p = hit->pointM;
            const glm::dvec3 exact = glm::normalize(glm::dvec3(0.008 * (p.x - 200.0), 0.008 * (p.y - 200.0), 1.0));
            const double cosine = glm::dot(exact, s.sun.direction());
            // Past the terminator a light reaches no point whose cell faces away from it: smooth shading changes
            // no shadow, so those pixels are dark either way.
            if (cosine <= 0.0 || glm::dot(hit->normal, s.sun.direction()) <= 0.0) continue;
            const glm::vec3 albedo = elevationAlbedo(p.z, g.minHeightM(), g.maxHeightM());
            ++lit;
            for (const bool smooth : {true, false}) {
                const double expected = double(albedo.g * sunColour.g) * cosine;
                error[smooth] = std::max(error[smooth], std::abs(double(films[smooth].get(x, y).g) - expected));
            }
        }
    INFO("largest error in green: smooth " << error[1] << ", facets " << error[0] << ", over " << lit << " pixels");
    REQUIRE(lit > 1000);
    // Inside the dome the smooth normal is exact (the border vertices' one-sided differences are not).
    CHECK(error[1] < 0.02 * error[0]);
    CHECK(error[0] > 0.005);
    // Only shading changes: the same rays of each kind, the same hits.
    CHECK(stats[1].primaryRays == stats[0].primaryRays);
    CHECK(stats[1].shadowRays == stats[0].shadowRays);
    CHECK(stats[1].hits == stats[0].hits);
}

TEST_CASE("Occlusion towards the sun: a wall's shadow ends where its height over tan(elevation) says", "[tracer]") {
    // A wall 100 m high along x = 50 m on otherwise flat ground (10 m cells; bilinear, so its flanks slope to
    // the ground at x = 40 and 60 m). With the sun in the west at 45 degrees a probe 1 m above the ground at x
    // sees the crest at height 1 + (x - 50): shadowed while that is below 100 m, up to x = 149 m.
    const int64_t n = 31;
    std::vector<float> z(size_t(n * n), 0.0f);
    for (int64_t j = 0; j < n; ++j) z[size_t(j * n + 5)] = 100.0f;
    HeightGrid g(n, n, 10.0, 10.0, z);
    TerrainRenderSettings s;
    s.threads = 1;
    s.sun = Sun{270.0, 45.0};
    auto litAt = [&](double xM) {
        const Ray probe{{xM, 150.0, 1.0}, s.sun.direction()};
        return !occluded(g, probe, {0.0, kInfinity}, CellMethod::Bilinear);
    };
    CHECK_FALSE(litAt(70.0));
    CHECK_FALSE(litAt(140.0));
    CHECK_FALSE(litAt(148.9));
    CHECK(litAt(149.1));
    CHECK(litAt(170.0));
    CHECK(litAt(30.0));
}

TEST_CASE("Golden image: St Helens at 160x90 matches the committed reference", "[tracer][golden]") {
    const std::string dem = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
    const std::string golden = std::string(TERRACAST_SOURCE_DIR) + "/tests/golden/st-helens-160x90.png";
    const LoadedDem loaded = loadDem(dem);
    TerrainRenderSettings s;
    s.width = 160;
    s.height = 90;
    s.threads = 2;
    s.camera = autoCamera(loaded.grid, 160.0 / 90.0);
    const Film film = renderTerrain(loaded.grid, TerrainSurface(loaded.grid, SurfaceMethod::Bilinear), s);
    testing::checkGolden(RgbImage{film.width, film.height, film.rgb}, golden);
}

TEST_CASE("Ranks' picture blocks: each rank's span is its own columns, and every block is drawn once", "[terrain]") {
    for (const auto& [bx, by, spans] : std::vector<std::array<int, 3>>{{15, 9, 2}, {15, 9, 3}, {2, 5, 4}, {7, 1, 1}}) {
        INFO(bx << " x " << by << " blocks over " << spans << " spans");
        const BlockOrder order = blocksBySpans(bx, by, spans);
        REQUIRE(order.spanEnds.size() == size_t(spans));
        REQUIRE(order.spanEnds.back() == int64_t(order.blocks.size()));
        std::vector<int> seen(size_t(bx * by), 0);
        int64_t begin = 0;
        for (int r = 0; r < spans; ++r) {
            const int c0 = bx * r / spans, c1 = bx * (r + 1) / spans;
            // Whole columns [c0, c1), row by row.
            CHECK(order.spanEnds[size_t(r)] - begin == int64_t(c1 - c0) * by);
            for (int64_t k = begin; k < order.spanEnds[size_t(r)]; ++k) {
                const auto [x, y] = order.blocks[size_t(k)];
                CHECK(x >= c0);
                CHECK(x < c1);
                if (k > begin) CHECK(std::pair(y, x) > std::pair(order.blocks[size_t(k - 1)].second,
                                                                 order.blocks[size_t(k - 1)].first));
                ++seen[size_t(y * bx + x)];
            }
            begin = order.spanEnds[size_t(r)];
        }
        CHECK(std::count(seen.begin(), seen.end(), 1) == bx * by);
    }
    // One process draws them in picture order, from a count of its own.
    const BlockOrder one = blocksBySpans(4, 3, 1);
    ranks::SpanTasks tasks(one.spanEnds);
    for (int64_t k = 0; k < 12; ++k) {
        CHECK(tasks.next() == k);
        CHECK(one.blocks[size_t(k)] == std::pair(int(k % 4), int(k / 4)));
    }
    CHECK(tasks.next() == 12);
    CHECK(tasks.next() == 12);
}

TEST_CASE("Ranks' picture blocks: simulated ranks keep to their spans, then share the rest, each block once",
          "[terrain]") {
    // Ranks taking turns in a scrambled order, each drawing from shared counts as the MPI window holds them.
    for (const int ranks : {2, 3, 5}) {
        const BlockOrder order = blocksBySpans(15, 9, ranks);
        std::vector<int64_t> counts(static_cast<size_t>(ranks), 0);
        const auto fetchAdd = [&](int s) { return counts[size_t(s)]++; };
        std::vector<int> cursor(static_cast<size_t>(ranks)), spent(static_cast<size_t>(ranks), 0);
        for (int r = 0; r < ranks; ++r) cursor[size_t(r)] = r;
        std::vector<std::vector<int64_t>> drawn(static_cast<size_t>(ranks));
        std::vector<bool> done(static_cast<size_t>(ranks), false);
        std::vector<int> seen(order.blocks.size(), 0);
        uint32_t state = 7;
        for (int finished = 0; finished < ranks;) {
            state = state * 1664525u + 1013904223u;
            const int r = int((state >> 16) % uint32_t(ranks));
            if (done[size_t(r)]) continue;
            const int64_t k = ranks::SpanTasks::next(order.spanEnds, cursor[size_t(r)], spent[size_t(r)], fetchAdd);
            if (k >= int64_t(order.blocks.size())) {
                done[size_t(r)] = true;
                ++finished;
                continue;
            }
            ++seen[size_t(k)];
            drawn[size_t(r)].push_back(k);
        }
        INFO(ranks << " ranks");
        CHECK(std::count(seen.begin(), seen.end(), 1) == std::ptrdiff_t(seen.size()));
        for (int r = 0; r < ranks; ++r) {
            // Each rank's first draws are its own span's first tasks, in order.
            const int64_t begin = r == 0 ? 0 : order.spanEnds[size_t(r - 1)];
            REQUIRE(!drawn[size_t(r)].empty());
            CHECK(drawn[size_t(r)].front() == begin);
            // Then on in its own span (its draws there rising) until the span is spent.
            const auto& d = drawn[size_t(r)];
            size_t own = 1;
            while (own < d.size() && d[own] >= begin && d[own] < order.spanEnds[size_t(r)]) {
                CHECK(d[own] > d[own - 1]);
                ++own;
            }
            // Every draw after that is from another span.
            for (size_t i = own; i < d.size(); ++i) CHECK((d[i] < begin || d[i] >= order.spanEnds[size_t(r)]));
        }
    }
}

TEST_CASE("Camera rays from the frame worked out once are the per-ray formula's, bit for bit", "[terrain]") {
    // The formula as it reads when everything is worked out for each ray.
    const auto perRay = [](const PinholeCamera& c, double fx, double fy, double aspect) {
        const glm::dvec3 forward = glm::normalize(c.lookAtM - c.eyeM);
        glm::dvec3 right = glm::cross(forward, c.up);
        if (glm::dot(right, right) < 1e-20) right = glm::cross(forward, glm::dvec3(0, 1, 0));
        right = glm::normalize(right);
        const glm::dvec3 camUp = glm::cross(right, forward);
        const double halfH = std::tan(radians(c.fovYDeg) * 0.5);
        const double sx = (2.0 * fx - 1.0) * (halfH * aspect), sy = (1.0 - 2.0 * fy) * halfH;
        return Ray{c.eyeM, glm::normalize(forward + sx * right + sy * camUp)};
    };
    PinholeCamera tilted;
    tilted.eyeM = {1234.5, -987.25, 2500.125};
    tilted.lookAtM = {40000.0, 31000.5, 120.0};
    tilted.fovYDeg = 37.5;
    PinholeCamera straightDown;  // up parallel to the view: the other cross product
    straightDown.eyeM = {10.0, 20.0, 5000.0};
    straightDown.lookAtM = {10.0, 20.0, 0.0};
    straightDown.fovYDeg = 60.0;
    for (const PinholeCamera& c : {tilted, straightDown}) {
        const PinholeCamera::Frame frame = c.frame();
        size_t differ = 0;
        for (int y = 0; y < 61; ++y)
            for (int x = 0; x < 83; ++x) {
                const double fx = (x + 0.5) / 83, fy = (y + 0.5) / 61, aspect = 83.0 / 61.0;
                const Ray a = frame.generate(fx, fy, aspect), b = perRay(c, fx, fy, aspect), g = c.generate(fx, fy, aspect);
                differ += !(a.origin == b.origin && a.dir == b.dir && g.dir == b.dir);
            }
        CHECK(differ == 0);
    }
}
