// The image sky: the equirectangular layout and its rotation, the light it casts on a surface of any
// orientation against the cosine-lobe integrals of a sky bright on one side of a plane, and a scene lit only
// by an EXR written and read back (a white furnace, a sphere lit from the east).
#include "support/scene_builders.h"
#include "support/temp_dir.h"
#include "loaders/image_io.h"
#include "loaders/scene_assets.h"
#include "tracer/sky/sky.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <functional>

using namespace terracast;
using namespace terracast::testing;

namespace {

constexpr double kPiD = 3.14159265358979323846;

// A width x height environment whose pixel (i, j) holds value(i, j) in every channel.
EnvironmentImage environment(int width, int height, const std::function<float(int, int)>& value) {
    EnvironmentImage e;
    e.width = width;
    e.height = height;
    e.rgb.resize(size_t(width) * height * 3);
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i)
            for (int c = 0; c < 3; ++c) e.rgb[(size_t(j) * width + i) * 3 + c] = value(i, j);
    return e;
}

// The unit direction at azimuth (clockwise from north) and angle from the zenith, in degrees.
glm::dvec3 direction(double azimuthDeg, double fromZenithDeg) {
    const double a = azimuthDeg * kPiD / 180.0, z = fromZenithDeg * kPiD / 180.0;
    return {std::sin(z) * std::sin(a), std::sin(z) * std::cos(a), std::cos(z)};
}

Sky imageSky(EnvironmentImage image, double rotationDeg = 0.0) {
    SkyDescription d;
    d.kind = SkyKind::Image;
    d.image = std::make_shared<const EnvironmentImage>(std::move(image));
    d.rotationDeg = rotationDeg;
    return Sky(d, std::nullopt, 0.0);
}

}  // namespace

TEST_CASE("Image sky: the middle column looks north, east to the right, the top row at the zenith", "[sky][image]") {
    CHECK(environmentCoordinates({0.0, 1.0, 0.0}).x == Approx(0.5));
    CHECK(environmentCoordinates({1.0, 0.0, 0.0}).x == Approx(0.75));
    CHECK(environmentCoordinates({-1.0, 0.0, 0.0}).x == Approx(0.25));
    CHECK(environmentCoordinates({0.0, 1.0, 0.0}).y == Approx(0.5));
    CHECK(environmentCoordinates({0.0, 0.0, 1.0}).y == Approx(0.0));
    // Each pixel a value of its own: a direction through a pixel's centre reads exactly that pixel.
    const EnvironmentImage e = environment(16, 8, [](int i, int j) { return float(1 + i + 16 * j); });
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 16; ++i) {
            const glm::dvec3 dir = direction(((i + 0.5) / 16.0 - 0.5) * 360.0, (j + 0.5) / 8.0 * 180.0);
            CHECK(environmentRadiance(e, dir, 0.0).r == Approx(1 + i + 16 * j));
            // Turned by 90 degrees clockwise, what was north is seen in the east.
            CHECK(environmentRadiance(e, direction(((i + 0.5) / 16.0 - 0.5) * 360.0 + 90.0, (j + 0.5) / 8.0 * 180.0),
                                      90.0)
                      .r == Approx(1 + i + 16 * j));
        }
}

