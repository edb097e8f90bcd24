// `terracast scene` end to end through the real executable: a sample scene renders, the ray tree of one pixel
// prints, scene-file errors cite file:line:column with exit 2, and the picture does not depend on threads.
#include "support/run_command.h"
#include "support/temp_dir.h"
#include "loaders/image_io.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace terracast;
using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {
const std::string kScenes = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/scenes/";
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
    CHECK(r.err.find(" 0 refraction rays") != std::string::npos);
}

TEST_CASE("CLI: scene --debug-pixel prints the pixel's ray tree", "[cli][scene]") {
    // Pixel (40, 30) of the 64x48 view of the spheres scene: through the glass ball, which refracts and reflects.
    const auto r = runTerracast("scene '" + kScenes + "absorption.toml' --size 64x48 --debug-pixel 24,22");
    INFO(r.out << r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.rfind("ray tree of pixel 24,22", 0) == 0);
    CHECK(r.out.find("primary from") != std::string::npos);
    CHECK(r.out.find("refraction from") != std::string::npos);
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
