// `render`'s cameras and pixel sampling: the orthographic, panorama and fisheye views of a flat square,
// checked pixel by pixel against the square's outline computed in the test from each projection's own
// formula; anti-aliasing against a supersampled picture box- or tent-filtered in the test; adaptive sampling
// spending its samples on edges.
#include "tracer/terrain/terrain_renderer.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>
#include <optional>

using namespace terracast;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// A flat square at height 0, 2 L on a side, centred on (L, L), on 10 m cells.
constexpr double kHalfSide = 500.0;
HeightGrid flatSquare() {
    const int64_t n = 101;
    return HeightGrid(n, n, 10.0, 10.0, std::vector<float>(size_t(n * n), 0.0f));
}

// Terrain lit by a sun overhead against a black sky: a pixel is terrain when it is bright.
TerrainRenderSettings plainSettings(int width, int height) {
    TerrainRenderSettings s;
    s.width = width;
    s.height = height;
    s.threads = 2;
    s.sky.kind = SkyKind::None;
    s.sky.samples = 0;
    s.sun = Sun{0.0, 90.0};
    return s;
}

bool terrainAt(const Film& f, int x, int y) { return f.get(x, y).g > 0.05f; }

// Where a ray meets the plane z = 0: inside the square, outside it, or too near its edge (within `margin`
// metres) for one ray per pixel to decide.
enum class Expect { Terrain, Sky, Edge };
Expect expectOnSquare(const glm::dvec3& origin, const glm::dvec3& dir, double margin) {
    if (dir.z >= 0.0) return Expect::Sky;
    const double t = -origin.z / dir.z;
    const glm::dvec3 p = origin + t * dir;
    const double outside = std::max(std::abs(p.x - kHalfSide), std::abs(p.y - kHalfSide)) - kHalfSide;
    if (std::abs(outside) < margin) return Expect::Edge;
    return outside < 0.0 ? Expect::Terrain : Expect::Sky;
}

// Compares the rendered mask with the expectation of every pixel; returns the pixels that disagree and counts
// those decided.
int disagreements(const Film& film, const std::function<Expect(int, int)>& expect, int& decided) {
    int wrong = 0;
    decided = 0;
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const Expect e = expect(x, y);
            if (e == Expect::Edge) continue;
            ++decided;
            if ((e == Expect::Terrain) != terrainAt(film, x, y)) ++wrong;
        }
    return wrong;
}

}  // namespace

TEST_CASE("render --view panorama: each column shows the square out to its edge at that azimuth",
          "[tracer][views]") {
    const HeightGrid g = flatSquare();
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    TerrainRenderSettings s = plainSettings(360, 180);
    PinholeCamera given;
    // Off the centre, so that a picture flipped left to right or top to bottom shows another outline.
    given.eyeM = {kHalfSide + 200.0, kHalfSide - 150.0, 300.0};
    given.lookAtM = {kHalfSide + 300.0, kHalfSide - 150.0, 300.0};  // the picture's centre looks east
    s.view = makeViewCamera(g, CameraKind::Panorama, given, 2.0);
    const Film film = renderTerrain(g, surface, s);
    // Equirectangular, written out here: column x is azimuth (x + 0.5) / W * 360 - 180 degrees from east
    // (clockwise seen from above, so the right half looks south), row y elevation 90 - (y + 0.5) / H * 180.
    int decided = 0;
    const int wrong = disagreements(
        film,
        [&](int x, int y) {
            const double az = ((x + 0.5) / s.width * 2.0 - 1.0) * kPiD, el = (1.0 - (y + 0.5) / s.height * 2.0) * kPiD / 2;
            const glm::dvec3 dir{std::cos(el) * std::cos(az), -std::cos(el) * std::sin(az), std::sin(el)};
            return expectOnSquare(given.eyeM, dir, 15.0);
        },
        decided);
    CHECK(decided > 360 * 180 * 9 / 10);
    CHECK(wrong == 0);
}

TEST_CASE("render --view fisheye: an equidistant 180-degree circle looking down sees the square's outline",
          "[tracer][views]") {
    const HeightGrid g = flatSquare();
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    TerrainRenderSettings s = plainSettings(300, 200);
    PinholeCamera given;
    given.eyeM = {kHalfSide - 150.0, kHalfSide + 100.0, 400.0};  // off the centre, as above
    given.lookAtM = {kHalfSide - 150.0, kHalfSide + 100.0, 0.0};
    given.up = {0.0, 1.0, 0.0};  // north at the top
    given.fovYDeg = 180.0;
    given.fovGiven = true;
    s.view = makeViewCamera(g, CameraKind::Fisheye, given, 1.5);
    RenderStats stats;
    const Film film = renderTerrain(g, surface, s, &stats);
    // The circle inscribed in the picture's height spans 180 degrees; the angle from the nadir grows linearly
    // with the distance from the centre, and its direction on the picture is its compass direction.
    int decided = 0, outsideCircle = 0;
    const int wrong = disagreements(
        film,
        [&](int x, int y) {
            const double px = ((x + 0.5) / s.width * 2.0 - 1.0) * 1.5, py = 1.0 - (y + 0.5) / s.height * 2.0;
            const double r = std::hypot(px, py);
            if (r > 1.0) {
                ++outsideCircle;
                return Expect::Sky;  // black
            }
            const double theta = r * kPiD / 2.0, phi = std::atan2(py, px);
            const glm::dvec3 dir{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)};
            return expectOnSquare(given.eyeM, dir, 15.0);
        },
        decided);
    CHECK(decided > 300 * 200 * 9 / 10);
    CHECK(wrong == 0);
    // Pixels outside the circle trace nothing.
    CHECK(stats.primaryRays == 300 * 200 - outsideCircle);
}

