// The debug ray tree adds up: in the sample scenes (terrain, glass, mirrors, water, haze), every ray that meets
// an object returns the light leaving its hit (the sky light added without rays plus its children's shares)
// times what crosses the medium, plus the haze; and the camera ray's share is the pixel's value.
#include "loaders/scene_assets.h"
#include "loaders/scene_file.h"
#include "tracer/scene/scene_pipeline.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace terracast;

namespace {

void checkClose(const glm::vec3& a, const glm::vec3& b) {
    for (int c = 0; c < 3; ++c) CHECK(a[c] == Approx(b[c]).epsilon(2e-5).margin(1e-7));
}

}  // namespace

TEST_CASE("The debug ray tree's shares add up to each ray's radiance and to the pixel", "[scene][tree]") {
    for (const std::string name : {"spheres-on-terrain", "lake", "absorption", "boxes-and-polygons", "low-sun"}) {
        const std::string path = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/" + name + ".toml";
        for (const int skySamples : {4, 0}) {
            SceneDescription d = loadSceneFile(path);
            d.sky.samples = skySamples;
            const LoadedSceneAssets loaded = loadSceneAssets(d);
            const Scene scene(d, loaded.assets);
            SceneRenderSettings s = sceneRenderSettings(d.render);
            s.width = 96;
            s.height = 54;
            s.samples = 1;
            const ViewCamera camera = makeSceneCamera(scene, d.camera, double(s.width) / double(s.height));
            int reflected = 0, hazed = 0, checked = 0;
            for (int y = 0; y < s.height; y += 10)
                for (int x = 0; x < s.width; x += 10) {
                    INFO(name << " with " << skySamples << " sky rays, pixel " << x << "," << y);
                    std::vector<RayRecord> tree;
                    const glm::vec3 pixel = tracePixel(scene, camera, s, x, y, &tree);
                    REQUIRE(!tree.empty());
                    checkClose(tree[0].share, pixel);
                    for (size_t k = 0; k < tree.size(); ++k) {
                        const RayRecord& r = tree[k];
                        if (r.kind == RayKind::Shadow || r.kind == RayKind::SkyVisibility) continue;
                        checkClose(r.contribution, r.weight * (r.atHit * r.passed + r.inscattered));
                        if (r.hit == "sky") continue;
                        glm::vec3 sum = r.skyLight;
                        for (size_t c = k + 1; c < tree.size() && tree[c].depth > r.depth; ++c)
                            if (tree[c].depth == r.depth + 1) sum += tree[c].share;
                        checkClose(sum, r.atHit);
                        ++checked;
                        reflected += r.kind == RayKind::Reflection;
                        hazed += r.inscattered != glm::vec3(0.0f);
                    }
                }
            INFO(name << ": " << checked << " rays checked, " << reflected << " reflections, " << hazed << " hazed");
            CHECK(checked > 20);
        }
    }
}
