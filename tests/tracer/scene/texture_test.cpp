// Textures on primitives: a checker on a level and on an upright plane, square by square against the parity of
// the hit point's coordinates computed here, and an image (written with GDAL as a PNG) on a sphere, each
// quadrant where the sphere's longitude and latitude put it.
#include "support/scene_builders.h"
#include "support/temp_dir.h"
#include "loaders/scene_assets.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>
#include <gdal_priv.h>

#include <cmath>

using namespace terracast;
using namespace terracast::testing;

namespace {

const glm::vec3 kRed{0.8f, 0.05f, 0.05f}, kBlue{0.05f, 0.05f, 0.8f};

// Lit straight along the view by a sun of irradiance 1, no sky: a diffuse pixel is its albedo times the
// cosine, so red and blue squares tell themselves apart by their dominant channel.
SceneDescription litAlong(const glm::dvec3& toSun) {
    SceneDescription d;
    LightDescription sun;
    sun.kind = LightKind::Sun;
    sun.azimuthDeg = glm::degrees(std::atan2(toSun.x, toSun.y));
    sun.elevationDeg = glm::degrees(std::asin(toSun.z));
    d.lights.push_back(sun);
    d.sky.kind = SkyKind::None;
    d.render.width = 120;
    d.render.height = 90;
    return d;
}

// Renders the description through `camera` and checks every pixel whose ray meets the plane (through the
// origin, with unit normal `n`) away from a square's border: red where floor(u / s) + floor(v / s) is even,
// blue where it is odd, with u and v the coordinates along `uAxis` and `vAxis`.
void checkChecker(SceneDescription d, const glm::dvec3& n, const glm::dvec3& uAxis, const glm::dvec3& vAxis,
                  double s) {
    MaterialDescription m;
    m.name = "board";
    m.colour = kRed;
    m.checker = true;
    m.checkerColour = kBlue;
    m.textureScale = s;
    d.materials.push_back(m);
    d.objects.push_back(plane({0.0, 0.0, 0.0}, n, "board"));
    const Scene scene(d, SceneAssets{});
    const ViewCamera camera = makeSceneCamera(scene, d.camera, double(d.render.width) / d.render.height);
    const Film film = renderScene(scene, camera, settingsFor(d));
    int checked = 0, wrong = 0;
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const auto ray = camera.generate((x + 0.5) / film.width, (y + 0.5) / film.height);
            const double t = -glm::dot(ray->origin, n) / glm::dot(ray->dir, n);
            if (!(t > 0.0)) continue;
            const glm::dvec3 p = ray->at(t);
            const double u = glm::dot(p, uAxis) / s, v = glm::dot(p, vAxis) / s;
            const double border = std::min({std::abs(u - std::round(u)), std::abs(v - std::round(v))});
            if (border < 0.02) continue;
            const bool even = ((int64_t(std::floor(u)) + int64_t(std::floor(v))) & 1) == 0;
            const glm::vec3 c = film.get(x, y);
            ++checked;
            wrong += even ? !(c.r > 4.0f * c.b) : !(c.b > 4.0f * c.r);
        }
    CHECK(checked > film.width * film.height / 2);
    CHECK(wrong == 0);
}

}  // namespace

TEST_CASE("A checker on a level plane: squares of texture_scale metres along east and north", "[scene][texture]") {
    SceneDescription d = litAlong({0.0, 0.0, 1.0});
    d.camera = lookingAt({0.3, -0.2, 30.0}, {0.3, 4.0, 0.0}, 50.0);
    checkChecker(d, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, 2.5);
}

TEST_CASE("A checker on an upright plane: squares along the level and up the plane", "[scene][texture]") {
    // A wall facing south-east; u runs level along it (towards the north-east), v straight up.
    const glm::dvec3 n = glm::normalize(glm::dvec3(1.0, -1.0, 0.0));
    SceneDescription d = litAlong(n);
    d.camera = lookingAt(glm::dvec3(12.0, -12.0, 1.0), {0.0, 0.0, 1.0}, 60.0);
    checkChecker(d, n, glm::normalize(glm::dvec3(1.0, 1.0, 0.0)), {0.0, 0.0, 1.0}, 0.7);
}

