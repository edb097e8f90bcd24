// Energy in scene materials: a white furnace (an object inside a uniform white sky, no other light) returns at
// most the sky's radiance for every kind of material a scene file describes with the defaults; a fully white
// diffuse surface returns it exactly; weights a file gives that add up to more than 1, and a scene without
// objects, are warned about; and a colour given for a height field is the terrain's colour.
#include "support/scene_builders.h"
#include "support/scene_text.h"
#include "tracer/scene/scene_renderer.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <string>

using namespace terracast;
using namespace terracast::testing;

namespace {

// A scene of one sphere of `material` (TOML keys of a [[material]] named "m") in a white sky of radiance 1 that
// lights surfaces by its whole hemisphere, and a sun of zero intensity: every bit of light comes from the sky.
SceneDescription furnace(const std::string& material) {
    const SceneFolder folder;
    return parse("[[material]]\nname = \"m\"\n" + material +
                     "\n[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n"
                     "[[light]]\nintensity = 0\n"
                     "[sky]\nmodel = \"flat\"\ncolor = [1, 1, 1]\nambient = 1\nsamples = 0\n"
                     "[camera]\neye = [0, -4, 0.5]\nlook_at = [0, 0, 0]\nfov = 40\n"
                     "[render]\nwidth = 24\nheight = 24\nmax_depth = 12\nmin_weight = 0.0001\n",
                 folder);
}

// The largest channel of any pixel of the scene's picture.
float brightest(const SceneDescription& d) {
    const Scene scene(d, {});
    const ViewCamera camera = makeSceneCamera(scene, d.camera, 1.0);
    const Film film = renderScene(scene, camera, settingsFor(d), nullptr);
    return *std::max_element(film.rgb.begin(), film.rgb.end());
}

}  // namespace

TEST_CASE("White furnace: every material kind with the default weights returns at most the light it receives",
          "[scene][energy]") {
    for (const std::string material :
         {"", "color = [1, 1, 1]", "ior = 1.5", "ior = 1.333\nabsorption = 0.3", "ior_rgb = [1.5, 1.6, 1.7]",
          "ior = 1.5\nfresnel = \"exact\"", "mirror = 0.9", "mirror = [0.2, 0.9, 0.5]\ncolor = [1, 1, 1]",
          "mirror = 0.6\ngloss = 40", "ks = 0.3\nmirror = 0.4\ncolor = [1, 1, 1]", "color = [0.05, 0.1, 0.1]\nior = 1.33"}) {
        INFO("material: " << material);
        const SceneDescription d = furnace(material);
        CHECK(d.warnings.empty());
        CHECK(brightest(d) <= 1.0f + 1e-5f);
    }
}

TEST_CASE("White furnace: a white diffuse surface facing the sky returns the sky's radiance", "[scene][energy]") {
    // The check above must be able to reach 1: the top of a white sphere sends back all the sky's light.
    CHECK(brightest(furnace("color = [1, 1, 1]")) == Approx(1.0).margin(0.02));
    // And it would see a material that adds light: a white diffuse surface that also mirrors.
    const SceneDescription d = furnace("color = [1, 1, 1]\nkd = 1\nmirror = 0.5");
    CHECK(brightest(d) > 1.2f);
    REQUIRE(d.warnings.size() == 1);
    CHECK(d.warnings[0] == "scene.toml:1:1: material \"m\": kd x max(color) + ks + max(mirror) = 1.5, above 1: the "
                           "surface sends back more light than it receives (lower kd, color, ks or mirror)");
}

TEST_CASE("The diffuse weight not given is what the other terms leave", "[scene][energy]") {
    const SceneFolder folder;
    const SceneDescription d = parse("[[material]]\nname = \"a\"\n"
                                     "[[material]]\nname = \"b\"\nmirror = [0.1, 0.3, 0.2]\nks = 0.2\n"
                                     "[[material]]\nname = \"c\"\nior = 1.5\n"
                                     "[[material]]\nname = \"d\"\nior = 1.5\nkd = 0.5\ncolor = [0.2, 0.2, 0.2]\n"
                                     "[[material]]\nname = \"e\"\ncolor = [0.3, 0.3, 0.3]\nmirror = 0.6\n",
                                     folder);
    REQUIRE(d.materials.size() == 5);
    CHECK(d.materials[0].kd == 1.0f);
    CHECK(d.materials[1].kd == Approx(0.5 / 0.8));  // (1 - 0.2 - 0.3) / 0.8
    CHECK(d.materials[2].kd == 0.0f);
    CHECK(d.materials[3].kd == 0.5f);
    CHECK(d.materials[4].kd == 1.0f);  // 0.3 + 0.6 leaves room for all of the colour
    // The material's warning, and the scene's: it has no object.
    REQUIRE(d.warnings.size() == 2);
    CHECK(d.warnings[1] == "scene.toml: the scene has no [[object]]: the picture shows only the sky");
    CHECK_THAT(d.warnings[0], Catch::StartsWith("scene.toml:10:1: material \"d\": kd x max(color) + ks + max(mirror) "
                                                "+ 1 (dielectric) = 1.1, above 1"));
}

TEST_CASE("A colour given to a height field's material is the terrain's colour", "[scene][energy]") {
    // A flat grid seen from above under the white furnace sky: each pixel is the colour itself.
    const SceneFolder folder;
    SceneDescription d = parse("[[material]]\nname = \"ground\"\ncolor = [0.2, 0.4, 0.6]\n"
                               "[[material]]\nname = \"ramp\"\n"
                               "[[light]]\nintensity = 0\n"
                               "[sky]\nmodel = \"flat\"\ncolor = [1, 1, 1]\nambient = 1\nsamples = 0\n",
                               folder);
    CHECK(d.materials[0].terrain == TerrainColouring::Plain);
    CHECK(d.materials[1].terrain == TerrainColouring::Elevation);
    for (const char* material : {"ground", "ramp"}) {
        INFO(material);
        SceneDescription scene = d;
        ObjectDescription field;
        field.kind = ObjectKind::HeightField;
        field.material = material;
        scene.objects.push_back(field);
        // Heights 0 at the middle, rising to 10 m at the edges: elevation colours vary, a plain colour does not.
        const int n = 9;
        std::vector<float> heights(size_t(n) * n);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) heights[size_t(j) * n + size_t(i)] = float(std::abs(i - 4) + std::abs(j - 4)) * 1.25f;
        SceneAssets assets;
        assets.grids.push_back(std::make_shared<const HeightGrid>(n, n, 1.0, 1.0, heights));
        scene.camera.eye = glm::dvec3(4.0, 4.0, 100.0);
        scene.camera.lookAt = glm::dvec3(4.0, 4.0, 0.0);
        scene.camera.up = glm::dvec3(0.0, 1.0, 0.0);
        scene.camera.fovDeg = 2.0;
        const Scene s(scene, assets);
        const glm::vec3 v = tracePixel(s, makeSceneCamera(s, scene.camera, 1.0), SceneRenderSettings{}, 480, 270,
                                       nullptr);
        if (std::string(material) == "ground") {
            // The pit's normal tilts by under 60 degrees: the sky light on it is 0.5 + 0.5 n.z of the colour.
            CHECK(v.b / v.r == Approx(3.0).epsilon(1e-5));
            CHECK(v.g / v.r == Approx(2.0).epsilon(1e-5));
        } else {
            CHECK_FALSE(v.b / v.r == Approx(3.0).epsilon(1e-3));
        }
    }
}
