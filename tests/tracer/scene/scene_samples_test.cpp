// The sample scenes in data-samples (*.toml): each renders at a small size against its golden image, and each
// traces only the ray kinds its content calls for.
#include "loaders/scene_assets.h"
#include "loaders/scene_file.h"
#include "support/golden.h"
#include "tracer/scene/scene_pipeline.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>

using namespace terracast;

namespace {

struct Rendered {
    Film film;
    SceneRayStats stats;
    bool bvh = false;
};

Rendered renderSample(const std::string& name, int width, int height) {
    const std::string path = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name + ".toml";
    const SceneDescription d = loadSceneFile(path);
    const LoadedSceneAssets loaded = loadSceneAssets(d);
    const Scene scene(d, loaded.assets);
    // The file's own settings, at this size, with the sampling capped so that CI stays quick.
    SceneRenderSettings s = sceneRenderSettings(d.render);
    s.width = width;
    s.height = height;
    s.samples = std::min(d.render.samples, 16);
    s.threads = 2;
    const ViewCamera camera = makeSceneCamera(scene, d.camera, double(width) / double(height));
    Rendered r;
    r.film = renderScene(scene, camera, s, &r.stats);
    r.bvh = scene.usesBvh();
    return r;
}

void checkSceneGolden(const std::string& name, const Rendered& r) {
    testing::checkGolden(RgbImage{r.film.width, r.film.height, r.film.rgb},
                         std::string(TERRACAST_SOURCE_DIR) + "/tests/golden/scenes/" + name + ".png", 1.0, 0.01);
}

}  // namespace

TEST_CASE("Every sample scene parses, loads and renders", "[scene][samples]") {
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(std::string(TERRACAST_SOURCE_DIR) + "/data-samples")) {
        if (entry.path().extension() != ".toml") continue;
        ++scenes;
        INFO(entry.path().string());
        const Rendered r = renderSample(entry.path().stem().string(), 48, 27);
        CHECK(r.stats.primary >= 48 * 27 - 1);
        // Something other than black: every sample scene is lit.
        float brightest = 0.0f;
        for (float v : r.film.rgb) brightest = std::max(brightest, v);
        CHECK(brightest > 0.05f);
    }
    CHECK(scenes >= 6);
}

TEST_CASE("Sample scene: a lake reflects and refracts", "[scene][samples][golden]") {
    const Rendered r = renderSample("lake", 160, 90);
    CHECK(r.stats.reflection > 0);
    CHECK(r.stats.refraction > 0);
    checkSceneGolden("lake", r);
}

TEST_CASE("Sample scene: glass and mirror spheres on terrain", "[scene][samples][golden]") {
    const Rendered r = renderSample("spheres-on-terrain", 160, 90);
    CHECK(r.stats.reflection > 0);
    CHECK(r.stats.refraction > 0);
    checkSceneGolden("spheres-on-terrain", r);
}

TEST_CASE("Sample scene: boxes and polygons pay for no refraction", "[scene][samples][golden]") {
    const Rendered r = renderSample("boxes-and-polygons", 160, 120);
    CHECK(r.stats.refraction == 0);
    CHECK(r.stats.reflection > 0);  // the floor is slightly reflective
    CHECK(r.bvh);
    checkSceneGolden("boxes-and-polygons", r);
}

TEST_CASE("Sample scene: a summit panorama pays for no reflection, refraction or BVH", "[scene][samples][golden]") {
    const Rendered r = renderSample("summit-panorama", 180, 60);
    CHECK(r.stats.reflection == 0);
    CHECK(r.stats.refraction == 0);
    CHECK(r.stats.shadow > 0);
    CHECK_FALSE(r.bvh);
    checkSceneGolden("summit-panorama", r);
}

TEST_CASE("Sample scene: a low sun over the terrain and the sea", "[scene][samples][golden]") {
    const Rendered r = renderSample("low-sun", 160, 90);
    CHECK(r.stats.shadow > 0);
    CHECK(r.stats.reflection > 0);  // the sea
    CHECK(r.stats.refraction > 0);
    checkSceneGolden("low-sun", r);
}

TEST_CASE("Sample scene: depth of field, soft shadows, glossy reflection and motion blur", "[scene][samples][golden]") {
    const Rendered r = renderSample("distribution", 160, 90);
    CHECK(r.stats.primary == 160 * 90 * 16);
    CHECK(r.stats.refraction == 0);
    CHECK(r.stats.reflection > 0);
    checkSceneGolden("distribution", r);
}

TEST_CASE("Sample scene: absorption and dispersion", "[scene][samples][golden]") {
    const Rendered r = renderSample("absorption", 160, 90);
    CHECK(r.stats.refraction > 0);
    checkSceneGolden("absorption", r);
}
