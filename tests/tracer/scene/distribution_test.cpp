// Distribution ray tracing through the scene renderer, against geometry: the penumbra of a sphere under a
// spherical light and of a wall or terrain step under the sun's disc, the coverage of a sphere moving across
// the shutter and the smear of a moving camera, the blur of a point off the focus plane, the spread of glossy
// reflections, how fast soft-shadow noise falls with the sample count, pixel filters across an edge, and the
// sample counts of adaptive sampling.
#include "support/convergence.h"
#include "support/scene_builders.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

using namespace terracast;
using namespace terracast::testing;

namespace {

MaterialDescription matte(const std::string& name, float kd) {
    MaterialDescription m;
    m.name = name;
    m.colour = glm::vec3(1.0f);
    m.kd = kd;
    return m;
}

// A one-pixel-high orthographic strip looking straight down on the line y = 0, x in [x0, x1].
CameraDescription stripCamera(double x0, double x1, double z) {
    CameraDescription c;
    c.kind = CameraKind::Orthographic;
    c.eye = glm::dvec3(0.5 * (x0 + x1), 0.0, z);
    c.lookAt = glm::dvec3(0.5 * (x0 + x1), 0.0, z - 1.0);
    c.up = {0, 1, 0};
    return c;
}

Film render(const SceneDescription& d, int width, int height, int spp, SamplePattern pattern, uint64_t seed = 0) {
    Scene scene(d, {});
    SceneRenderSettings s;
    s.width = width;
    s.height = height;
    s.samples = spp;
    s.pattern = pattern;
    s.seed = seed;
    s.threads = 2;
    return renderScene(scene, makeSceneCamera(scene, d.camera, double(width) / height), s);
}

// Angular radius of a sphere of radius r seen from distance d.
double angularRadius(double r, double d) { return std::asin(std::min(1.0, r / d)); }

// A black half-plane (x < edge) under a white sky, seen from above by a strip camera `width` pixels wide and
// `height` high with 1 m pixels.
SceneDescription blackHalfPlane(double edge, int width, int height) {
    SceneDescription d;
    d.materials.push_back(matte("black", 0.0f));
    d.objects.push_back(box({-100.0, -5000.0, -1.0}, {edge, 5000.0, 0.0}, "black"));
    d.sky.kind = SkyKind::Flat;
    d.sky.colour = glm::vec3(1.0f);
    d.camera = stripCamera(0.0, double(width), 10.0);
    d.camera.orthoHeightM = double(height);
    return d;
}

}  // namespace