TEST_CASE("render --view orthographic: straight down, the square is a rectangle of the fitted span",
          "[tracer][views]") {
    const HeightGrid g = flatSquare();
    const TerrainSurface surface(g, SurfaceMethod::Bilinear);
    TerrainRenderSettings s = plainSettings(400, 200);
    PinholeCamera given;
    given.eyeM = {kHalfSide, kHalfSide, 50.0};  // below nothing: the rays start behind the grid's box anyway
    given.lookAtM = {kHalfSide, kHalfSide, -10.0};
    given.up = {0.0, 1.0, 0.0};
    s.view = makeViewCamera(g, CameraKind::Orthographic, given, 2.0);
    const Film film = renderTerrain(g, surface, s);
    // The span fits the square's height (1000 m) with 5 % to spare on each side: 1050 m over 200 rows, 2100 m
    // over 400 columns; the square covers rows 4.76 .. 195.2 and columns 104.8 .. 295.2 (pixel centres inside).
    const double metresPerPixel = 2.1 * kHalfSide / 200.0;
    int decided = 0;
    const int wrong = disagreements(
        film,
        [&](int x, int y) {
            const glm::dvec3 origin{kHalfSide + (x + 0.5 - 200.0) * metresPerPixel,
                                    kHalfSide + (100.0 - (y + 0.5)) * metresPerPixel, 1000.0};
            return expectOnSquare(origin, {0.0, 0.0, -1.0}, 1.0);
        },
        decided);
    CHECK(decided > 400 * 200 * 9 / 10);
    CHECK(wrong == 0);
    // Without perspective, the square's near and far edges have the same width when seen at a slant.
    given.eyeM = {kHalfSide, -1000.0, 1000.0};
    given.lookAtM = {kHalfSide, kHalfSide, 0.0};
    given.up = {0.0, 0.0, 1.0};
    s.view = makeViewCamera(g, CameraKind::Orthographic, given, 2.0);
    const Film slant = renderTerrain(g, surface, s);
    std::vector<int> widths;
    for (int y = 0; y < 200; ++y) {
        int n = 0;
        for (int x = 0; x < 400; ++x) n += terrainAt(slant, x, y);
        if (n > 0) widths.push_back(n);
    }
    REQUIRE(widths.size() > 20);
    CHECK(std::abs(widths[2] - widths[widths.size() - 3]) <= 1);
}

TEST_CASE("render's default panorama and fisheye stand 2 m above the ground at the centre", "[tracer][views]") {
    std::vector<float> z(size_t(21 * 11), 100.0f);
    z[size_t(5 * 21 + 10)] = 250.0f;  // the centre vertex (10, 5)
    const HeightGrid g(21, 11, 30.0, 20.0, z);
    const ViewCamera pano = makeViewCamera(g, CameraKind::Panorama, std::nullopt, 2.0);
    CHECK(pano.eye().x == Approx(300.0));
    CHECK(pano.eye().y == Approx(100.0));
    CHECK(pano.eye().z == Approx(252.0));
    CHECK(pano.forward().y == Approx(1.0));  // north in the middle
    const ViewCamera fish = makeViewCamera(g, CameraKind::Fisheye, std::nullopt, 1.0);
    CHECK(fish.eye().z == Approx(252.0));
    CHECK(fish.forward().z == Approx(1.0));  // the zenith
    // The centre of the picture looks straight up; its top edge looks north.
    const auto top = fish.generate(0.5, 0.0);
    REQUIRE(top);
    CHECK(top->dir.y == Approx(1.0).margin(1e-9));
    PinholeCamera withFov;
    withFov.eyeM = {0, 0, 300};
    withFov.lookAtM = {100, 100, 300};
    withFov.fovGiven = true;
    CHECK_THROWS_WITH(makeViewCamera(g, CameraKind::Panorama, withFov, 2.0),
                      "--camera: fov does not apply to --view panorama (found fov=40)");
}

