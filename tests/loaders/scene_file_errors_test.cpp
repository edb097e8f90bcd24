// Scene-file parser tests, invalid scenes: every error is one InputError at the LINE:COL of the offending key
// or value, saying what was expected and what was found, with a near-miss suggestion for a misspelt key or
// name; random mutations of a valid scene raise nothing else.
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

TEST_CASE("Scene file: a missing, folder or empty scene path is named in the error", "[loaders]") {
    const TempDir dir("scene-load");
    const std::string missing = dir.file("nothing.toml");
    CHECK_THROWS_WITH(loadSceneFile(missing), missing + ": no such file");
    CHECK_THROWS_WITH(loadSceneFile(dir.path().string()), dir.path().string() + ": is a directory");
    // An empty file is a valid, empty scene.
    const std::string empty = dir.file("empty.toml");
    std::ofstream(empty).close();
    CHECK(loadSceneFile(empty).objects.empty());
}

TEST_CASE("Scene file: TOML syntax errors carry the parser's line and column", "[loaders]") {
    CHECK(errorOf("[camera]\nfov = 30\n[render\n") ==
          "scene.toml:3:8: invalid TOML: Error while parsing table header: expected ']', saw '\\n'");
    CHECK(errorOf("[render]\nwidth = 1\nwidth = 2\n") ==
          "scene.toml:3:9: invalid TOML: Error while parsing key-value pair: cannot redefine existing integer "
          "'width'");
}

TEST_CASE("Scene file: an unknown top-level table or key is refused with a suggestion", "[loaders]") {
    CHECK(errorOf("[camra]\nfov = 30\n") == "scene.toml:1:2: unknown table [camra] (did you mean [camera]?)");
    CHECK(errorOf("[render]\nwidth = 10\n\n[[objects]]\ntype = \"sphere\"\n") ==
          "scene.toml:4:3: unknown table [[objects]] (did you mean [[object]]?)");
    CHECK(errorOf("[lens]\n") == "scene.toml:1:2: unknown table [lens]");
    CHECK(errorOf("width = 10\n") ==
          "scene.toml:1:1: unknown top-level key 'width'; a scene holds only the tables [camera], [[material]], "
          "[[object]], [[light]], [sky], [render]");
    // A section in the wrong form.
    CHECK(errorOf("[object]\ntype = \"sphere\"\n") ==
          "scene.toml:1:2: object: expected [[object]] tables (an array of tables), found a table");
    CHECK(errorOf("[[camera]]\nfov = 30\n") == "scene.toml:1:3: camera: expected one table [camera], found an array of tables");
    CHECK(errorOf("object = [1]\n") == "scene.toml:1:11: object[0]: expected a table, found an integer");
}

TEST_CASE("Scene file: an unknown key in any table is refused with a near-miss suggestion", "[loaders]") {
    CHECK(errorOf("[[object]]\n"
                  "type = \"sphere\"\n"
                  "center = [0, 0, 0]\n"
                  "radus = 2\n") == "scene.toml:4:1: unknown key 'radus' in [[object]] (did you mean 'radius'?)");
    CHECK(errorOf("[[material]]\nname = \"red\"\ncolour = [1, 0, 0]\n") ==
          "scene.toml:3:1: unknown key 'colour' in [[material]] (did you mean 'color'?)");
    CHECK(errorOf("[render]\nwidht = 10\n") == "scene.toml:2:1: unknown key 'widht' in [render] (did you mean 'width'?)");
    CHECK(errorOf("[camera]\nlookat = [1, 2, 3]\n") ==
          "scene.toml:2:1: unknown key 'lookat' in [camera] (did you mean 'look_at'?)");
    CHECK(errorOf("[sky]\n  Haze = 2\n") == "scene.toml:2:3: unknown key 'Haze' in [sky] (did you mean 'haze'?)");
    CHECK(errorOf("[sky]\nsamples = -1\n") == "scene.toml:2:11: samples: expected an integer in 0..1024, found -1");
    CHECK(errorOf("[sky]\nmodel = \"none\"\nsamples = 4\n").rfind("scene.toml:3:1: key 'samples' does not apply", 0) == 0);
    CHECK(errorOf("[[light]]\nbrightness = 2\n") == "scene.toml:2:1: unknown key 'brightness' in [[light]]");
    // The first unknown key in the file is the one reported, whatever the alphabet says.
    CHECK(errorOf("[render]\nzz = 1\naa = 2\n") == "scene.toml:2:1: unknown key 'zz' in [render]");
    // A misspelt `type` is reported as such, not as a missing type.
    CHECK(errorOf("[[object]]\ntpye = \"box\"\n") ==
          "scene.toml:2:1: unknown key 'tpye' in [[object]] (did you mean 'type'?)");
    // Control characters in a quoted key stay on one line.
    CHECK(errorOf("[render]\n\"a\\nb\" = 1\n") == "scene.toml:2:1: unknown key 'a\\nb' in [render]");
}