TEST_CASE("The penumbra behind a sphere under a spherical light spans the predicted interval", "[distribution]") {
    // Light of radius 1 at height 10, occluder of radius 1 at height 5, both above the origin; floor at z = 0.
    const double lightR = 1.0, lightH = 10.0, occR = 1.0, occH = 5.0;
    SceneDescription d;
    d.materials.push_back(matte("floor", 1.0f));
    ObjectDescription floor;
    floor.kind = ObjectKind::Plane;
    floor.material = "floor";
    d.objects.push_back(floor);
    d.sky.kind = SkyKind::None;
    LightDescription light;
    light.kind = LightKind::Sphere;
    light.position = {0, 0, lightH};
    light.radiusM = lightR;
    light.intensity = 100.0f;
    d.lights.push_back(light);
    const double x0 = 0.0, x1 = 8.0;
    const int width = 400;
    // The camera sits just above the floor, below the occluder, so it sees only the floor.
    d.camera = stripCamera(x0, x1, 0.5);
    d.camera.orthoHeightM = (x1 - x0) / width;  // square pixels
    const Film lit = render(d, width, 1, 256, SamplePattern::Stratified);
    d.objects.push_back(sphere({0, 0, occH}, occR, "floor"));
    const Film shadowed = render(d, width, 1, 256, SamplePattern::Stratified);

    // Seen from a floor point, the light and the occluder are discs on the sky of angular radii aL and aO whose
    // centres are theta apart: fully lit once theta >= aL + aO, in umbra while theta <= aO - aL. These are the
    // similar-triangles edges of the shadow, measured along the floor.
    auto edge = [&](bool outer) {
        double lo = 0.0, hi = x1;
        for (int k = 0; k < 100; ++k) {
            const double x = 0.5 * (lo + hi);
            const glm::dvec3 p{x, 0, 0}, toL{-x, 0, lightH}, toO{-x, 0, occH};
            const double theta = std::acos(glm::dot(glm::normalize(toL), glm::normalize(toO)));
            const double aL = angularRadius(lightR, glm::length(toL)), aO = angularRadius(occR, glm::length(toO));
            const bool beyond = outer ? theta >= aL + aO : theta > aO - aL;
            (beyond ? hi : lo) = x;
        }
        return 0.5 * (lo + hi);
    };
    const double inner = edge(false), outer = edge(true);
    INFO("umbra ends at " << inner << " m, penumbra at " << outer << " m");
    // Similar triangles on the vertical section: the penumbra's outer edge near x = occR * lightH / (lightH - occH)
    // + lightR * occH / (lightH - occH) = 3 m, the umbra near (occR * lightH - lightR * occH) / (lightH - occH) = 1 m.
    CHECK(outer == Approx(3.0).margin(0.35));
    CHECK(inner == Approx(1.0).margin(0.35));
    const double pixel = (x1 - x0) / width;
    int umbra = 0, penumbra = 0, full = 0;
    for (int i = 0; i < width; ++i) {
        const double x = x0 + (i + 0.5) * pixel;
        const double v = double(shadowed.get(i, 0).r / lit.get(i, 0).r);
        if (x < inner - 2 * pixel) {
            CHECK(v == 0.0);
            ++umbra;
        } else if (x > outer + 2 * pixel) {
            CHECK(v == Approx(1.0).epsilon(1e-6));
            ++full;
        } else if (x > inner + 0.1 * (outer - inner) && x < outer - 0.1 * (outer - inner)) {
            // Near its edges the penumbra's partial cover is too thin for 256 samples to see.
            CHECK(v > 0.0);
            CHECK(v < 1.0);
            ++penumbra;
        }
    }
    CHECK(umbra > 20);
    CHECK(penumbra > 50);
    CHECK(full > 100);
}

TEST_CASE("A sphere moving across the shutter covers each pixel on its path for the predicted time", "[distribution]") {
    // A black sphere of radius 1 moves from x = -5 to x = 5 during the shutter; the sky is white. A point x on
    // the path is covered while |x - (-5 + 10 t)| <= 1: for a fifth of the shutter when |x| <= 4.
    SceneDescription d;
    d.materials.push_back(matte("black", 0.0f));
    d.objects.push_back(sphere({-5, 0, 0}, 1.0, "black"));
    d.objects.back().velocity = {10, 0, 0};
    d.sky.kind = SkyKind::Flat;
    d.sky.colour = glm::vec3(1.0f);
    d.camera = stripCamera(-8.0, 8.0, 10.0);
    d.camera.shutterOpen = 0.0;
    d.camera.shutterClose = 1.0;
    const int width = 320;
    d.camera.orthoHeightM = 16.0 / width;
    const Film film = render(d, width, 1, 256, SamplePattern::Stratified);
    auto coverage = [](double x) {
        const double t0 = std::clamp((x + 4.0) / 10.0, 0.0, 1.0), t1 = std::clamp((x + 6.0) / 10.0, 0.0, 1.0);
        return t1 - t0;
    };
    for (int i = 0; i < width; ++i) {
        const double x = -8.0 + (i + 0.5) * 16.0 / width;
        if (std::abs(std::abs(x) - 4.0) < 0.15 || std::abs(std::abs(x) - 6.0) < 0.15) continue;  // kinks
        INFO("x = " << x);
        CHECK(1.0 - double(film.get(i, 0).r) == Approx(coverage(x)).margin(0.01));
    }
}

