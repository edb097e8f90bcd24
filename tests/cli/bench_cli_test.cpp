// `terracast bench` through the real executable: a tiny synthetic grid gives a complete report (every method,
// both cameras, finite positive rates, ratios to Embree's own pass), grids over --max-memory are reported as
// skipped without being made, bad options are refused with one line and exit 2, --svg draws the rates that
// the report gives, and --file-to-picture times `render` from a PNG height map with both tracers.
#include "heightfield/traversal.h"
#include "tracer/measure/whole_process.h"
#include "support/json.h"
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

using namespace terracast::testing;

namespace {

bool finitePositive(const JsonValue& v) { return v.isNumber() && std::isfinite(v.number) && v.number > 0.0; }

// Points TMPDIR at another folder while alive (the commands run under it inherit it), then restores it.
class TmpDirOverride {
public:
    explicit TmpDirOverride(const std::string& dir) {
        if (const char* old = std::getenv("TMPDIR")) old_ = old, had_ = true;
        ::setenv("TMPDIR", dir.c_str(), 1);
    }
    ~TmpDirOverride() {
        if (had_) ::setenv("TMPDIR", old_.c_str(), 1);
        else ::unsetenv("TMPDIR");
    }
    TmpDirOverride(const TmpDirOverride&) = delete;
    TmpDirOverride& operator=(const TmpDirOverride&) = delete;

private:
    std::string old_;
    bool had_ = false;
};

// One line of the bench chart: the method and camera it draws and its points (x, y) in SVG units.
struct SvgLine {
    std::string method, camera;
    std::vector<std::pair<double, double>> points;
};

std::vector<SvgLine> svgPolylines(const std::string& svg) {
    std::vector<SvgLine> lines;
    const std::regex element("<polyline ([^>]*)/>");
    const std::regex attribute("([a-z-]+)=\"([^\"]*)\"");
    for (auto e = std::sregex_iterator(svg.begin(), svg.end(), element); e != std::sregex_iterator(); ++e) {
        const std::string attrs = (*e)[1];
        std::map<std::string, std::string> a;
        for (auto t = std::sregex_iterator(attrs.begin(), attrs.end(), attribute); t != std::sregex_iterator(); ++t)
            a[(*t)[1]] = (*t)[2];
        SvgLine line{a["data-method"], a["data-camera"], {}};
        std::stringstream in(a["points"]);
        std::string xy;
        while (in >> xy) {
            const auto comma = xy.find(',');
            line.points.emplace_back(std::stod(xy.substr(0, comma)), std::stod(xy.substr(comma + 1)));
        }
        lines.push_back(line);
    }
    return lines;
}

}  // namespace