TEST_CASE("Scene file: a key of another type names the types that take it", "[loaders]") {
    CHECK(errorOf("[[object]]\n"
                  "type = \"box\"\n"
                  "radius = 1\n") ==
          "scene.toml:3:1: key 'radius' does not apply to an object of type \"box\" (only to \"sphere\")");
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\nvertices = []\n") ==
          "scene.toml:3:1: key 'vertices' does not apply to an object of type \"sphere\" (only to \"triangle\", "
          "\"polygon\")");
    CHECK(errorOf("[camera]\naperture = 0.1\n") ==
          "scene.toml:2:1: key 'aperture' does not apply to a camera of type \"pinhole\" (only to \"thin-lens\")");
    CHECK(errorOf("[[light]]\ntype = \"point\"\nelevation = 3\n") ==
          "scene.toml:3:1: key 'elevation' does not apply to a light of type \"point\" (only to \"sun\")");
    CHECK(errorOf("[sky]\nmodel = \"flat\"\nhaze = 1\n") ==
          "scene.toml:3:1: key 'haze' does not apply to a sky of model \"flat\" (only to \"physical\")");
}

TEST_CASE("Scene file: a value of the wrong type says what was expected and found", "[loaders]") {
    CHECK(errorOf("[[object]]\n"
                  "type = \"sphere\"\n"
                  "center = [0, 0, 0]\n"
                  "radius = \"big\"\n") == "scene.toml:4:10: radius: expected a number in (0, 1e+09], found a string");
    CHECK(errorOf("[render]\nwidth = 960.5\n") ==
          "scene.toml:2:9: width: expected an integer in 1..16384, found a floating-point number");
    CHECK(errorOf("[sky]\naerial_perspective = \"yes\"\n") ==
          "scene.toml:2:22: aerial_perspective: expected true or false, found a string");
    CHECK(errorOf("[camera]\ntype = 3\n") == "scene.toml:2:8: type: expected a string, found an integer");
    CHECK(errorOf("[camera]\neye = [0, \"1\", 2]\n") == "scene.toml:2:11: eye[1]: expected a number in [-1e+09, 1e+09], found a string");
    CHECK(errorOf("[[material]]\nname = \"m\"\nior = [1.5, 1.5, 1.5]\n") ==
          "scene.toml:3:7: ior: expected a number > 0, found an array (ior_rgb takes one index per channel)");
    CHECK(errorOf("[[material]]\nname = \"m\"\nmirror = true\n") ==
          "scene.toml:3:10: mirror: expected a number or an array of 3 numbers [r, g, b], found a boolean");
    CHECK(errorOf("[camera]\ntype = \"pinhol\"\n") ==
          "scene.toml:2:8: type: expected one of \"pinhole\", \"orthographic\", \"thin-lens\", \"panorama\", "
          "\"fisheye\", found \"pinhol\" (did you mean \"pinhole\"?)");
    CHECK(errorOf("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\nmethod = \"bilinar\"\n") ==
          "scene.toml:4:10: method: expected one of \"bilinear\", \"bilinear-double\", \"triangles\", \"nearest\", "
          "\"reference\", \"embree\", \"embree-grid\", found \"bilinar\" (did you mean \"bilinear\"?)");
    CHECK(errorOf("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\nnormals = \"smoth\"\n") ==
          "scene.toml:4:11: normals: expected one of \"smooth\", \"facet\", found \"smoth\" (did you mean "
          "\"smooth\"?)");
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nnormals = \"facet\"\n").find(
              "normals") != std::string::npos);
    const SceneFolder folder;
    const SceneDescription s = parse("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\nnormals = \"facet\"\n"
                                     "[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\n",
                                     folder);
    CHECK_FALSE(s.objects[0].smoothNormals);
    CHECK(s.objects[1].smoothNormals);
}