TEST_CASE("A thin lens blurs a point off the focus plane over the predicted circle of confusion", "[distribution][heavy]") {
    // Camera at the origin looking north, focused at 10 m with a 0.1 m lens radius, fov 10 degrees over 200
    // pixels. A small black ball on a white sky: at the focus distance it keeps its own size; at 5 m it spreads
    // by the circle of confusion, 2 a |z - f| / z on the focus plane, seen from the lens.
    const double a = 0.1, f = 10.0, fov = 10.0;
    const int size = 200;
    const double pixelsPerRadian = size / (2.0 * std::tan(fov * M_PI / 360.0));
    auto darkWidth = [&](double z, double r) {
        SceneDescription d;
        d.materials.push_back(matte("black", 0.0f));
        d.objects.push_back(sphere({0, z, 0}, r, "black"));
        d.sky.kind = SkyKind::Flat;
        d.sky.colour = glm::vec3(1.0f);
        d.camera.kind = CameraKind::ThinLens;
        d.camera.eye = glm::dvec3(0.0);
        d.camera.lookAt = glm::dvec3(0, 1, 0);
        d.camera.fovDeg = fov;
        d.camera.apertureRadiusM = a;
        d.camera.focusDistanceM = f;
        const Film film = render(d, size, size, 256, SamplePattern::Stratified);
        // Width of the pixels along the middle row that lose any light, and of the transition zone.
        int dark = 0, partial = 0;
        for (int x = 0; x < size; ++x) {
            const float v = film.get(x, size / 2).r;
            dark += v < 0.995f;
            partial += v > 0.01f && v < 0.99f;
        }
        return std::pair<double, double>(dark, partial);
    };
    const double r = 0.02;
    const auto [sharp, sharpEdge] = darkWidth(f, 2.0 * r);
    CHECK(sharp == Approx(2.0 * 2.0 * r / f * pixelsPerRadian).margin(2.0));
    CHECK(sharpEdge <= 4.0);
    const auto [blurred, blurredEdge] = darkWidth(5.0, r);
    const double coc = 2.0 * a * std::abs(5.0 - f) / 5.0 / f;  // radians, as seen from the lens
    INFO("predicted width " << (coc + 2.0 * r / 5.0) * pixelsPerRadian << " px");
    CHECK(blurred == Approx((coc + 2.0 * r / 5.0) * pixelsPerRadian).margin(3.0));
    CHECK(blurredEdge > 10.0);
}

TEST_CASE("Glossy reflections spread around the mirror direction by the Phong lobe", "[distribution]") {
    SceneDescription d;
    MaterialDescription m;
    m.name = "brushed";
    m.kd = 0.0f;
    m.mirror = glm::vec3(0.9f);
    m.gloss = 50.0f;
    d.materials.push_back(m);
    ObjectDescription floor;
    floor.kind = ObjectKind::Plane;
    floor.material = "brushed";
    d.objects.push_back(floor);
    d.sky.kind = SkyKind::Flat;
    d.camera.eye = glm::dvec3(0, 0, 5);
    d.camera.lookAt = glm::dvec3(0, 5, 0);
    d.render.width = d.render.height = 1;
    Scene scene(d, {});
    const ViewCamera cam = makeSceneCamera(scene, d.camera, 1.0);
    SceneRenderSettings s;
    s.width = s.height = 1;
    s.samples = 4096;
    s.pattern = SamplePattern::Random;
    s.maxDepth = 1;
    std::vector<RayRecord> tree;
    tracePixel(scene, cam, s, 0, 0, &tree);
    // Under a lobe proportional to cos^n the mean cosine to the axis is (n + 1) / (n + 2); the pixel's film
    // positions vary a little, so the mirror direction of each primary ray is the axis.
    double sumCos = 0.0;
    int reflections = 0;
    glm::dvec3 mirrorDir{0.0};
    for (const RayRecord& r : tree) {
        if (r.kind == RayKind::Primary) mirrorDir = glm::dvec3(r.dir.x, r.dir.y, -r.dir.z);
        if (r.kind != RayKind::Reflection) continue;
        REQUIRE(r.dir.z > 0.0);
        sumCos += glm::dot(r.dir, mirrorDir);
        ++reflections;
    }
    REQUIRE(reflections == 4096);
    CHECK(sumCos / reflections == Approx(51.0 / 52.0).margin(0.002));
}