TEST_CASE("Image sky: the light on a surface is the cosine-weighted mean about its normal", "[sky][image]") {
    // Bright above the horizon, dark below: a surface whose normal stands phi above the horizon sees the
    // bright half over (1 + sin phi) / 2 of its cosine lobe. Bright in the east, dark in the west: (1 + n.x) / 2.
    const Sky upper = imageSky(environment(256, 128, [](int, int j) { return j < 64 ? 1.0f : 0.0f; }));
    const Sky east = imageSky(environment(256, 128, [](int i, int) { return i >= 128 ? 1.0f : 0.0f; }));
    for (double fromZenith : {0.0, 30.0, 60.0, 90.0, 120.0, 170.0})
        for (double azimuth : {0.0, 45.0, 100.0, 200.0, 300.0}) {
            const glm::dvec3 n = direction(azimuth, fromZenith);
            INFO("normal at azimuth " << azimuth << ", " << fromZenith << " from the zenith");
            CHECK(upper.ambient(n).r == Approx((1.0 + n.z) / 2.0).margin(0.01));
            CHECK(east.ambient(n).g == Approx((1.0 + n.x) / 2.0).margin(0.01));
        }
    // Turning the east sky by 180 degrees makes it the west sky.
    const Sky west = imageSky(environment(256, 128, [](int i, int) { return i >= 128 ? 1.0f : 0.0f; }), 180.0);
    CHECK(west.ambient(glm::dvec3(-1.0, 0.0, 0.0)).b == Approx(1.0).margin(0.01));
    CHECK(west.ambient(glm::dvec3(1.0, 0.0, 0.0)).b == Approx(0.0).margin(0.01));
}

TEST_CASE("Image sky from an EXR: a white furnace, and a sphere lit from the east", "[sky][image][scene]") {
    TempDir dir("environment");
    const auto writeExr = [&](const std::string& name, const std::function<float(int, int)>& value) {
        RgbImage picture;
        picture.width = 128;
        picture.height = 64;
        picture.rgb.resize(128 * 64 * 3);
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 128; ++i)
                for (int c = 0; c < 3; ++c) picture.at(i, j, c) = value(i, j);
        const std::string path = dir.file(name);
        writeImage(path, picture);
        return path;
    };
    // A white diffuse sphere under a uniform sky of radiance 0.75 (exact in half float): every pixel, sphere or
    // sky, is 0.75.
    SceneDescription d;
    // No [[light]]: under an image sky that means no sun either, the image lights the scene alone.
    d.sky.kind = SkyKind::Image;
    d.sky.imagePath = writeExr("uniform.exr", [](int, int) { return 0.75f; });
    d.camera = lookingAt({0.0, -10.0, 0.0}, {0.0, 0.0, 0.0}, 15.0);
    d.render.width = 48;
    d.render.height = 48;
    MaterialDescription white;
    white.name = "white";
    white.colour = glm::vec3(1.0f);
    d.materials.push_back(white);
    d.objects.push_back(sphere({0.0, 0.0, 0.0}, 1.0, "white"));
    {
        const LoadedSceneAssets loaded = loadSceneAssets(d);
        REQUIRE(loaded.assets.environment);
        const Scene scene(d, loaded.assets);
        const Film film = renderScene(scene, makeSceneCamera(scene, d.camera, 1.0), settingsFor(d));
        for (int y = 0; y < 48; ++y)
            for (int x = 0; x < 48; ++x) {
                INFO("pixel " << x << ", " << y);
                CHECK(film.get(x, y).g == Approx(0.75).margin(0.005));
            }
    }
    // Bright in the eastern half only: the sphere seen from the south is lit (1 + n.x) / 2 at each point.
    d.sky.imagePath = writeExr("east.exr", [](int i, int) { return i >= 64 ? 1.0f : 0.0f; });
    const LoadedSceneAssets loaded = loadSceneAssets(d);
    const Scene scene(d, loaded.assets);
    const ViewCamera camera = makeSceneCamera(scene, d.camera, 1.0);
    const Film film = renderScene(scene, camera, settingsFor(d));
    int checked = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x) {
            const auto ray = camera.generate((x + 0.5) / 48.0, (y + 0.5) / 48.0);
            // Where the ray meets the unit sphere, if it does.
            const double b = glm::dot(ray->origin, ray->dir), c = glm::dot(ray->origin, ray->origin) - 1.0;
            if (b * b - c <= 0.0) continue;
            const glm::dvec3 n = ray->at(-b - std::sqrt(b * b - c));
            ++checked;
            CHECK(film.get(x, y).r == Approx((1.0 + n.x) / 2.0).margin(0.015));
        }
    CHECK(checked > 500);
}