TEST_CASE("Scene file: integers are accepted where numbers are expected", "[loaders]") {
    const SceneFolder folder;
    const SceneDescription s = parse("[[object]]\ntype = \"sphere\"\ncenter = [1, -2, 3]\nradius = 2\n"
                                     "[[material]]\nname = \"m\"\ncolor = [1, 0, 1]\nior = 2\n"
                                     "[[light]]\nelevation = 90\n",
                                     folder);
    CHECK(s.objects.at(0).radiusM == 2.0);
    CHECK(s.objects.at(0).centre == glm::dvec3(1, -2, 3));
    CHECK(s.materials.at(0).colour == glm::vec3(1, 0, 1));
    CHECK(s.materials.at(0).ior == glm::vec3(2.0f));
    CHECK(s.lights.at(0).elevationDeg == 90.0);
}

TEST_CASE("Scene file: a negative or zero radius is refused", "[loaders]") {
    CHECK(errorOf("[[object]]\n"
                  "type = \"sphere\"\n"
                  "center = [0, 0, 0]\n"
                  "radius = -2\n") == "scene.toml:4:10: radius: expected a number in (0, 1e+09], found -2");
    CHECK(errorOf("[[light]]\ntype = \"sphere\"\nposition = [0, 0, 9]\nradius = 0\n") ==
          "scene.toml:4:10: radius: expected a number in (0, 1e+09], found 0");
}

TEST_CASE("Scene file: coordinates and lengths beyond a million kilometres are refused", "[loaders]") {
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\ncenter = [1e300, 0, 0]\nradius = 1\n") ==
          "scene.toml:3:11: center[0]: expected a number in [-1e+09, 1e+09], found 1e+300");
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 2e9\n") ==
          "scene.toml:4:10: radius: expected a number in (0, 1e+09], found 2000000000");
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, -1e10, 0]]\n") ==
          "scene.toml:3:39: vertices[2][1]: expected a number in [-1e+09, 1e+09], found -10000000000");
    CHECK(errorOf("[camera]\neye = [0, 0, 1e9]\nlook_at = [0, 1e9, 0]\n") == "(no error)");
}

TEST_CASE("Scene file: an index of refraction at or below zero is refused", "[loaders]") {
    CHECK(errorOf("[[material]]\nname = \"glass\"\nior = 0\n") == "scene.toml:3:7: ior: expected a number > 0, found 0");
    CHECK(errorOf("[[material]]\nname = \"glass\"\nior_rgb = [1.5, -1.5, 1.5]\n") ==
          "scene.toml:3:17: ior_rgb[1]: expected a number > 0, found -1.5");
    CHECK(errorOf("[[material]]\nname = \"glass\"\nior = 1.5\nior_rgb = [1.5, 1.6, 1.7]\n") ==
          "scene.toml:4:1: ior_rgb: give either ior or ior_rgb, not both");
}

TEST_CASE("Scene file: zero-length directions are refused", "[loaders]") {
    CHECK(errorOf("[[object]]\ntype = \"plane\"\nnormal = [0, 0, 0.0]\n") ==
          "scene.toml:3:10: normal: expected a non-zero direction, found [0, 0, 0]");
    CHECK(errorOf("[camera]\nup = [0, 0, 0]\n") == "scene.toml:2:6: up: expected a non-zero direction, found [0, 0, 0]");
    CHECK(errorOf("[camera]\neye = [1, 2, 3]\nlook_at = [1, 2, 3]\n") ==
          "scene.toml:3:11: look_at: expected a point other than eye, found the same point (the view direction has "
          "zero length)");
    CHECK(errorOf("[camera]\neye = [0, 0, 10]\nlook_at = [0, 0, 0]\nup = [0, 0, 2]\n") ==
          "scene.toml:4:6: up: expected a direction not parallel to the view from eye to look_at, found [0, 0, 2]");
}

