// `terracast scene` end to end through the real executable: a sample scene renders, the ray tree of one pixel
// prints (and nothing is written without -o), scene-file errors cite file:line:column with exit 2, the picture
// does not depend on threads, --focus finds the distance to what a pixel sees, and --adaptive reports its
// samples.
#include "support/run_command.h"
#include "support/temp_dir.h"
#include "loaders/image_io.h"

#include <catch2/catch.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>
#include <vector>

using namespace terracast;
using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {
const std::string kScenes = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
}

TEST_CASE("CLI: scene renders a sample scene and reports rays by kind", "[cli][scene]") {
    TempDir dir("scene-cli");
    const std::string out = (dir.path() / "boxes.png").string();
    const auto r = runTerracast("scene '" + kScenes + "boxes-and-polygons.toml' -o '" + out + "' --size 64x48 --threads 2");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const RgbImage image = readImage(out);
    CHECK(image.width == 64);
    CHECK(image.height == 48);
    CHECK(r.err.find("3072 primary") != std::string::npos);
    CHECK(r.err.find(" 0 refraction,") != std::string::npos);
    CHECK(r.err.find(" sky-visibility rays") != std::string::npos);
}

namespace {

// The names in a folder, sorted.
std::vector<std::string> listing(const fs::path& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

// Three numbers written "a, b, c".
glm::dvec3 triple(const std::string& text) {
    glm::dvec3 v{0.0};
    REQUIRE(std::sscanf(text.c_str(), "%lf, %lf, %lf", &v.x, &v.y, &v.z) == 3);
    return v;
}

// One line of a printed ray tree.
struct TreeLine {
    int depth = 0;
    std::string kind, hit, valueName;
    glm::dvec3 origin{0.0}, dir{0.0}, weight{0.0}, value{0.0}, share{0.0};
    double t = 0.0;  // 0 when the line gives no distance
};

std::vector<TreeLine> parseTree(const std::string& out) {
    static const std::regex line(R"(( *)(\w+) from \(([^)]*)\) dir \(([^)]*)\) -> (.+?)(?: at (\S+) m)?  )"
                                 R"(weight \(([^)]*)\) (returns|transmittance|adds) \(([^)]*)\)(?:.* adds \(([^)]*)\).*)?)");
    std::vector<TreeLine> tree;
    std::istringstream in(out);
    for (std::string text; std::getline(in, text);) {
        std::smatch m;
        if (!std::regex_match(text, m, line)) continue;
        TreeLine l;
        l.depth = int(m[1].length()) / 2;
        l.kind = m[2];
        l.origin = triple(m[3]);
        l.dir = triple(m[4]);
        l.hit = m[5];
        if (m[6].matched) l.t = std::stod(m[6]);
        l.weight = triple(m[7]);
        l.valueName = m[8];
        l.value = triple(m[9]);
        l.share = m[10].matched ? triple(m[10]) : l.value;  // a sky-visibility ray's only value is its share
        tree.push_back(l);
    }
    return tree;
}

void checkNear(const glm::dvec3& got, const glm::dvec3& want, double margin) {
    INFO("got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x << ", " << want.y << ", "
                 << want.z << ")");
    CHECK(glm::length(got - want) < margin);
}

}  // namespace

TEST_CASE("CLI: scene --debug-pixel prints the pixel's ray tree and writes no image", "[cli][scene]") {
    // A mirror-finished ball straight ahead of a pinhole camera, lit by a sun in the south, with no sky: the
    // tree of pixel (3, 2) of a 5x5 picture is worked out here from the camera, the sphere and the sun alone.
    TempDir dir("scene-debug");
    const std::string scene = dir.file("ball.toml");
    std::ofstream(scene) << "[camera]\neye = [0, 0, 0]\nlook_at = [0, 10, 0]\nfov = 40\n"
                            "[[material]]\nname = \"shiny\"\ncolor = [0.5, 0.5, 0.5]\nmirror = 0.5\n"
                            "[[object]]\ntype = \"sphere\"\nname = \"ball\"\ncenter = [0, 10, 0]\nradius = 2\n"
                            "material = \"shiny\"\n"
                            "[[light]]\ntype = \"sun\"\nazimuth = 180\nelevation = 30\n"
                            "[sky]\nmodel = \"none\"\n"
                            "[render]\nwidth = 5\nheight = 5\noutput = \"ball.png\"\n";
    const auto r = runTerracast("scene '" + scene + "' --debug-pixel 3,2");
    INFO(r.out << r.err);
    REQUIRE(r.exitCode == 0);
    // The file's own output is not rendered: a debug run leaves nothing behind.
    CHECK(listing(dir.path()) == std::vector<std::string>{"ball.toml"});
    CHECK(r.out.rfind("ray tree of pixel 3,2 (3 rays; ", 0) == 0);

    // Pixel (3, 2): 0.4 of the half-width right of the centre, on the horizon.
    const double tanHalf = std::tan(20.0 * M_PI / 180.0);
    const glm::dvec3 dir0 = glm::normalize(glm::dvec3(0.4 * tanHalf, 1.0, 0.0));
    const glm::dvec3 centre{0, 10, 0};
    const double along = glm::dot(centre, dir0), off = glm::length(centre - along * dir0);
    const double t = along - std::sqrt(4.0 - off * off);
    const glm::dvec3 p = t * dir0, n = (p - centre) / 2.0;
    const glm::dvec3 sun{0.0, -std::cos(M_PI / 6.0), std::sin(M_PI / 6.0)};
    const double shade = 0.5 * glm::dot(n, sun);  // albedo x cos; the reflection sees only black sky
    REQUIRE(shade > 0.1);

    const auto tree = parseTree(r.out);
    REQUIRE(tree.size() == 3);
    CHECK(tree[0].kind == "primary");
    CHECK(tree[0].depth == 0);
    checkNear(tree[0].origin, glm::dvec3(0.0), 1e-3);
    checkNear(tree[0].dir, dir0, 1e-3);
    CHECK(tree[0].hit == "ball");
    CHECK(tree[0].t == Approx(t).margin(1e-3));
    checkNear(tree[0].weight, glm::dvec3(1.0), 1e-3);
    CHECK(tree[0].valueName == "returns");
    checkNear(tree[0].value, glm::dvec3(shade), 1e-3);
    checkNear(tree[0].share, glm::dvec3(shade), 1e-3);  // what the camera ray adds to the pixel

    CHECK(tree[1].kind == "shadow");
    CHECK(tree[1].depth == 1);
    checkNear(tree[1].origin, p, 1e-3);
    checkNear(tree[1].dir, sun, 1e-3);
    CHECK(tree[1].hit == "light");
    CHECK(tree[1].valueName == "transmittance");
    checkNear(tree[1].value, glm::dvec3(1.0), 1e-3);
    checkNear(tree[1].share, glm::dvec3(shade), 1e-3);  // all of the ball's light comes from the sun

    CHECK(tree[2].kind == "reflection");
    CHECK(tree[2].depth == 1);
    checkNear(tree[2].origin, p, 1e-3);
    checkNear(tree[2].dir, dir0 - 2.0 * glm::dot(dir0, n) * n, 1e-3);
    CHECK(tree[2].hit == "sky");
    checkNear(tree[2].weight, glm::dvec3(0.5), 1e-3);
    checkNear(tree[2].value, glm::dvec3(0.0), 1e-6);
    checkNear(tree[2].share, glm::dvec3(0.0), 1e-6);

    const size_t value = r.out.find("pixel value (");
    REQUIRE(value != std::string::npos);
    checkNear(triple(r.out.substr(value + 13)), glm::dvec3(shade), 1e-3);

    // With -o the image is rendered too, where -o says.
    const std::string out = dir.file("debug.png");
    const auto withImage = runTerracast("scene '" + scene + "' --debug-pixel 3,2 -o '" + out + "'");
    REQUIRE(withImage.exitCode == 0);
    CHECK(readImage(out).width == 5);
    CHECK_FALSE(fs::exists(dir.path() / "ball.png"));
}

TEST_CASE("CLI: scene --debug-pixel on a sample scene traces glass and leaves the samples folder alone", "[cli][scene]") {
    // Pixel (24, 22) of the 64x48 view of the absorption scene looks through the middle green-glass ball, which
    // refracts and reflects. The scene names its own output beside it; a debug run must not write it.
    const auto before = listing(kScenes);
    const auto r = runTerracast("scene '" + kScenes + "absorption.toml' --size 64x48 --debug-pixel 24,22");
    INFO(r.out << r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(listing(kScenes) == before);
    CHECK_FALSE(fs::exists(kScenes + "absorption.png"));
    CHECK(r.out.rfind("ray tree of pixel 24,22", 0) == 0);
    const auto tree = parseTree(r.out);
    REQUIRE(tree.size() >= 3);
    CHECK(tree[0].kind == "primary");
    checkNear(tree[0].origin, glm::dvec3(0.0, -8.0, 3.0), 1e-3);
    CHECK(tree[0].hit == "sphere 3");
    CHECK(tree[1].kind == "refraction");
    CHECK(tree[1].hit == "sphere 3");  // and out through its far side
    CHECK(r.out.find("pixel value (") != std::string::npos);
    const auto outside = runTerracast("scene '" + kScenes + "absorption.toml' --size 64x48 --debug-pixel 64,2");
    CHECK(outside.exitCode == 2);
    CHECK(outside.err == "terracast: error: --debug-pixel: expected a pixel inside 64x48, found 64,2\n");
}

TEST_CASE("CLI: a scene-file error cites file, line and column, exits 2 and writes nothing", "[cli][scene]") {
    TempDir dir("scene-err");
    const std::string scene = (dir.path() / "bad.toml").string();
    std::ofstream(scene) << "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\n";
    const std::string out = (dir.path() / "out.png").string();
    const auto r = runTerracast("scene '" + scene + "' -o '" + out + "'");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err.rfind("terracast: error: " + scene + ":4:10: ", 0) == 0);
    CHECK_FALSE(fs::exists(out));
    // A scene without any output named anywhere.
    std::ofstream(scene) << "[[object]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1\n";
    const auto noOut = runTerracast("scene '" + scene + "'");
    CHECK(noOut.exitCode == 2);
    CHECK(noOut.err == "terracast: error: " + scene + ": no output image: give -o OUT or set output in [render]\n");
}

TEST_CASE("CLI: a scene renders byte-identical PNGs with 1, 2 and 8 threads, run after run", "[cli][scene]") {
    TempDir dir("scene-det");
    std::string first;
    int run = 0;
    for (int threads : {1, 2, 8, 8}) {
        const std::string out = (dir.path() / (std::to_string(run++) + "-" + std::to_string(threads) + "-threads.png")).string();
        const auto r = runTerracast("scene '" + kScenes + "spheres-on-terrain.toml' -o '" + out +
                                    "' --size 96x54 --spp 4 --threads " + std::to_string(threads));
        REQUIRE(r.exitCode == 0);
        const std::string bytes = slurp(out);
        if (first.empty()) first = bytes;
        CHECK(bytes == first);
    }
}

TEST_CASE("CLI: scene --focus sets the focus distance to what the pixel sees", "[cli][scene]") {
    // A thin lens 2 m above a ground plane, looking down the +y axis at a point 10 m ahead.
    TempDir dir("scene-focus");
    const std::string scene = dir.file("focus.toml");
    std::ofstream(scene) << "[camera]\ntype = \"thin-lens\"\neye = [0, 0, 2]\nlook_at = [0, 10, 0]\nfov = 40\n"
                            "aperture = 0.05\n"
                            "[[object]]\ntype = \"plane\"\n"
                            "[sky]\nmodel = \"flat\"\n";
    const std::string out = dir.file("focus.png");
    const int width = 64, height = 48, px = 10, py = 40;
    const auto r = runTerracast("scene '" + scene + "' -o '" + out + "' --size 64x48 --threads 2 --focus 10,40");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(readImage(out).width == width);

    // The pixel centre's pinhole ray, with its component along the view axis scaled to 1, meets the plane z = 0
    // after s of those units: s is the distance along the axis.
    const glm::dvec3 eye{0, 0, 2};
    const glm::dvec3 forward = glm::normalize(glm::dvec3(0, 10, 0) - eye);
    const glm::dvec3 right = glm::normalize(glm::cross(forward, glm::dvec3(0, 0, 1)));
    const glm::dvec3 up = glm::cross(right, forward);
    const double tanV = std::tan(20.0 * M_PI / 180.0), aspect = double(width) / height;
    const double sx = 2.0 * (px + 0.5) / width - 1.0, sy = 1.0 - 2.0 * (py + 0.5) / height;
    const glm::dvec3 d = forward + sx * tanV * aspect * right + sy * tanV * up;
    const double expected = -eye.z / d.z;
    const std::string key = "terracast: focus distance ";
    const size_t at = r.err.find(key);
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(r.err.substr(at + key.size())) == Approx(expected).margin(0.006));
    CHECK(r.err.find(" m (pixel 10,40)") != std::string::npos);
    // Another pixel sees the ground farther away; a pixel in the sky has nothing to focus on.
    const auto higher = runTerracast("scene '" + scene + "' -o '" + out + "' --size 64x48 --focus 10,30");
    REQUIRE(higher.exitCode == 0);
    CHECK(std::stod(higher.err.substr(higher.err.find(key) + key.size())) > expected + 1.0);
    const auto sky = runTerracast("scene '" + scene + "' -o '" + dir.file("sky.png") + "' --size 64x48 --focus 10,2");
    CHECK(sky.exitCode == 2);
    CHECK(sky.err == "terracast: error: --focus: pixel 10,2 sees the sky; pick a pixel on an object\n");
    CHECK_FALSE(fs::exists(dir.file("sky.png")));
}