TEST_CASE("Soft-shadow noise falls as 1/sqrt(spp) with random samples and faster with stratified ones", "[distribution]") {
    // A sphere between a floor and a spherical light; the camera looks down on the penumbra.
    SceneDescription d;
    d.materials.push_back(matte("floor", 1.0f));
    ObjectDescription floor;
    floor.kind = ObjectKind::Plane;
    floor.material = "floor";
    d.objects.push_back(floor);
    d.objects.push_back(sphere({0, 0, 5}, 1.0, "floor"));
    d.sky.kind = SkyKind::None;
    LightDescription light;
    light.kind = LightKind::Sphere;
    light.position = {0, 0, 10};
    light.radiusM = 1.5;
    light.intensity = 100.0f;
    d.lights.push_back(light);
    d.camera.kind = CameraKind::Orthographic;
    d.camera.eye = glm::dvec3(2.0, 0.0, 20.0);
    d.camera.lookAt = glm::dvec3(2.0, 0.0, 0.0);
    d.camera.up = {0, 1, 0};
    d.camera.orthoHeightM = 3.0;
    const int size = 24;
    const Film reference = render(d, size, size, 4096, SamplePattern::Stratified, 99);
    auto rms = [&](SamplePattern pattern, int spp) {
        double sum = 0.0;
        int n = 0;
        for (uint64_t seed = 1; seed <= 4; ++seed) {
            const Film f = render(d, size, size, spp, pattern, seed);
            for (size_t k = 0; k < f.rgb.size(); k += 3) {
                const double e = double(f.rgb[k]) - double(reference.rgb[k]);
                sum += e * e;
                ++n;
            }
        }
        return std::sqrt(sum / n);
    };
    const std::vector<double> counts{4, 16, 64, 256};
    std::vector<double> random, stratified;
    for (double n : counts) {
        random.push_back(rms(SamplePattern::Random, int(n)));
        stratified.push_back(rms(SamplePattern::Stratified, int(n)));
    }
    const PowerLawFit r = fitPowerLaw(counts, random), s = fitPowerLaw(counts, stratified);
    INFO("random slope " << r.exponent << ", stratified slope " << s.exponent);
    CHECK(r.exponent == Approx(-0.5).margin(0.1));
    CHECK(s.exponent < r.exponent - 0.15);
    CHECK(stratified.back() < random.back());
}

namespace {

// The share of a disc of angular radius a that lies beyond a straight edge crossing it at angular distance
// `offset` from its centre (positive when the centre is on the visible side): a circular segment.
double discShareBeyond(double offset, double a) {
    const double u = std::clamp(-offset / a, -1.0, 1.0);
    return (std::acos(u) - u * std::sqrt(1.0 - u * u)) / M_PI;
}

}  // namespace

