// What the command line promises about its options, through the real executable: --quiet keeps stderr empty,
// the map products refuse Embree's methods, compare measures every method --methods lists, and the map view
// ignores the perspective-only --sky and --camera.
#include "support/json.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <filesystem>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {
const std::string kDem =
    std::string(TERRACAST_SOURCE_DIR) + "/data-samples/landfire-storm-lake-mt-utm12n-int16-small-nodata.tif";
const std::string kScene = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/boxes-and-polygons.toml";
}  // namespace

TEST_CASE("CLI: --quiet leaves stderr empty, and without it one summary line ends the job", "[cli]") {
    const TempDir dir("options-quiet");
    // The DEM has no vertical unit: its warning is printed either way.
    const std::string warning = "terracast: warning: " + kDem + ": no vertical unit, assuming metres\n";
    const auto loud = runTerracast("render '" + kDem + "' -o '" + dir.file("a.png") + "' --size 32x24");
    REQUIRE(loud.exitCode == 0);
    CHECK(loud.err.rfind(warning, 0) == 0);
    CHECK(lineCount(loud.err) == 2);
    CHECK(loud.err.find("terracast: rendered ") != std::string::npos);
    const auto quiet = runTerracast("render '" + kDem + "' -o '" + dir.file("b.png") + "' --size 32x24 -q");
    REQUIRE(quiet.exitCode == 0);
    CHECK(quiet.err == warning);
    const auto scene = runTerracast("scene '" + kScene + "' -o '" + dir.file("c.png") + "' --size 32x24 --spp 1 -q");
    REQUIRE(scene.exitCode == 0);
    CHECK(scene.err.empty());
    CHECK(fs::exists(dir.file("c.png")));
}

TEST_CASE("CLI: the map products trace the grid directly and refuse Embree's methods", "[cli]") {
    const TempDir dir("options-maps");
    for (const std::string command : {"shadow", "horizon", "viewshed"})
        for (const std::string method : {"embree", "embree-grid"}) {
            INFO(command << " --method " << method);
            const std::string extra = command == "horizon" ? " --azimuth 90" : command == "viewshed" ? " --observer 1,1 --lonlat" : "";
            const auto r = runTerracast(command + " '" + kDem + "' -o '" + dir.file("m.tif") + "' --method " + method + extra);
            CHECK(r.exitCode == 2);
            CHECK(r.err == "terracast: error: --method: " + command + " traces the grid directly; expected bilinear, "
                           "bilinear-double, triangles, nearest or reference, found '" + method + "'\n");
        }
    CHECK(dir.entryCount() == 0);
}

TEST_CASE("CLI: compare measures every method --methods lists, in that order", "[cli]") {
    const TempDir dir("options-compare");
    const auto r = runTerracast("compare '" + kDem + "' --size 32x24 --methods nearest,triangles,bilinear,embree "
                                "--json '" + dir.file("c.json") + "'");
    REQUIRE(r.exitCode == 0);
    const JsonValue report = parseJson(slurp(dir.file("c.json")));
    std::vector<std::string> names;
    for (const auto& m : report["methods"].array) names.push_back(m["name"].string);
    // The reference is always measured too, first.
    REQUIRE(names.size() == 5);
    CHECK(names[0] == report["reference"].string);
    CHECK(names[1] == "nearest");
    CHECK(names[2] == "triangles");
    CHECK(names[3] == "bilinear");
    CHECK(names[4] == "embree");
}

TEST_CASE("CLI: the map view ignores --sky and --camera, which only the perspective view reads", "[cli]") {
    const TempDir dir("options-mapview");
    const auto map = runTerracast("render '" + kDem + "' --view map -o '" + dir.file("m.png") +
                                  "' --sky bogus --camera nonsense -q");
    CHECK(map.exitCode == 0);
    CHECK(fs::exists(dir.file("m.png")));
    const auto perspective = runTerracast("render '" + kDem + "' -o '" + dir.file("p.png") + "' --sky bogus -q");
    CHECK(perspective.exitCode == 2);
    CHECK(perspective.err == "terracast: error: --sky: expected physical, gradient, flat or none, found 'bogus'\n");
}