TEST_CASE("Scene file: a non-planar polygon is refused with the largest distance found", "[loaders]") {
    // A saddle: corners of a 4 m square alternately 0.25 m below and above z = 0. Newell's normal is +z by
    // symmetry and the plane passes through the centroid at z = 0, so every corner is 0.25 m away; the
    // tolerance is a millionth of the 4 m extent.
    CHECK(errorOf("[[object]]\n"
                  "type = \"polygon\"\n"
                  "vertices = [[0, 0, -0.25], [4, 0, 0.25], [4, 4, -0.25], [0, 4, 0.25]]\n") ==
          "scene.toml:3:12: vertices: expected a planar polygon, found vertices[0] 0.25 m from the polygon's plane "
          "(tolerance 4e-06 m)");
    // Within the tolerance, and on a tilted plane far from the origin, a non-convex polygon is fine.
    const SceneFolder folder;
    const SceneDescription s = parse("[[object]]\n"
                                     "type = \"polygon\"\n"
                                     "vertices = [[1000, 0, 1000], [1004, 0, 1004], [1004, 4, 1004.000001],\n"
                                     "            [1002, 1, 1002], [1000, 4, 1000]]\n",
                                     folder);
    CHECK(s.objects.at(0).vertices.size() == 5);
    CHECK(errorOf("[[object]]\ntype = \"polygon\"\nvertices = [[0, 0, 0], [1, 0, 0]]\n") ==
          "scene.toml:3:12: vertices: expected at least 3 points, found 2");
}

TEST_CASE("Scene file: a degenerate triangle or polygon is refused", "[loaders]") {
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 1, 1], [3, 3, 3]]\n") ==
          "scene.toml:3:12: vertices: expected a triangle with an area, found a degenerate one (zero area: its "
          "vertices coincide or lie on one line)");
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\nvertices = [[5, 5, 5], [5, 5, 5], [5, 5, 5]]\n") ==
          "scene.toml:3:12: vertices: expected a triangle with an area, found a degenerate one (zero area: its "
          "vertices coincide or lie on one line)");
    CHECK(errorOf("[[object]]\ntype = \"polygon\"\nvertices = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]\n") ==
          "scene.toml:3:12: vertices: expected a polygon with an area, found a degenerate one (zero area: its "
          "vertices coincide or lie on one line)");
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]\n") ==
          "scene.toml:3:12: vertices: expected exactly 3 points, found 4");
}

TEST_CASE("Scene file: other out-of-range values are refused with the range and the value", "[loaders]") {
    CHECK(errorOf("[camera]\nfov = 180\n") == "scene.toml:2:7: fov: expected a number in (0, 180), found 180");
    CHECK(errorOf("[camera]\ntype = \"fisheye\"\nfov = 361\n") ==
          "scene.toml:3:7: fov: expected a number in (0, 360], found 361");
    CHECK(errorOf("[camera]\ntype = \"thin-lens\"\naperture = -0.1\n") ==
          "scene.toml:3:12: aperture: expected a number in [0, 1e+09], found -0.1");
    CHECK(errorOf("[camera]\nshutter = [0.5, 0.25]\n") ==
          "scene.toml:2:11: shutter: expected [open, close] in increasing order, found [0.5, 0.25]");
    CHECK(errorOf("[[material]]\nname = \"m\"\nmirror = [0, 1.5, 0]\n") ==
          "scene.toml:3:14: mirror[1]: expected a number in [0, 1], found 1.5");
    CHECK(errorOf("[[material]]\nname = \"m\"\nexponent = 0\n") ==
          "scene.toml:3:12: exponent: expected a number > 0, found 0");
    CHECK(errorOf("[[material]]\nname = \"m\"\ncolor = [1, 1, 1e39]\n") ==
          "scene.toml:3:16: color[2]: expected a number of magnitude at most 3.4e+38, found 1e+39");
    CHECK(errorOf("[[object]]\ntype = \"box\"\nmin = [0, 0, 5]\nmax = [1, 1, 5]\n") ==
          "scene.toml:4:7: max: expected a corner above min on every axis, found z = 5 for min and 5 for max");
    CHECK(errorOf("[[object]]\ntype = \"water\"\nlevel = nan\n[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\"\n") ==
          "scene.toml:3:9: level: expected a finite number in [-1e+09, 1e+09], found nan");
    CHECK(errorOf("[[light]]\nelevation = 91\n") ==
          "scene.toml:2:13: elevation: expected a number in [-90, 90], found 91");
    CHECK(errorOf("[render]\nwidth = 0\n") == "scene.toml:2:9: width: expected an integer in 1..16384, found 0");
    CHECK(errorOf("[render]\nsamples = 65537\n") ==
          "scene.toml:2:11: samples: expected an integer in 1..65536, found 65537");
    CHECK(errorOf("[render]\nmin_weight = 1\n") == "scene.toml:2:14: min_weight: expected a number in [0, 1), found 1");
    CHECK(errorOf("[render]\nseed = -1\n") == "scene.toml:2:8: seed: expected an integer >= 0, found -1");
    CHECK(errorOf("[render]\nexposure = 0\n") == "scene.toml:2:12: exposure: expected a number > 0, found 0");
    CHECK(errorOf("[render]\nsampler = \"sobol\"\n") ==
          "scene.toml:2:11: sampler: expected one of \"regular\", \"random\", \"stratified\", \"poisson\", "
          "\"best-candidate\", found \"sobol\"");
}