TEST_CASE("The sun's disc casts a penumbra of the similar-triangles width behind an edge, a point sun none",
          "[distribution]") {
    // A wall (a box, or the step of a plateau in a height grid) whose top edge runs along y at x = 0, z = H; the
    // sun in the west at elevation e. Its shadow on the floor (z = 0) ends at x = H / tan(e). A floor point x
    // sees the edge at elevation atan(H / x), so the sun's disc of angular radius a is partly hidden while that
    // elevation is within a of e: the penumbra runs from H / tan(e + a) to H / tan(e - a). By similar triangles
    // the edge lies D = H / sin(e) from its shadow along the sun's rays; across them the penumbra spans
    // 2 D tan(a), stretched on the floor by 1 / sin(e).
    const double H = 5.0, e = 45.0 * M_PI / 180.0;
    const double x0 = 3.5, x1 = 6.5;
    const int width = 300;
    const double pixel = (x1 - x0) / width;
    for (const bool terrain : {false, true}) {
        for (const double aDeg : {2.0, 0.0}) {
            INFO((terrain ? "plateau of a height grid" : "box") << ", sun radius " << aDeg << " degrees");
            const double a = aDeg * M_PI / 180.0;
            SceneDescription d;
            SceneAssets assets;
            d.materials.push_back(matte("white", 1.0f));
            if (terrain) {
                // 0.5 m cells from x = -3 to 8 and y = -10 to 10; heights H up to x = 0, then 0.
                const int w = 23, h = 41;
                std::vector<float> heights(size_t(w) * h);
                for (int j = 0; j < h; ++j)
                    for (int i = 0; i < w; ++i) heights[size_t(j) * w + size_t(i)] = -3.0 + 0.5 * i <= 0.0 ? float(H) : 0.0f;
                assets.grids.push_back(std::make_shared<const HeightGrid>(w, h, 0.5, 0.5, heights));
                ObjectDescription plateau;
                plateau.kind = ObjectKind::HeightField;
                plateau.offsetM = {-3.0, -10.0, 0.0};
                d.objects.push_back(plateau);
            } else {
                ObjectDescription floor;
                floor.kind = ObjectKind::Plane;
                floor.material = "white";
                d.objects.push_back(floor);
                ObjectDescription wall;
                wall.kind = ObjectKind::Box;
                wall.boxMin = {-3.0, -50.0, 0.0};
                wall.boxMax = {0.0, 50.0, H};
                wall.material = "white";
                d.objects.push_back(wall);
            }
            d.sky.kind = SkyKind::None;
            LightDescription sun;
            sun.azimuthDeg = 270.0;
            sun.elevationDeg = 45.0;
            sun.angularRadiusDeg = aDeg;
            d.lights.push_back(sun);
            d.camera = stripCamera(x0, x1, 1.0);
            d.camera.orthoHeightM = pixel;
            Scene scene(d, assets);
            SceneRenderSettings s;
            s.width = width;
            s.height = 1;
            s.samples = 256;
            s.threads = 2;
            const Film film = renderScene(scene, makeSceneCamera(scene, d.camera, double(width)), s);
            // Fully lit brightness, from the pixels beyond the widest penumbra.
            double lit = 0.0;
            int litPixels = 0;
            for (int i = 0; i < width; ++i)
                if (x0 + (i + 0.5) * pixel > 6.0) lit += film.get(i, 0).r, ++litPixels;
            lit /= litPixels;
            REQUIRE(lit > 0.1);

            int lastDark = -1, firstLit = width;
            for (int i = 0; i < width; ++i) {
                const double x = x0 + (i + 0.5) * pixel;
                const double v = film.get(i, 0).r / lit;
                if (v < 1e-3) lastDark = i;
                if (v > 1.0 - 1e-3 && firstLit == width) firstLit = i;
                if (a > 0.0) {
                    INFO("x = " << x);
                    CHECK(v == Approx(discShareBeyond(e - std::atan(H / x), a)).margin(0.03));
                }
            }
            REQUIRE(lastDark >= 0);
            REQUIRE(firstLit < width);
            const double measured = (firstLit - lastDark - 1) * pixel;  // pixels neither dark nor fully lit
            if (a > 0.0) {
                const double D = H / std::sin(e);
                const double predicted = 2.0 * D * std::tan(a) / std::sin(e);
                INFO("penumbra " << measured << " m, predicted " << predicted << " m");
                CHECK(predicted == Approx(H / std::tan(e - a) - H / std::tan(e + a)).epsilon(0.01));
                CHECK(measured == Approx(predicted).margin(4.0 * pixel));
                CHECK(x0 + (lastDark + 0.5) * pixel == Approx(H / std::tan(e + a)).margin(4.0 * pixel));
            } else {
                // A hard edge: at most the one pixel the edge crosses is partly lit, and it lies at H / tan(e).
                CHECK(firstLit - lastDark - 1 <= 1);
                CHECK(x0 + (lastDark + 1) * pixel == Approx(H / std::tan(e)).margin(pixel));
            }
        }
    }
}

TEST_CASE("A moving camera smears a static sphere over the span it travels", "[distribution]") {
    // A black ball of radius 1 at the origin under a white sky; an orthographic camera moving east at 4 m/s over
    // a one-second shutter. The ray that starts over x sweeps x + 4 t, so the ball darkens the film from
    // x = -1 - 4 to x = 1, a span of 2 + 4 m, and each point for the time its ray spends within 1 m of the centre.
    const double v = 4.0, r = 1.0;
    SceneDescription d;
    d.materials.push_back(matte("black", 0.0f));
    d.objects.push_back(sphere({0, 0, 0}, r, "black"));
    d.sky.kind = SkyKind::Flat;
    d.sky.colour = glm::vec3(1.0f);
    d.camera = stripCamera(-8.0, 8.0, 10.0);
    d.camera.shutterOpen = 0.0;
    d.camera.shutterClose = 1.0;
    d.camera.velocity = {v, 0.0, 0.0};
    const int width = 320;
    const double pixel = 16.0 / width;
    d.camera.orthoHeightM = pixel;
    const Film film = render(d, width, 1, 256, SamplePattern::Stratified);
    auto coverage = [&](double x) {
        const double t0 = std::clamp((-r - x) / v, 0.0, 1.0), t1 = std::clamp((r - x) / v, 0.0, 1.0);
        return t1 - t0;
    };
    int dark = 0;
    for (int i = 0; i < width; ++i) {
        const double x = -8.0 + (i + 0.5) * pixel;
        const double covered = 1.0 - double(film.get(i, 0).r);
        dark += covered > 1e-3;
        if (std::abs(x - 1.0) < 0.15 || std::abs(x + 1.0) < 0.15 || std::abs(x + 3.0) < 0.15 || std::abs(x + 5.0) < 0.15)
            continue;  // kinks of the coverage curve
        INFO("x = " << x);
        CHECK(covered == Approx(coverage(x)).margin(0.01));
    }
    CHECK(dark == Approx((2.0 * r + v) / pixel).margin(2.0));
}