TEST_CASE("An image texture on a sphere: longitude across, latitude up, repeated by texture_scale",
          "[scene][texture]") {
    TempDir dir("texture");
    // 64 x 64 in four quadrants, top row first: red (north-west), green (north-east), blue (south-west),
    // white (south-east); written as an 8-bit PNG.
    const std::string path = dir.file("quadrants.png");
    {
        GDALAllRegister();
        GDALDatasetUniquePtr mem(GetGDALDriverManager()->GetDriverByName("MEM")->Create("", 64, 64, 3, GDT_Byte, nullptr));
        const int colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
        for (int c = 0; c < 3; ++c) {
            std::vector<uint8_t> band(64 * 64);
            for (int j = 0; j < 64; ++j)
                for (int i = 0; i < 64; ++i) band[size_t(j * 64 + i)] = uint8_t(colours[(j >= 32) * 2 + (i >= 32)][c]);
            REQUIRE(mem->GetRasterBand(c + 1)->RasterIO(GF_Write, 0, 0, 64, 64, band.data(), 64, 64, GDT_Byte, 0, 0) ==
                    CE_None);
        }
        GDALDatasetUniquePtr png(GetGDALDriverManager()->GetDriverByName("PNG")->CreateCopy(path.c_str(), mem.get(),
                                                                                             FALSE, nullptr, nullptr, nullptr));
        REQUIRE(png);
    }
    const DrapeImage image = loadTexture(path);
    REQUIRE(image.width == 64);
    // The sphere seen from the south (-y): its visible middle has longitude -90 degrees from +x, u = 0.25,
    // the middle of the image's left half; above the equator v > 0.5, the image's top half.
    SceneDescription d = litAlong({0.0, -1.0, 0.0});
    d.camera = lookingAt({0.0, -10.0, 0.0}, {0.0, 0.0, 0.0}, 15.0);
    MaterialDescription m;
    m.name = "globe";
    m.texturePath = path;
    d.materials.push_back(m);
    d.objects.push_back(sphere({0.0, 0.0, 0.0}, 1.0, "globe"));
    const LoadedSceneAssets loaded = loadSceneAssets(d);
    const Scene scene(d, loaded.assets);
    const ViewCamera camera = makeSceneCamera(scene, d.camera, double(d.render.width) / d.render.height);
    const Film film = renderScene(scene, camera, settingsFor(d));
    const auto at = [&](double fx, double fy) { return film.get(int(fx * film.width), int(fy * film.height)); };
    // Just above and below the middle of the disc, a little to the left (further west, u < 0.25) and right.
    for (const double fx : {0.47, 0.53}) {
        const glm::vec3 north = at(fx, 0.42), south = at(fx, 0.58);
        INFO("fx " << fx);
        CHECK(north.r > 5.0f * std::max(north.g, north.b));  // red
        CHECK(south.b > 5.0f * std::max(south.r, south.g));  // blue
    }
    // With texture_scale 0.5 the image repeats twice around and twice from pole to pole. Just above the equator
    // (v = 0.57) the repeat is at 0.13 of its height, in the image's bottom half; left of the middle
    // (u = 0.22, u / 0.5 = 0.44) its left half, right of it (u = 0.28, u / 0.5 = 0.56) its right half.
    d.materials.back().textureScale = 0.5;
    const Scene repeated(d, loaded.assets);
    const Film film2 = renderScene(repeated, camera, settingsFor(d));
    const glm::vec3 west = film2.get(int(0.45 * film2.width), int(0.42 * film2.height));
    const glm::vec3 east = film2.get(int(0.55 * film2.width), int(0.42 * film2.height));
    CHECK(west.b > 5.0f * std::max(west.r, west.g));  // blue: the south-west quadrant
    CHECK(east.r > 0.5f * east.b);                     // white: the south-east quadrant
    CHECK(east.g > 0.5f * east.b);
}