TEST_CASE("Scene file: the sun's time is checked as ISO 8601 with a zone", "[loaders]") {
    CHECK(errorOf("[[light]]\ntime = \"2026-13-01T10:00Z\"\n") ==
          "scene.toml:2:8: time: expected an ISO 8601 time such as \"2026-06-21T19:30Z\", found "
          "\"2026-13-01T10:00Z\" (month 13 is not in 01..12)");
    CHECK(errorOf("[[light]]\ntime = \"2025-02-29T10:00Z\"\n") ==
          "scene.toml:2:8: time: expected an ISO 8601 time such as \"2026-06-21T19:30Z\", found "
          "\"2025-02-29T10:00Z\" (day 29 is not in month 02)");
    CHECK(errorOf("[[light]]\ntime = \"2026-06-21T19:30\"\n") ==
          "scene.toml:2:8: time: expected an ISO 8601 time such as \"2026-06-21T19:30Z\", found "
          "\"2026-06-21T19:30\" (the time needs a zone: Z for UTC or an offset such as +02:00)");
    CHECK(errorOf("[[light]]\ntime = 2026-06-21T19:30:00\n") ==
          "scene.toml:2:8: time: expected a time with a zone, such as 2026-06-21T19:30:00Z, found a local date-time");
    CHECK(errorOf("[[light]]\ntime = \"9999-12-31T23:30-01:00\"\n") ==
          "scene.toml:2:8: time: expected a time whose UTC date falls in the years 0001..9999");
    CHECK(errorOf("[[light]]\nazimuth = 200\ntime = \"2026-06-21T19:30Z\"\n") ==
          "scene.toml:2:1: key 'azimuth' conflicts with 'time', which sets the sun's position; give one or the "
          "other");
}

TEST_CASE("Scene file: a missing required key is reported at the table header", "[loaders]") {
    CHECK(errorOf("[render]\nwidth = 10\n\n[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\n") ==
          "scene.toml:4:1: missing required key 'radius' for an object of type \"sphere\"");
    CHECK(errorOf("[[object]]\ntype = \"heightfield\"\n") ==
          "scene.toml:1:1: missing required key 'file' for an object of type \"heightfield\"");
    CHECK(errorOf("[[object]]\nname = \"rock\"\n") ==
          "scene.toml:1:1: missing required key 'type' in [[object]] (one of \"heightfield\", \"sphere\", \"plane\", "
          "\"triangle\", \"polygon\", \"box\", \"water\")");
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\n") ==
          "scene.toml:1:1: missing required key 'vertices' for an object of type \"triangle\"");
    CHECK(errorOf("[[light]]\ntype = \"point\"\n") ==
          "scene.toml:1:1: missing required key 'position' for a light of type \"point\"");
    CHECK(errorOf("[[material]]\ncolor = [1, 0, 0]\n") == "scene.toml:1:1: missing required key 'name' in [[material]]");
}