TEST_CASE("Tent and Gaussian filters spread a straight edge over the pixels their footprints reach",
          "[distribution]") {
    // A black half-plane (x < 10.1 m) under a white sky, seen from above with 1 m pixels. A pixel whose centre
    // is at c averages its samples weighted by the filter, so it shows the share of the filter's 1D profile
    // that lies beyond the edge: the integral of f1 from (10.1 - c) to the radius.
    const double edge = 10.1, tolerance = 0.004;
    const int width = 24;
    const SceneDescription d = blackHalfPlane(edge, width, 1);
    Scene scene(d, {});
    const ViewCamera camera = makeSceneCamera(scene, d.camera, double(width));

    // Each filter's profile, written out on its own: box 1 / (2 r); tent (r - |x|) / r^2; Gaussian
    // exp(-alpha x^2) - exp(-alpha r^2), normalised by Simpson's rule.
    auto profile = [](FilterKind kind, double r, double alpha, double x) {
        if (std::abs(x) > r) return 0.0;
        switch (kind) {
        case FilterKind::Box: return 1.0;
        case FilterKind::Tent: return r - std::abs(x);
        case FilterKind::Gaussian: return std::exp(-alpha * x * x) - std::exp(-alpha * r * r);
        }
        return 0.0;
    };
    auto integral = [&](FilterKind kind, double r, double alpha, double lo, double hi) {
        lo = std::clamp(lo, -r, r);
        hi = std::clamp(hi, -r, r);
        if (hi <= lo) return 0.0;
        const int n = 2000;  // even
        const double h = (hi - lo) / n;
        double sum = profile(kind, r, alpha, lo) + profile(kind, r, alpha, hi);
        for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * profile(kind, r, alpha, lo + k * h);
        return sum * h / 3.0;
    };
    struct Case {
        FilterKind kind;
        double radius;
    };
    std::vector<std::vector<double>> profiles;
    for (const Case c : {Case{FilterKind::Box, 0.5}, Case{FilterKind::Tent, 1.0}, Case{FilterKind::Gaussian, 1.0}}) {
        INFO(filterKindName(c.kind));
        SceneRenderSettings s;
        s.width = width;
        s.height = 1;
        s.samples = 4096;
        s.threads = 2;
        s.filter.kind = c.kind;
        s.filter.radius = c.radius;
        s.filter.alpha = 2.0;
        REQUIRE_FALSE(s.filter.problem());
        const Film film = renderScene(scene, camera, s);
        const double total = integral(c.kind, c.radius, 2.0, -c.radius, c.radius);
        int partial = 0;
        std::vector<double> expected;
        for (int i = 0; i < width; ++i) {
            const double centre = i + 0.5;
            expected.push_back(integral(c.kind, c.radius, 2.0, edge - centre, c.radius) / total);
            INFO("pixel " << i);
            CHECK(double(film.get(i, 0).r) == Approx(expected.back()).margin(tolerance));
            partial += expected.back() > 1e-9 && expected.back() < 1.0 - 1e-9;
        }
        // The box reaches only the pixel the edge crosses; the wider filters reach its neighbours.
        CHECK(partial == (c.kind == FilterKind::Box ? 1 : 2));
        profiles.push_back(expected);
    }
    // The profiles differ by well over twice the tolerance, so the checks above tell the filters apart.
    for (size_t a = 0; a < profiles.size(); ++a)
        for (size_t b = a + 1; b < profiles.size(); ++b) {
            double most = 0.0;
            for (int i = 0; i < width; ++i) most = std::max(most, std::abs(profiles[a][size_t(i)] - profiles[b][size_t(i)]));
            CHECK(most > 2.5 * tolerance);
        }
}

