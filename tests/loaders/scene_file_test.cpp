// Scene-file parser tests, valid scenes: every key's value lands in the struct it names, documented defaults
// fill what a scene leaves out, paths resolve against the scene's folder, and the format document's examples
// parse. Scenes are written inline, one string literal per line, so every expected LINE:COL can be read off
// the text. Files a scene names are created in a temporary folder.
#include "support/scene_text.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <regex>
#include <string>
#include <vector>

using namespace terracast;
using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

bool at(const SourceLocation& where, int line, int column) { return where.line == line && where.column == column; }

}  // namespace

TEST_CASE("Scene file: a full example parses to the structs it states", "[loaders]") {
    const SceneFolder folder;
    const SceneDescription s = parse(kFullScene, folder);
    CHECK(s.path == "scene.toml");

    const CameraDescription& c = s.camera;
    CHECK(c.kind == CameraKind::ThinLens);
    REQUIRE(c.eye);
    CHECK(*c.eye == glm::dvec3(100, -200, 1500.5));
    REQUIRE(c.lookAt);
    CHECK(*c.lookAt == glm::dvec3(2000, 3000, 900));
    CHECK(c.up == glm::dvec3(0, 0.5, 1));
    CHECK(c.fovDeg == 35.0);
    CHECK(c.apertureRadiusM == 0.05);
    CHECK(c.focusDistanceM == 2500.0);
    CHECK(c.shutterOpen == 0.0);
    CHECK(c.shutterClose == 0.02);
    CHECK(c.velocity == glm::dvec3(1, 2, 3));
    CHECK(at(c.where, 1, 1));

    REQUIRE(s.materials.size() == 4);
    const MaterialDescription& glass = s.materials[0];
    CHECK(glass.name == "glass");
    CHECK(glass.colour == glm::vec3(0.9f, 1.0f, 0.95f));
    CHECK(glass.kd == 0.1f);
    CHECK(glass.ks == 0.5f);
    CHECK(glass.exponent == 64.0f);
    CHECK(glass.mirror == glm::vec3(0.25f));
    CHECK(glass.gloss == 100.0f);
    CHECK(glass.dielectric);
    CHECK(glass.dispersive);
    CHECK(glass.ior == glm::vec3(1.51f, 1.52f, 1.53f));
    CHECK(glass.absorptionPerM == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(glass.fresnel == FresnelModel::Exact);
    CHECK(glass.terrain == TerrainColouring::Plain);  // a colour given is a height field's colour too
    CHECK(at(glass.where, 12, 1));
    CHECK(s.materials[1].name == "rock");
    CHECK(s.materials[1].terrain == TerrainColouring::Slope);
    CHECK_FALSE(s.materials[1].dielectric);
    const MaterialDescription& photo = s.materials[2];
    CHECK(photo.terrain == TerrainColouring::Drape);
    CHECK(photo.drapePath == folder.file("ortho.tif"));
    CHECK(at(photo.drapeWhere, 30, 1));
    CHECK(photo.mirror == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(photo.kd == Approx(0.875));  // (1 - 0.3) / 0.8: all of the default colour and the mirror would exceed 1
    // The glass's weights add up to more than 1 (0.1 + 0.5 + 0.25 + 1): a warning at its table.
    REQUIRE(s.warnings.size() == 1);
    CHECK_THAT(s.warnings[0], Catch::StartsWith("scene.toml:12:1: material \"glass\": kd x max(color) + ks"));
    const MaterialDescription& lake = s.materials[3];
    CHECK(lake.dielectric);
    CHECK_FALSE(lake.dispersive);
    CHECK(lake.ior == glm::vec3(1.33f));
    CHECK(lake.absorptionPerM == glm::vec3(0.5f));
    CHECK(lake.fresnel == FresnelModel::Schlick);

    REQUIRE(s.objects.size() == 7);
    const ObjectDescription& terrain = s.objects[0];
    CHECK(terrain.kind == ObjectKind::HeightField);
    CHECK(terrain.name == "valley");
    CHECK(terrain.material == "photo");
    CHECK(terrain.filePath == folder.file("dem.tif"));
    CHECK(terrain.offsetM == glm::dvec3(10, 20, -5));
    CHECK(terrain.exaggeration == 2.0);
    CHECK(terrain.method == SurfaceMethod::EmbreeGrid);
    CHECK(terrain.cellSizeM == 30.0);
    CHECK(terrain.heightScale == 0.1);
    CHECK(at(terrain.where, 38, 1));
    CHECK(at(terrain.fileWhere, 41, 1));
    CHECK(at(terrain.materialWhere, 42, 1));
    const ObjectDescription& sphere = s.objects[1];
    CHECK(sphere.kind == ObjectKind::Sphere);
    CHECK(sphere.name == "sphere 2");  // "<type> <position in the file>" by default
    CHECK(sphere.material == "glass");
    CHECK(sphere.centre == glm::dvec3(1, 2, 3));
    CHECK(sphere.radiusM == 4.5);
    CHECK(sphere.velocity == glm::dvec3(0, 0, -1));
    CHECK(s.objects[2].kind == ObjectKind::Plane);
    CHECK(s.objects[2].point == glm::dvec3(0, 0, 100));
    CHECK(s.objects[2].normal == glm::dvec3(0, 1, 1));
    CHECK(s.objects[3].kind == ObjectKind::Triangle);
    CHECK(s.objects[3].vertices ==
          std::vector<glm::dvec3>{glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0)});
    CHECK(s.objects[4].kind == ObjectKind::Polygon);
    REQUIRE(s.objects[4].vertices.size() == 5);
    CHECK(s.objects[4].vertices[3] == glm::dvec3(2, 1, 1));
    CHECK(s.objects[5].kind == ObjectKind::Box);
    CHECK(s.objects[5].boxMin == glm::dvec3(-1, -2, -3));
    CHECK(s.objects[5].boxMax == glm::dvec3(1, 2, 3));
    CHECK(s.objects[6].kind == ObjectKind::Water);
    CHECK(s.objects[6].levelM == 812.5);
    CHECK(s.objects[6].material == "lake");

    REQUIRE(s.lights.size() == 4);
    const LightDescription& sun = s.lights[0];
    CHECK(sun.kind == LightKind::Sun);
    CHECK(sun.colour == glm::vec3(1.0f, 0.9f, 0.8f));
    CHECK(sun.intensity == 2.0f);
    CHECK(formatUtc(*sun.time) == "2026-06-21T19:30:00Z");  // 21:30 at +02:00 is 19:30 UTC
    CHECK(sun.angularRadiusDeg == 0.5);
    CHECK(s.lights[1].kind == LightKind::Point);
    CHECK(s.lights[1].position == glm::dvec3(5, 6, 7));
    CHECK(s.lights[1].intensity == 100.0f);
    CHECK(s.lights[2].kind == LightKind::Sphere);
    CHECK(s.lights[2].position == glm::dvec3(-5, -6, 7));
    CHECK(s.lights[2].radiusM == 0.5);
    CHECK(s.lights[2].colour == glm::vec3(0.5f, 0.5f, 1.0f));
    CHECK(s.lights[3].kind == LightKind::Sun);  // the default type
    CHECK(s.lights[3].azimuthDeg == 270.0);
    CHECK(s.lights[3].elevationDeg == -5.0);
    CHECK_FALSE(s.lights[3].time);
    CHECK(at(s.lights[3].where, 97, 1));

    CHECK(s.sky.kind == SkyKind::Physical);
    CHECK(s.sky.haze == 2.5);
    CHECK_FALSE(s.sky.aerialPerspective);
    CHECK(s.sky.ambient == 0.3f);
    CHECK(at(s.sky.where, 101, 1));

    const RenderDescription& r = s.render;
    CHECK(r.width == 320);
    CHECK(r.height == 200);
    CHECK(r.samples == 16);
    CHECK(r.sampler == SamplePattern::Poisson);
    CHECK(r.filter == FilterKind::Gaussian);
    CHECK(r.maxDepth == 12);
    CHECK(r.minWeight == 0.001);
    CHECK(r.seed == 42u);
    CHECK(r.threads == 3);
    CHECK(r.output == (fs::path(folder.path()) / "out/picture.png").string());
    CHECK(r.exposure == 1.5f);
}

TEST_CASE("Scene file: the three-line scene gets the documented defaults", "[loaders]") {
    const SceneFolder folder;
    const SceneDescription s = parse("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"", folder);
    REQUIRE(s.objects.size() == 1);
    const ObjectDescription& o = s.objects[0];
    const ObjectDescription defaults;
    CHECK(o.kind == ObjectKind::HeightField);
    CHECK(o.name == "heightfield 1");
    CHECK(o.material.empty());
    CHECK(o.filePath == folder.file("dem.tif"));
    CHECK(o.offsetM == defaults.offsetM);
    CHECK(o.exaggeration == defaults.exaggeration);
    CHECK(o.method == defaults.method);
    CHECK(o.cellSizeM == defaults.cellSizeM);
    CHECK(o.heightScale == defaults.heightScale);
    CHECK(at(o.where, 1, 1));
    CHECK(at(o.fileWhere, 3, 1));
    CHECK(s.materials.empty());
    CHECK(s.lights.empty());  // the renderer adds its default sun

    const CameraDescription camera;
    CHECK(s.camera.kind == camera.kind);
    CHECK_FALSE(s.camera.eye);
    CHECK_FALSE(s.camera.lookAt);
    CHECK(s.camera.up == camera.up);
    CHECK(s.camera.fovDeg == camera.fovDeg);
    CHECK(s.camera.orthoHeightM == camera.orthoHeightM);
    CHECK(s.camera.apertureRadiusM == camera.apertureRadiusM);
    CHECK(s.camera.shutterOpen == camera.shutterOpen);
    CHECK(s.camera.shutterClose == camera.shutterClose);
    const SkyDescription sky;
    CHECK(s.sky.kind == sky.kind);
    CHECK(s.sky.colour == sky.colour);
    CHECK(s.sky.haze == sky.haze);
    CHECK(s.sky.aerialPerspective == sky.aerialPerspective);
    CHECK(s.sky.ambient == sky.ambient);
    const RenderDescription render;
    CHECK(s.render.width == render.width);
    CHECK(s.render.height == render.height);
    CHECK(s.render.samples == render.samples);
    CHECK(s.render.sampler == render.sampler);
    CHECK(s.render.filter == render.filter);
    CHECK(s.render.maxDepth == render.maxDepth);
    CHECK(s.render.minWeight == render.minWeight);
    CHECK(s.render.seed == render.seed);
    CHECK(s.render.threads == render.threads);
    CHECK(s.render.output.empty());
    CHECK(s.render.exposure == render.exposure);
}

TEST_CASE("Scene file: per-type defaults and the other camera, sky and light types", "[loaders]") {
    const SceneFolder folder;
    const SceneDescription fisheye = parse("[camera]\ntype = \"fisheye\"\n", folder);
    CHECK(fisheye.camera.kind == CameraKind::Fisheye);
    CHECK(fisheye.camera.fovDeg == 180.0);  // a fisheye's default field, not the pinhole's
    CHECK(parse("[camera]\ntype = \"fisheye\"\nfov = 360\n", folder).camera.fovDeg == 360.0);
    const SceneDescription ortho = parse("[camera]\ntype = \"orthographic\"\nheight = 5000\n", folder);
    CHECK(ortho.camera.kind == CameraKind::Orthographic);
    CHECK(ortho.camera.orthoHeightM == 5000.0);
    // A straight-down view with the default up is left to the camera to orient.
    const SceneDescription down = parse("[camera]\neye = [0, 0, 100]\nlook_at = [0, 0, 0]\n", folder);
    CHECK(down.camera.up == glm::dvec3(0, 0, 1));
    CHECK(parse("[camera]\ntype = \"panorama\"\n", folder).camera.kind == CameraKind::Panorama);

    const SceneDescription flat = parse("[sky]\nmodel = \"flat\"\ncolor = [0.1, 0.2, 0.3]\nambient = 0\n", folder);
    CHECK(flat.sky.kind == SkyKind::Flat);
    CHECK(flat.sky.colour == glm::vec3(0.1f, 0.2f, 0.3f));
    CHECK(flat.sky.ambient == 0.0f);
    CHECK(parse("[sky]\nmodel = \"gradient\"\n", folder).sky.kind == SkyKind::Gradient);
    CHECK(parse("[sky]\nmodel = \"none\"\n", folder).sky.kind == SkyKind::None);
    // Sky-visibility rays; the ambient scale defaults to the model's own when unset.
    const SceneDescription rays = parse("[sky]\nmodel = \"gradient\"\nsamples = 12\n", folder);
    CHECK(rays.sky.samples == 12);
    CHECK_FALSE(rays.sky.ambient);
    CHECK(rays.sky.ambientScale() == 0.15f);
    CHECK(parse("[sky]\n", folder).sky.ambientScale() == 1.0f);

    // A TOML offset date-time is accepted as well as a string, and normalised to UTC across midnight.
    const SceneDescription native = parse("[[light]]\ntime = 2026-01-01T00:30:00-01:00\n", folder);
    CHECK(formatUtc(*native.lights.at(0).time) == "2026-01-01T01:30:00Z");
    const SceneDescription back = parse("[[light]]\ntime = \"2024-03-01T00:15Z\"\n", folder);
    CHECK(formatUtc(*back.lights.at(0).time) == "2024-03-01T00:15:00Z");
    const SceneDescription leap = parse("[[light]]\ntime = \"2024-03-01T01:00:00.75+0200\"\n", folder);
    CHECK(formatUtc(*leap.lights.at(0).time) == "2024-02-29T23:00:00Z");  // 2024 is a leap year

    // Every method the tracer knows is accepted.
    for (const char* method : {"bilinear", "bilinear-double", "triangles", "nearest", "reference", "embree"}) {
        const std::string text =
            std::string("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\nmethod = \"") + method + "\"\n";
        CHECK(parse(text, folder).objects.at(0).method == parseSurfaceMethod(method));
    }
}

TEST_CASE("Scene file: paths resolve against the scene file's folder", "[loaders]") {
    const TempDir root("scene-paths");
    fs::create_directories(root.path() / "scenes");
    fs::create_directories(root.path() / "dems");
    std::ofstream(root.file("dems/dem.tif")) << "x";
    std::ofstream(root.file("ortho.tif")) << "x";
    const std::string absoluteDrape = root.file("ortho.tif");
    const std::string scenePath = root.file("scenes/valley.toml");
    std::ofstream(scenePath) << "[[material]]\nname = \"photo\"\ndrape = \"" << absoluteDrape << "\"\n"
                             << "[[object]]\ntype = \"heightfield\"\nfile = \"../dems/dem.tif\"\n"
                             << "[render]\noutput = \"pictures/valley.png\"\n";

    // With any path allowed (terracast scene --allow-paths).
    const SceneDescription s = loadSceneFile(scenePath, true);
    CHECK(s.path == scenePath);
    CHECK(s.objects.at(0).filePath == (root.path() / "dems" / "dem.tif").string());
    CHECK(s.materials.at(0).drapePath == absoluteDrape);  // absolute paths stay as they are
    CHECK(s.render.output == (root.path() / "scenes" / "pictures" / "valley.png").string());

    // Without a base folder, relative paths are left relative to the working directory.
    const SceneDescription here = parseSceneText("[render]\noutput = \"a/b.png\"\n", "scene.toml", "", true);
    CHECK(here.render.output == "a/b.png");

    // The same scene seen from its parent folder does not find the DEM, and says where it looked.
    const std::string moved = root.file("valley.toml");
    fs::copy_file(scenePath, moved);
    CHECK_THROWS_WITH(loadSceneFile(moved, true),
                      moved + ":6:1: file: " + (root.path().parent_path() / "dems" / "dem.tif").string() +
                          ": no such file");
}

TEST_CASE("Scene file: by default its paths stay in its folder, and name no network", "[loaders]") {
    const TempDir root("scene-confined");
    fs::create_directories(root.path() / "scene" / "dems");
    std::ofstream(root.file("outside.tif")) << "x";
    std::ofstream(root.file("scene/dems/dem.tif")) << "x";
    fs::create_symlink("../outside.tif", root.path() / "scene" / "link.tif");
    fs::create_symlink("dems/dem.tif", root.path() / "scene" / "inner-link.tif");
    const std::string folder = root.file("scene");
    const auto load = [&](const std::string& text) {
        std::ofstream(root.file("scene/s.toml")) << text;
        return loadSceneFile(root.file("scene/s.toml"));
    };
    const auto object = [](const std::string& file) { return "[[object]]\ntype = \"heightfield\"\nfile = \"" + file + "\"\n"; };
    // Inside the folder, directly, through a subfolder's "..", or through a link that stays inside.
    CHECK(load(object("dems/dem.tif")).objects.at(0).filePath == folder + "/dems/dem.tif");
    CHECK_NOTHROW(load(object("dems/../dems/dem.tif")));
    CHECK_NOTHROW(load(object("inner-link.tif")));
    CHECK(load("[render]\noutput = \"pictures/out.png\"\n").render.output == folder + "/pictures/out.png");
    const std::string rule = "a scene file may name only files in its own folder unless --allow-paths is given";
    const std::string s = root.file("scene/s.toml");
    CHECK_THROWS_WITH(load(object("../outside.tif")),
                      s + ":3:8: file: \"../outside.tif\" leads out of the scene file's folder (to " +
                          root.file("outside.tif") + "); " + rule);
    CHECK_THROWS_WITH(load(object("link.tif")), Catch::Contains("\"link.tif\" leads out of the scene file's folder"));
    CHECK_THROWS_WITH(load(object(root.file("outside.tif"))),
                      s + ":3:8: file: \"" + root.file("outside.tif") + "\" is an absolute path; " + rule);
    CHECK_THROWS_WITH(load(object("/vsicurl/https://example.com/dem.tif")),
                      Catch::Contains("is a GDAL virtual or network path; " + rule));
    CHECK_THROWS_WITH(load(object("https://example.com/dem.tif")), Catch::Contains("GDAL virtual or network path"));
    CHECK_THROWS_WITH(load("[[material]]\nname = \"m\"\ndrape = \"../outside.tif\"\n"),
                      Catch::Contains("drape: \"../outside.tif\" leads out"));
    CHECK_THROWS_WITH(load("[render]\noutput = \"/tmp/replaced.png\"\n"),
                      Catch::Contains("output: \"/tmp/replaced.png\" is an absolute path"));
    CHECK_THROWS_WITH(load("[render]\noutput = \"../replaced.png\"\n"), Catch::Contains("output: \"../replaced.png\" leads out"));

    // Named by a relative path from its own folder, with an output that does not exist yet.
    const fs::path was = fs::current_path();
    fs::current_path(folder);
    std::ofstream("here.toml") << "[render]\noutput = \"new/out.png\"\n" << object("dems/dem.tif");
    std::string output;
    CHECK_NOTHROW(output = loadSceneFile("here.toml").render.output);
    CHECK_THROWS_WITH(parseSceneText("[render]\noutput = \"../out.png\"\n", "here.toml", ""), Catch::Contains("leads out"));
    fs::current_path(was);
    CHECK(output == "new/out.png");
}

TEST_CASE("Scene file: the examples of docs/scene-format.md together form a valid scene", "[loaders]") {
    std::ifstream page(TERRACAST_SOURCE_DIR "/docs/scene-format.md");
    REQUIRE(page);
    std::string line;
    std::string scene;
    int blocks = 0;
    bool inBlock = false;
    while (std::getline(page, line)) {
        if (line == "```toml") {
            inBlock = true;
            ++blocks;
        } else if (inBlock && line == "```") {
            inBlock = false;
        } else if (inBlock) {
            scene += line + "\n";
        }
    }
    CHECK(blocks == 7);  // the smallest scene and one example for each of the six sections
    const TempDir dir("scene-docs");
    for (const char* name : {"dem.tif", "white-mountains.hgt"}) std::ofstream(dir.file(name)) << "x";
    const SceneDescription s = parseSceneText(scene, "scene-format.md", dir.path().string());
    CHECK(s.objects.size() == 5);
    CHECK(s.materials.size() == 2);
    CHECK(s.lights.size() == 2);
    CHECK(s.camera.kind == CameraKind::ThinLens);
    CHECK(s.render.samples == 16);
}

// Byte flips, truncations and swapped lines of a valid scene: whatever the damage, parsing either succeeds or
// throws an InputError of one line that starts with the file name and a line and column.