TEST_CASE("Scene file: a duplicate material name is refused", "[loaders]") {
    CHECK(errorOf("[[material]]\nname = \"rock\"\n[[material]]\nname = \"sand\"\n[[material]]\nname = \"rock\"\n") ==
          "scene.toml:6:8: name: material \"rock\" is already defined at line 2");
}

TEST_CASE("Scene file: an unknown material name is refused with a suggestion", "[loaders]") {
    // Materials may be defined after the objects that use them.
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"glas\"\n"
                  "[[material]]\nname = \"glass\"\n") ==
          "scene.toml:5:12: material: no [[material]] is named \"glas\" (did you mean \"glass\"?)");
    CHECK(errorOf("[[object]]\ntype = \"box\"\nmaterial = \"steel\"\n[[material]]\nname = \"glass\"\n") ==
          "scene.toml:3:12: material: no [[material]] is named \"steel\"");
    CHECK(errorOf("[[object]]\ntype = \"box\"\nmaterial = \"steel\"\n") ==
          "scene.toml:3:12: material: no [[material]] is named \"steel\" (the scene defines no [[material]])");
}

TEST_CASE("Scene file: a missing height-field file, drape, texture or sky image is reported at its key", "[loaders]") {
    const SceneFolder folder;
    const auto error = [&](const std::string& text) -> std::string {
        try {
            parse(text, folder);
        } catch (const InputError& e) {
            return e.what();
        }
        return "(no error)";
    };
    CHECK(error("[[object]]\ntype = \"heightfield\"\n  file = \"missing.tif\"\n") ==
          "scene.toml:3:3: file: " + folder.file("missing.tif") + ": no such file");
    fs::create_directories(folder.file("tiles"));
    CHECK(error("[[object]]\ntype = \"heightfield\"\nfile = \"tiles\"\n") ==
          "scene.toml:3:1: file: " + folder.file("tiles") + ": is a directory, expected a file");
    // The system would see only "dem.tif", which exists.
    CHECK(error("[[object]]\ntype = \"heightfield\"\nfile = \"dem.tif\\u0000.zip\"\n") ==
          "scene.toml:3:8: file: expected a file path, found a string with a control character (code 0)");
    // A newline would make a name that breaks scripts listing the folder.
    CHECK(error("[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n[render]\noutput = \"a\\nb.png\"\n") ==
          "scene.toml:6:10: output: expected a file path, found a string with a control character (code 10)");
    CHECK(error("[[material]]\nname = \"photo\"\ndrape = \"missing-ortho.tif\"\n") ==
          "scene.toml:3:1: drape: " + folder.file("missing-ortho.tif") + ": no such file");
    CHECK(error("[[material]]\nname = \"photo\"\nterrain = \"drape\"\n") ==
          "scene.toml:3:11: terrain: \"drape\" needs a raster to drape (drape = \"file.tif\")");
    CHECK(error("[[material]]\nname = \"photo\"\nterrain = \"slope\"\ndrape = \"ortho.tif\"\n") ==
          "scene.toml:4:1: drape: applies only with terrain = \"drape\", found terrain = \"slope\"");
    CHECK(error("[[material]]\nname = \"globe\"\ntexture = \"missing-map.png\"\n") ==
          "scene.toml:3:1: texture: " + folder.file("missing-map.png") + ": no such file");
    CHECK(error("[sky]\nmodel = \"image\"\n") ==
          "scene.toml:1:1: missing required key 'file' for a sky of model \"image\" (an equirectangular EXR, HDR or "
          "PNG)");
    CHECK(error("[sky]\nmodel = \"image\"\nfile = \"missing-sky.exr\"\n") ==
          "scene.toml:3:1: file: " + folder.file("missing-sky.exr") + ": no such file");
    CHECK(error("[sky]\nmodel = \"physical\"\nrotation = 90\n") ==
          "scene.toml:3:1: key 'rotation' does not apply to a sky of model \"physical\" (only to \"image\")");
    CHECK(error("[[material]]\nname = \"board\"\ntexture_scale = 2\n") ==
          "scene.toml:3:1: texture_scale: applies only with texture or checker");
    CHECK(error("[[material]]\nname = \"board\"\nchecker = [0, 0, 0]\ntexture_scale = 0\n") ==
          "scene.toml:4:17: texture_scale: expected a number > 0, found 0");
}