TEST_CASE("Across an edge, tent and Gaussian pixels are no noisier than the box's at equal samples",
          "[distribution]") {
    // A black half-plane (x < 10.5 m) under a white sky, seen from above with 1 m pixels: the edge runs through
    // the centres of column 10, so under every symmetric filter that column's pixels are 0.5. Each of its 3000
    // pixels is an independent estimate from 16 random samples; their spread is the filter's noise. A filter
    // whose samples are drawn in proportion to it averages values of 0 and 1 as the box does; weighting uniform
    // samples by the filter instead gives about twice the box's noise.
    const int width = 21, height = 3000;
    const SceneDescription d = blackHalfPlane(10.5, width, height);
    Scene scene(d, {});
    const ViewCamera camera = makeSceneCamera(scene, d.camera, double(width) / height);
    double boxNoise = 0.0;
    for (const FilterKind kind : {FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian}) {
        SceneRenderSettings s;
        s.width = width;
        s.height = height;
        s.samples = 16;
        s.pattern = SamplePattern::Random;
        s.threads = 2;
        s.filter = PixelFilter::defaults(kind);
        const Film film = renderScene(scene, camera, s);
        double sum = 0.0, squares = 0.0;
        for (int y = 0; y < height; ++y) {
            const double v = film.get(10, y).r;
            sum += v;
            squares += (v - 0.5) * (v - 0.5);
        }
        const double noise = std::sqrt(squares / height);
        INFO(filterKindName(kind) << ": mean " << sum / height << ", RMS error " << noise << ", box " << boxNoise);
        CHECK(sum / height == Approx(0.5).margin(4.0 * noise / std::sqrt(double(height))));
        if (kind == FilterKind::Box) {
            boxNoise = noise;
            CHECK(noise == Approx(0.125).epsilon(0.05));  // sqrt(0.5 x 0.5 / 16)
        } else {
            CHECK(noise <= 1.06 * boxNoise);
        }
    }
}

TEST_CASE("Adaptive sampling stops flat pixels at the minimum and spends the maximum on edges", "[distribution]") {
    // A black box covers x < 10.5 of a 16 x 8 m view with 1 m pixels; the sky is white. Pixels wholly on one
    // side see one value, so their standard error is 0 as soon as the rule allows stopping; pixels of column
    // 10 are half black, their standard error near 0.5 / sqrt(n) stays far above the threshold up to the cap.
    SceneDescription d;
    d.materials.push_back(matte("black", 0.0f));
    ObjectDescription half;
    half.kind = ObjectKind::Box;
    half.boxMin = {-100.0, -100.0, -1.0};
    half.boxMax = {10.5, 100.0, 0.0};
    half.material = "black";
    d.objects.push_back(half);
    d.sky.kind = SkyKind::Flat;
    d.sky.colour = glm::vec3(1.0f);
    d.camera.kind = CameraKind::Orthographic;
    d.camera.eye = glm::dvec3(8.0, 4.0, 10.0);
    d.camera.lookAt = glm::dvec3(8.0, 4.0, 0.0);
    d.camera.up = {0, 1, 0};
    d.camera.orthoHeightM = 8.0;
    Scene scene(d, {});
    const ViewCamera camera = makeSceneCamera(scene, d.camera, 2.0);
    SceneRenderSettings s;
    s.width = 16;
    s.height = 8;
    s.threads = 2;
    s.adaptive = true;
    s.rule.minSamples = 16;
    s.rule.maxSamples = 64;
    s.rule.absoluteError = 0.002;
    s.rule.relativeError = 0.01;
    SceneRayStats stats;
    const Film film = renderScene(scene, camera, s, &stats);
    CHECK(stats.samples == 8 * (15 * 16 + 64));
    CHECK(stats.primary == stats.samples);
    for (int y = 0; y < 8; ++y) {
        INFO("row " << y);
        for (int x = 0; x < 16; ++x) {
            SceneRayStats one;
            tracePixel(scene, camera, s, x, y, nullptr, &one);
            CHECK(one.samples == (x == 10 ? 64 : 16));
        }
        CHECK(film.get(9, y).r == 0.0f);
        CHECK(film.get(11, y).r == 1.0f);
        CHECK(film.get(10, y).r == Approx(0.5f).margin(0.1));
    }
    // Without adaptivity every pixel takes the same count.
    s.adaptive = false;
    s.samples = 64;
    renderScene(scene, camera, s, &stats);
    CHECK(stats.samples == 16 * 8 * 64);
}