TEST_CASE("CLI: scene --adaptive reports the samples it used", "[cli][scene]") {
    // Seen from above, a black box covers x < 10.5 and a white sky the rest of a 16 x 8 m picture with 1 m
    // pixels: the edge runs down the middle of column 10. Flat pixels have no variance and stop at the 16
    // samples the rule needs at least; edge pixels, half black, never reach the error and take all 64.
    TempDir dir("scene-adaptive");
    const std::string scene = dir.file("edge.toml");
    std::ofstream(scene) << "[camera]\ntype = \"orthographic\"\neye = [8, 4, 10]\nlook_at = [8, 4, 0]\nup = [0, 1, 0]\n"
                            "height = 8\n"
                            "[[material]]\nname = \"black\"\nkd = 0\n"
                            "[[object]]\ntype = \"box\"\nmin = [-100, -100, -1]\nmax = [10.5, 100, 0]\n"
                            "material = \"black\"\n"
                            "[sky]\nmodel = \"flat\"\ncolor = [1, 1, 1]\n"
                            "[render]\nwidth = 16\nheight = 8\n";
    const std::string out = dir.file("edge.png");
    const auto r = runTerracast("scene '" + scene + "' -o '" + out + "' --spp 64 --adaptive 0.002 --threads 2");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const double average = (15.0 * 16.0 + 64.0) / 16.0;  // per row: 15 flat pixels and one edge pixel
    std::ostringstream report;
    report << std::fixed << std::setprecision(1) << "(16x8, " << average << " spp on average, adaptive up to 64)";
    CHECK(r.err.find(report.str()) != std::string::npos);
    // One primary ray per camera sample.
    std::ostringstream primary;
    primary << ": " << int(average * 16 * 8) << " primary";
    CHECK(r.err.find(primary.str()) != std::string::npos);
    const RgbImage image = readImage(out);
    REQUIRE(image.width == 16);
    for (int y = 0; y < 8; ++y) {
        CHECK(image.at(9, y, 0) == 0.0f);
        CHECK(image.at(11, y, 0) == Approx(1.0f).margin(1e-3));
        CHECK(image.at(10, y, 0) == Approx(0.5f).margin(0.15));  // half covered
    }
}