TEST_CASE("Scene file: arrays of the wrong length are refused", "[loaders]") {
    CHECK(errorOf("[camera]\neye = [1, 2]\n") == "scene.toml:2:7: eye: expected an array of 3 numbers [x, y, z], found "
                                                 "an array of 2 values");
    CHECK(errorOf("[[material]]\nname = \"m\"\ncolor = [1, 0, 0, 1]\n") ==
          "scene.toml:3:9: color: expected an array of 3 numbers [r, g, b], found an array of 4 values");
    CHECK(errorOf("[camera]\nshutter = [0]\n") ==
          "scene.toml:2:11: shutter: expected an array of 2 numbers [open, close], found an array of 1 value");
    CHECK(errorOf("[[object]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 0], [0, 1, 0]]\n") ==
          "scene.toml:3:24: vertices[1]: expected an array of 3 numbers [x, y, z], found an array of 2 values");
}

TEST_CASE("Scene file: keys that only a dielectric uses need ior", "[loaders]") {
    CHECK(errorOf("[[material]]\nname = \"m\"\nabsorption = 0.1\n") ==
          "scene.toml:3:1: key 'absorption' applies only to a dielectric material (one with ior or ior_rgb)");
    CHECK(errorOf("[[material]]\nname = \"m\"\nfresnel = \"exact\"\n") ==
          "scene.toml:3:1: key 'fresnel' applies only to a dielectric material (one with ior or ior_rgb)");
}

TEST_CASE("Scene file: water needs a height field in the scene", "[loaders]") {
    CHECK(errorOf("[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n[[object]]\ntype = \"water\"\n") ==
          "scene.toml:5:1: a water object needs a heightfield object in the scene (it is clipped to the terrain's "
          "footprint)");
}

TEST_CASE("Scene file: 2000 random mutations of a valid scene only ever raise located InputErrors", "[loaders]") {
    const SceneFolder folder;
    const std::regex located(R"(^scene\.toml:[0-9]+:[0-9]+: [^\n]+$)");
    const std::string alphabet = "[]{}\"'=,.#\n\\-+0123456789eEinfatrsxyz_ \t";
    std::mt19937 rng(20260621);
    const auto below = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(rng); };
    int parsed = 0;
    int refused = 0;
    std::vector<std::string> unexpected;
    for (int trial = 0; trial < 2000; ++trial) {
        std::string text = kFullScene;
        const size_t mutations = 1 + below(3);
        for (size_t m = 0; m < mutations && !text.empty(); ++m) {
            switch (below(4)) {
                case 0: text[below(text.size())] = static_cast<char>(below(256)); break;
                case 1: text[below(text.size())] = alphabet[below(alphabet.size())]; break;
                case 2: text.resize(below(text.size())); break;
                default: {
                    std::vector<std::string> lines;
                    size_t start = 0;
                    for (size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
                        lines.push_back(text.substr(start, end - start));
                    lines.push_back(text.substr(start));
                    std::swap(lines[below(lines.size())], lines[below(lines.size())]);
                    text.clear();
                    for (size_t i = 0; i < lines.size(); ++i) text += (i ? "\n" : "") + lines[i];
                }
            }
        }
        try {
            parse(text, folder);
            ++parsed;
        } catch (const InputError& e) {
            ++refused;
            if (!std::regex_match(std::string(e.what()), located)) unexpected.push_back(e.what());
        } catch (const std::exception& e) {
            unexpected.push_back(std::string("not an InputError: ") + e.what());
        }
    }
    INFO("parsed " << parsed << ", refused " << refused);
    for (size_t i = 0; i < std::min<size_t>(unexpected.size(), 5); ++i) UNSCOPED_INFO(unexpected[i]);
    CHECK(unexpected.empty());
    CHECK(parsed + refused == 2000);
    CHECK(refused > 1000);  // the mutations do damage: most scenes must be refused
}
