// `terracast bench` through the real executable: a tiny synthetic grid gives a complete report (every method,
// both cameras, finite positive rates, ratios to Embree's own pass), grids over --max-memory are reported as
// skipped without being made, and bad options are refused with one line and exit 2.
#include "support/json.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

using namespace terracast::testing;

namespace {

bool finitePositive(const JsonValue& v) { return v.isNumber() && std::isfinite(v.number) && v.number > 0.0; }

}  // namespace

TEST_CASE("CLI: bench on a 65 x 65 grid reports every method on both cameras", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "bench.json").string();
    const auto r = runTerracast("bench --sizes 65 --threads 1 --json '" + json + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    for (const char* name : {"bilinear", "bilinear-flat", "triangles", "embree", "embree-grid", "synthetic-65"})
        CHECK(r.out.find(name) != std::string::npos);

    const JsonValue doc = parseJson(slurp(json));
    CHECK(doc["image_width"].number == 1024);
    CHECK(doc["image_height"].number == 768);
    CHECK(doc["sun_elevation_deg"].number == 20);
    REQUIRE(doc["threads"].array.size() == 1);
    CHECK(doc["threads"][0].number == 1);
    REQUIRE(doc["grids"].array.size() == 1);
    const JsonValue& grid = doc["grids"][0];
    CHECK(grid["dem"].string == "synthetic-65");
    CHECK(grid["width"].number == 65);
    CHECK(grid["height"].number == 65);
    CHECK(grid["cells"].number == 64 * 64);
    CHECK(grid["rays"].number == 1024 * 768);
    CHECK_FALSE(grid["skipped"].boolean);

    const std::vector<std::string> expected{"bilinear", "bilinear-flat", "triangles", "embree", "embree-grid"};
    REQUIRE(grid["methods"].array.size() == expected.size());
    double directBytesPerCell = 0.0;
    for (size_t k = 0; k < expected.size(); ++k) {
        const JsonValue& m = grid["methods"][k];
        INFO("method " << expected[k]);
        CHECK(m["name"].string == expected[k]);
        CHECK_FALSE(m["skipped"].boolean);
        for (const char* key : {"build_s", "memory_bytes", "peak_memory_bytes", "bytes_per_cell", "peak_bytes_per_cell",
                                "hit_agreement", "primary_rays_per_s", "shadow_rays_per_s"}) {
            INFO(key);
            CHECK(finitePositive(m[key]));
        }
        CHECK(finitePositive(m["ratio_to_embree"]["primary"]));
        CHECK(finitePositive(m["ratio_to_embree"]["shadow"]));
        CHECK(m["peak_bytes_per_cell"].number >= m["bytes_per_cell"].number);
        CHECK(m["bytes_per_cell"].number == Approx(m["memory_bytes"].number / (64.0 * 64.0)));
        if (k == 0) directBytesPerCell = m["bytes_per_cell"].number;
        if (k < 3) CHECK(m["bytes_per_cell"].number == directBytesPerCell);  // the same grid and pyramid
        if (k >= 3) CHECK(m["bytes_per_cell"].number > 4 * directBytesPerCell);  // Embree copies and indexes
        // The agreement is with bilinear's verdicts: the flat walk must reproduce them exactly, the triangle
        // surfaces nearly.
        if (k <= 1) CHECK(m["hit_agreement"].number == 1.0);
        else CHECK(m["hit_agreement"].number > 0.99);

        REQUIRE(m["passes"].array.size() == 2);
        CHECK(m["passes"][0]["camera"].string == "corner");
        CHECK(m["passes"][1]["camera"].string == "grazing");
        for (const JsonValue& p : m["passes"].array) {
            INFO("camera " << p["camera"].string);
            CHECK(p["threads"].number == 1);
            CHECK(p["primary_rays"].number == 1024 * 768);
            CHECK(finitePositive(p["shadow_rays"]));
            CHECK(p["shadow_rays"].number <= p["primary_rays"].number);
            CHECK(finitePositive(p["primary_rays_per_s"]));
            CHECK(finitePositive(p["shadow_rays_per_s"]));
            CHECK(finitePositive(p["ratio_to_embree"]["primary"]));
            CHECK(finitePositive(p["ratio_to_embree"]["shadow"]));
            if (expected[k] == "embree") {
                CHECK(p["ratio_to_embree"]["primary"].number == 1.0);
                CHECK(p["ratio_to_embree"]["shadow"].number == 1.0);
            }
        }
        // The headline numbers are the corner camera's at the most threads.
        CHECK(m["primary_rays_per_s"].number == m["passes"][0]["primary_rays_per_s"].number);
        CHECK(m["shadow_rays_per_s"].number == m["passes"][0]["shadow_rays_per_s"].number);
    }
    // The same camera rays for every method; the flat walk and the pyramid shade the same hits.
    CHECK(grid["methods"][0]["passes"][0]["shadow_rays"].number == grid["methods"][1]["passes"][0]["shadow_rays"].number);
    CHECK(grid["methods"][0]["passes"][1]["shadow_rays"].number == grid["methods"][1]["passes"][1]["shadow_rays"].number);
}

TEST_CASE("CLI: bench skips grids over --max-memory and says what they need", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "skipped.json").string();
    // 100 MiB holds neither one pass's buffers at 1024 x 768 nor the 32769^2 grid: nothing is made or traced.
    const auto r = runTerracast("bench --sizes 65 --large --max-memory 100M --json '" + json + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.find("synthetic-32769") != std::string::npos);
    CHECK(r.out.find("skipped") != std::string::npos);
    const JsonValue doc = parseJson(slurp(json));
    REQUIRE(doc["grids"].array.size() == 2);
    CHECK(doc["grids"][0]["dem"].string == "synthetic-65");
    const JsonValue& large = doc["grids"][1];
    CHECK(large["dem"].string == "synthetic-32769");
    CHECK(large["width"].number == 32769);
    CHECK(large["skipped"].boolean);
    // float32 heights alone: 32769^2 x 4 bytes, 4 GiB.
    CHECK(large["memory_needed_bytes"].number > 32769.0 * 32769.0 * 4.0);
    CHECK(large["methods"].array.empty());
    for (const JsonValue& g : doc["grids"].array) CHECK(g["skipped"].boolean);
}

TEST_CASE("CLI: bench refuses bad options with one line and exit 2", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "never.json").string();
    const std::string out = " --json '" + json + "'";
    // Each refusal names what it refused.
    const std::pair<std::string, std::string> cases[] = {
        {"--sizes 100" + out, "--sizes"},
        {"--sizes 65,abc" + out, "--sizes"},
        {"--sizes 131073" + out, "--sizes"},
        {"--threads -1" + out, "--threads"},
        {"--max-memory lots" + out, "--max-memory"},
        {"--real --data /no/such/folder" + out, "/no/such/folder"},
        {"--sizes 65 --json /no/such/folder/r.json", "/no/such/folder"},
    };
    for (const auto& [args, named] : cases) {
        INFO(args);
        const auto r = runTerracast("bench " + args);
        CHECK(r.exitCode == 2);
        CHECK(lineCount(r.err) == 1);
        CHECK(r.err.rfind("terracast: error: ", 0) == 0);
        CHECK(r.err.find(named) != std::string::npos);
        CHECK(r.out.empty());
    }
    CHECK_FALSE(std::filesystem::exists(json));
}