TEST_CASE("CLI: bench on a 65 x 65 grid reports every method on both cameras", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "bench.json").string();
    const auto r = runTerracast("bench --sizes 65 --threads 1 --repeat 2 --json '" + json + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    for (const char* name : {"bilinear", "bilinear-flat", "triangles", "embree", "embree-grid", "synthetic-65"})
        CHECK(r.out.find(name) != std::string::npos);

    const JsonValue doc = parseJson(slurp(json));
    CHECK(doc["image_width"].number == 1024);
    CHECK(doc["image_height"].number == 768);
    CHECK(doc["sun_elevation_deg"].number == 20);
    CHECK(doc["cpu"].type == JsonValue::Type::String);
    // The direct kernels' instruction set, as the library reports it, in the JSON and the header line.
    CHECK(doc["kernels"].string == terracast::kernelIsaName(terracast::kernelIsa()));
    CHECK(r.out.find(std::string("direct kernels: ") + terracast::kernelIsaName(terracast::kernelIsa())) !=
          std::string::npos);
    CHECK(doc["file_to_picture"].type == JsonValue::Type::Null);  // only with --file-to-picture
    REQUIRE(doc["threads"].array.size() == 1);
    CHECK(doc["threads"][0].number == 1);
    CHECK(doc["repeat"].number == 2);
    CHECK(doc["bands"].number == 8);
    CHECK(r.out.find("2 traces per pass after one untimed, in 8 bands of rows") != std::string::npos);
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

TEST_CASE("CLI: bench --methods measures the methods asked for, in report order, with embree as reference",
          "[cli][bench][heavy]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "methods.json").string();
    const auto r = runTerracast("bench --sizes 17 --threads 1 --repeat 1 --methods embree-grid,triangles --json '" + json + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const JsonValue doc = parseJson(slurp(json));
    REQUIRE(doc["grids"].array.size() == 1);
    CHECK(doc["grids"][0]["reference"].string == "triangles");  // hit agreement is measured against it
    const JsonValue& methods = doc["grids"][0]["methods"];
    REQUIRE(methods.array.size() == 3);
    CHECK(methods[0]["name"].string == "triangles");
    CHECK(methods[1]["name"].string == "embree");
    CHECK(methods[2]["name"].string == "embree-grid");
    CHECK(r.out.find("bilinear") == std::string::npos);
}

TEST_CASE("CLI: bench skips grids over --max-memory and says what they need", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "skipped.json").string();
    // 100 MiB holds neither one pass's buffers at 1024 x 768 nor the 32769^2 grid: nothing is made or traced.
    const auto r = runTerracast("bench --sizes 65 --repeat 1 --large --max-memory 100M --json '" + json + "'");
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
    // The int16 grid (2.7 bytes per cell) is made through a transient float32 copy (4 bytes per vertex).
    CHECK(large["memory_needed_bytes"].number > 32769.0 * 32769.0 * (4.0 + 2.0));
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
        {"--repeat 0" + out, "--repeat"},
        {"--bands 0" + out, "--bands"},
        {"--bands 769" + out, "--bands"},
        {"--max-memory lots" + out, "--max-memory"},
        {"--real --data /no/such/folder" + out, "/no/such/folder"},
        {"--sizes 65 --json /no/such/folder/r.json", "/no/such/folder"},
        {"--sizes 65 --svg /no/such/folder/r.svg" + out, "/no/such/folder"},
        {"--sizes 65 --methods bilinear,nope" + out, "--methods"},
        {"--sizes 65 --methods bilinear," + out, "--methods"},
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

TEST_CASE("CLI: bench --svg draws each method's rates on both cameras, ordered as the report", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::string json = (dir.path() / "bench.json").string();
    const std::string svgPath = (dir.path() / "rates.svg").string();
    const auto r = runTerracast("bench --sizes 9,17 --threads 1 --repeat 1 --json '" + json + "' --svg '" + svgPath + "'");
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    const std::string svg = slurp(svgPath);
    REQUIRE(svg.rfind("<svg", 0) == 0);
    const auto end = svg.find_last_not_of(" \n");
    REQUIRE(end != std::string::npos);
    CHECK(svg.substr(0, end + 1).size() >= 6);
    CHECK(svg.compare(end + 1 - 6, 6, "</svg>") == 0);
    CHECK(svg.find("</svg>") == end + 1 - 6);  // one document
    // Every element opened is closed: as many <g ...> as </g>.
    size_t open = 0, close = 0;
    for (size_t k = svg.find("<g "); k != std::string::npos; k = svg.find("<g ", k + 1)) ++open;
    for (size_t k = svg.find("</g>"); k != std::string::npos; k = svg.find("</g>", k + 1)) ++close;
    CHECK(open == close);
    CHECK(svg.find("grid size") != std::string::npos);
    CHECK(svg.find("hardware thread") != std::string::npos);

    const JsonValue doc = parseJson(slurp(json));
    const auto& grids = doc["grids"].array;
    REQUIRE(grids.size() == 2);
    const std::vector<SvgLine> lines = svgPolylines(svg);
    for (const char* camera : {"corner", "grazing"}) {
        INFO("camera " << camera);
        // The headline of each method and grid: its pass on this camera at the most threads (1 here).
        std::map<std::string, std::vector<double>> rates;
        for (const JsonValue& g : grids)
            for (const JsonValue& m : g["methods"].array)
                for (const JsonValue& p : m["passes"].array)
                    if (p["camera"].string == camera) rates[m["name"].string].push_back(p["primary_rays_per_s"].number);
        REQUIRE(rates.size() == 5);
        std::map<std::string, const SvgLine*> byMethod;
        for (const auto& line : lines)
            if (line.camera == camera) {
                CHECK(byMethod.count(line.method) == 0);  // one line per method
                byMethod[line.method] = &line;
            }
        REQUIRE(byMethod.size() == rates.size());
        for (const auto& [method, values] : rates) {
            INFO("method " << method);
            REQUIRE(byMethod.count(method) == 1);
            REQUIRE(byMethod[method]->points.size() == grids.size());
            // Sizes grow to the right.
            CHECK(byMethod[method]->points[0].first < byMethod[method]->points[1].first);
        }
        // On each grid, a higher rate is drawn higher up (a smaller y).
        for (size_t g = 0; g < grids.size(); ++g)
            for (const auto& [a, ra] : rates)
                for (const auto& [b, rb] : rates) {
                    INFO(a << " against " << b << " on grid " << g);
                    const double ya = byMethod[a]->points[g].second, yb = byMethod[b]->points[g].second;
                    if (ra[g] > 1.01 * rb[g]) CHECK(ya < yb);
                    if (ra[g] > rb[g]) CHECK(ya <= yb);
                }
    }
}

TEST_CASE("CLI: bench --file-to-picture renders a PNG height map with bilinear and with embree", "[cli][bench]") {
    TempDir dir("bench-cli");
    const std::filesystem::path scratch = dir.path() / "tmp";
    std::filesystem::create_directories(scratch);
    const std::string json = (dir.path() / "bench.json").string();
    CommandResult r;
    {
        const TmpDirOverride tmp(scratch.string());
        r = runTerracast("bench --sizes 129 --threads 2 --repeat 1 --file-to-picture --paired-runs 1 --json '" + json + "'");
    }
    INFO(r.err);
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.find("file to picture") != std::string::npos);
    CHECK(r.out.find("total embree / bilinear") != std::string::npos);
    // The height map and the pictures went into a folder of their own, removed afterwards.
    CHECK(std::filesystem::is_empty(scratch));

    const JsonValue doc = parseJson(slurp(json));
    const JsonValue& f = doc["file_to_picture"];
    CHECK(f["dem"].string == "synthetic-129");
    CHECK(f["width"].number == 129);
    CHECK(f["cell_size_m"].number == 30);
    CHECK_FALSE(f["skipped"].boolean);
    CHECK(f["threads"].number == 2);
    CHECK(f["image_width"].number == 1024);
    CHECK(f["image_height"].number == 768);
    CHECK(finitePositive(f["height_map_bytes"]));
    CHECK(finitePositive(f["height_map_write_s"]));
    REQUIRE(f["methods"].array.size() == 2);
    CHECK(f["methods"][0]["name"].string == "bilinear");
    CHECK(f["methods"][1]["name"].string == "embree");
    for (const JsonValue& m : f["methods"].array) {
        INFO("method " << m["name"].string);
        CHECK_FALSE(m["skipped"].boolean);
        for (const char* key : {"load_s", "build_s", "render_s", "write_s", "total_s", "picture_bytes"}) {
            INFO(key);
            CHECK(finitePositive(m[key]));
        }
        // The pyramid is part of the load: the whole grid's for bilinear, Embree traces no pyramid but the grid
        // builds one as it is loaded all the same.
        CHECK(m["pyramid_s"].number > 0.0);
        CHECK(m["pyramid_s"].number <= m["load_s"].number);
        // The phases add up to the whole (the report keeps six significant digits of each).
        const double phases = m["load_s"].number + m["build_s"].number + m["render_s"].number + m["write_s"].number;
        CHECK(m["total_s"].number == Approx(phases).epsilon(1e-4));
        // Each picture read back at the size asked for.
        CHECK(m["picture_width"].number == 1024);
        CHECK(m["picture_height"].number == 768);
    }
    CHECK(f["total_ratio_embree_to_bilinear"].number ==
          Approx(f["methods"][1]["total_s"].number / f["methods"][0]["total_s"].number).epsilon(1e-4));
    // The exact patch and Embree's two triangles per cell draw nearly the same picture.
    REQUIRE(f["picture_mean_abs_diff"].isNumber());
    CHECK(f["picture_mean_abs_diff"].number >= 0.0);
    CHECK(f["picture_mean_abs_diff"].number < 3.0);

    // Whole processes against POV-Ray, where it is installed (it is not needed to build or test terracast).
    const JsonValue& w = f["whole_process"];
    if (terracast::findOnPath("povray").empty()) {
        CHECK_FALSE(w["ran"].boolean);
        CHECK(w["why"].string.find("POV-Ray is not installed") != std::string::npos);
        CHECK(r.out.find("whole processes against POV-Ray: not run") != std::string::npos);
    } else {
        REQUIRE(w["ran"].boolean);
        CHECK(w["povray_version"].string.rfind("POV-Ray 3.", 0) == 0);
        for (const char* program : {"terracast", "povray"}) {
            INFO(program);
            REQUIRE(w[program]["seconds"].array.size() == 1);
            CHECK(finitePositive(w[program]["median_s"]));
            CHECK(w[program]["best_s"].number == w[program]["median_s"].number);
        }
        CHECK(w["speedup_over_povray"].number ==
              Approx(w["povray"]["median_s"].number / w["terracast"]["median_s"].number).epsilon(1e-4));
        // POV-Ray's height_field, two triangles per cell, is the independent tessellation: the pixels whose
        // camera rays meet it are those where terracast's triangles surface is met, but for grazing edges.
        CHECK(w["silhouette_pixels"].number > 0.1 * 1024 * 768);
        CHECK(w["silhouette_mismatches"].number >= 0);
        CHECK(w["silhouette_mismatches"].number <= 1e-4 * w["silhouette_pixels"].number);
    }
    CHECK(std::filesystem::is_empty(scratch));
}

TEST_CASE("CLI: bench --povray takes a program, none, or refuses what is not one", "[cli][bench]") {
    TempDir dir("bench-povray");
    const std::string json = (dir.path() / "bench.json").string();
    auto r = runTerracast("bench --sizes 65 --methods bilinear --repeat 1 --file-to-picture --povray '" +
                          (dir.path() / "no-povray").string() + "' --json '" + json + "'");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("--povray: expected an executable") != std::string::npos);
    CHECK(r.err.find("no-povray") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(json));
    r = runTerracast("bench --sizes 65 --methods bilinear --repeat 1 --file-to-picture --povray none --json '" + json + "'");
    REQUIRE(r.exitCode == 0);
    const JsonValue doc = parseJson(slurp(json));
    CHECK_FALSE(doc["file_to_picture"]["whole_process"]["ran"].boolean);
}