namespace {

// A bright square on black at the picture's centre (a flat patch of valid cells in a grid of nodata), so every
// pixel on its outline is part terrain, part sky.
struct EdgeScene {
    HeightGrid grid;
    TerrainRenderSettings settings;
};

EdgeScene edgeScene(int width, int height) {
    const int64_t n = 41;
    std::vector<float> z(size_t(n * n), 0.0f);
    std::vector<uint8_t> valid(size_t(n * n), 0);
    for (int64_t j = 12; j <= 28; ++j)
        for (int64_t i = 12; i <= 28; ++i) valid[size_t(j * n + i)] = 1;
    EdgeScene e{HeightGrid(n, n, 10.0, 10.0, z, valid), plainSettings(width, height)};
    // Looking almost straight down, the square's outline runs at a slant across the pixels.
    e.settings.camera.eyeM = {200.0, 200.0, 2000.0};
    e.settings.camera.lookAtM = {200.0, 200.0, 0.0};
    e.settings.camera.up = {std::sin(0.3), std::cos(0.3), 0.0};
    e.settings.camera.fovYDeg = 7.0;
    return e;
}

// A picture rendered at `factor` times the resolution, one ray per subpixel, filtered down in the test: the
// box filter averages each pixel's subpixels, the tent (radius 1) weighs the subpixels within a pixel of the
// centre by (1 - |dx|)(1 - |dy|).
Film supersampled(int width, int height, int factor, bool tent) {
    EdgeScene fine = edgeScene(width * factor, height * factor);
    const TerrainSurface surface(fine.grid, SurfaceMethod::Bilinear);
    const Film f = renderTerrain(fine.grid, surface, fine.settings);
    Film out(width, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            glm::dvec3 sum{0.0};
            double weights = 0.0;
            for (int sy = (y - 1) * factor; sy < (y + 2) * factor; ++sy)
                for (int sx = (x - 1) * factor; sx < (x + 2) * factor; ++sx) {
                    if (sx < 0 || sy < 0 || sx >= f.width || sy >= f.height) continue;
                    const double dx = (sx + 0.5) / factor - (x + 0.5), dy = (sy + 0.5) / factor - (y + 0.5);
                    const double w = tent ? std::max(0.0, 1.0 - std::abs(dx)) * std::max(0.0, 1.0 - std::abs(dy))
                                          : (std::abs(dx) < 0.5 && std::abs(dy) < 0.5 ? 1.0 : 0.0);
                    sum += w * glm::dvec3(f.get(sx, sy));
                    weights += w;
                }
            out.set(x, y, glm::vec3(sum / weights));
        }
    return out;
}

// The largest and the mean difference in green over the pixels where the reference is neither black nor
// fully lit: the outline.
struct EdgeError {
    double worst = 0.0, mean = 0.0;
    int pixels = 0;
};
EdgeError edgeError(const Film& a, const Film& reference) {
    float lit = 0.0f;
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) lit = std::max(lit, reference.get(x, y).g);
    EdgeError e;
    for (int y = 0; y < reference.height; ++y)
        for (int x = 0; x < reference.width; ++x) {
            const float r = reference.get(x, y).g;
            if (r < 0.02f * lit || r > 0.98f * lit) continue;
            const double d = std::abs(double(a.get(x, y).g) - r) / lit;
            e.worst = std::max(e.worst, d);
            e.mean += d;
            ++e.pixels;
        }
    if (e.pixels > 0) e.mean /= e.pixels;
    return e;
}

}  // namespace

TEST_CASE("render --spp: anti-aliased outlines match a supersampled picture filtered in the test",
          "[tracer][views][sampling]") {
    const int width = 64, height = 48;
    for (const bool tent : {false, true}) {
        INFO((tent ? "tent filter" : "box filter"));
        const Film reference = supersampled(width, height, 16, tent);
        EdgeScene e = edgeScene(width, height);
        const TerrainSurface surface(e.grid, SurfaceMethod::Bilinear);
        const Film aliased = renderTerrain(e.grid, surface, e.settings);
        e.settings.sampling =
            PixelSampling::make(256, SamplePattern::Stratified, tent ? FilterKind::Tent : FilterKind::Box, false, 0.0);
        RenderStats stats;
        const Film smooth = renderTerrain(e.grid, surface, e.settings, &stats);
        CHECK(stats.primaryRays == int64_t(width) * height * 256);
        const EdgeError before = edgeError(aliased, reference), after = edgeError(smooth, reference);
        REQUIRE(after.pixels > 100);
        // One ray per pixel is all or nothing on the outline (about a quarter off on average); 256 stratified
        // samples are within a few percent everywhere.
        CHECK(before.mean > 0.15);
        CHECK(after.mean < 0.01);
        CHECK(after.worst < 0.05);
    }
}

TEST_CASE("render --adaptive: flat pixels stop at the minimum, outlines take more samples",
          "[tracer][views][sampling]") {
    EdgeScene e = edgeScene(64, 48);
    const TerrainSurface surface(e.grid, SurfaceMethod::Bilinear);
    e.settings.sampling = PixelSampling::make(256, SamplePattern::Stratified, FilterKind::Box, true, 0.002);
    RenderStats stats;
    const Film adaptive = renderTerrain(e.grid, surface, e.settings, &stats);
    const int64_t pixels = 64 * 48;
    // Uniform pixels (all sky or all terrain) have no variance: 16 samples each. The outline's pixels go on.
    CHECK(stats.primaryRays > pixels * 16 + 50 * 100);
    CHECK(stats.primaryRays < pixels * 64);
    const Film reference = supersampled(64, 48, 16, false);
    CHECK(edgeError(adaptive, reference).mean < 0.03);
}
