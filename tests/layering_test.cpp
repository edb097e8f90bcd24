// The include graph of docs/architecture.md, checked over every source file of the tree: each folder includes
// only the folders below it, heightfield/ and tracer/sampling/ nothing but GLM and the standard library, the
// file-format libraries only the loaders, Embree only the terrain surface's sources, and nothing cli/. CMake's
// link lists cannot see what a header-only file includes; this can.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// What the files under `folder` (or the one file named) may include from the project; the first rule whose
// folder starts a file's path applies, so the more specific rules come first.
struct Rule {
    std::string folder;
    std::vector<std::string> allowed;  // project include prefixes; "*" = any
    bool standardAndGlmOnly = false;   // angle-bracket includes limited to GLM and the standard library
};

const std::vector<Rule>& rules() {
    static const std::vector<std::string> description{"tracer/scene/scene_description.h",
                                                      "tracer/scene/scene_assets.h"};
    static const std::vector<Rule> r = [] {
        const auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
            a.insert(a.end(), b.begin(), b.end());
            return a;
        };
        const std::vector<std::string> base{"heightfield/", "tracer/core/", "tracer/sampling/", "tracer/camera/",
                                            "tracer/sky/"};
        return std::vector<Rule>{
            {"tracer/scene/scene_description.h", with(base, description)},
            {"tracer/scene/scene_assets.h", with(base, description)},
            {"tracer/scene/scene_assets.cpp", with(base, description)},
            {"heightfield/", {"heightfield/"}, true},
            {"tracer/core/", {"tracer/core/", "heightfield/"}},
            {"tracer/sampling/", {"tracer/sampling/"}, true},
            {"tracer/camera/", {"tracer/camera/", "heightfield/", "tracer/core/", "tracer/sampling/"}},
            {"tracer/sky/", {"tracer/sky/", "tracer/sampling/", "tracer/core/"}},
            {"loaders/", with(with(base, description), {"loaders/"})},
            {"tracer/terrain/", with(with(base, description), {"tracer/terrain/", "loaders/"})},
            {"tracer/scene/", with(base, {"tracer/scene/", "tracer/terrain/", "loaders/"})},
            {"tracer/measure/", with(base, {"tracer/measure/", "tracer/terrain/", "loaders/"})},
            {"cli/", with(base, {"tracer/", "loaders/", "cli/"})},
            {"python/", with(base, {"tracer/", "loaders/", "python/"})},
            {"bench/", {"*"}},
            {"examples/", {"*"}},
            {"fuzz/", {"*"}},
            {"tests/", {"*"}},
        };
    }();
    return r;
}

// Third-party headers (by prefix) and the only folders (or files) that may include them.
struct Confinement {
    std::string header;
    std::vector<std::string> places;
};

const std::vector<Confinement>& confinements() {
    static const std::vector<Confinement> c{
        {"gdal", {"loaders/", "tests/"}},          {"cpl_", {"loaders/", "tests/"}},
        {"ogr_", {"loaders/", "tests/"}},          {"OpenImageIO/", {"loaders/", "tests/"}},
        {"toml++/", {"loaders/", "tests/"}},       {"embree3/", {"tracer/terrain/embree_terrain.cpp", "tests/"}},
        {"CLI/", {"cli/"}},                        {"catch2/", {"tests/"}},
        {"benchmark/", {"bench/"}},               {"pybind11/", {"python/"}},
    };
    return c;
}

bool startsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// The layering errors of one file, given its path relative to the source tree and its text: one line each,
// "path:line: includes X (...)".
std::vector<std::string> layeringViolations(const std::string& path, const std::string& text) {
    std::vector<std::string> errors;
    const auto rule = std::find_if(rules().begin(), rules().end(), [&](const Rule& r) { return startsWith(path, r.folder); });
    if (rule == rules().end()) return errors;
    static const std::regex include(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
    std::istringstream in(text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        std::smatch m;
        if (!std::regex_search(line, m, include)) continue;
        const bool quoted = m[1] == "\"";
        const std::string header = m[2];
        const std::string where = path + ":" + std::to_string(number) + ": includes " + header;
        if (startsWith(header, "cli/") && !startsWith(path, "cli/")) errors.push_back(where + " (nothing includes cli/)");
        for (const auto& c : confinements())
            if (!quoted && startsWith(header, c.header) &&
                std::none_of(c.places.begin(), c.places.end(), [&](const std::string& p) { return startsWith(path, p); }))
                errors.push_back(where + " (only " + c.places.front() + " may)");
        if (quoted) {
            const bool ok = std::any_of(rule->allowed.begin(), rule->allowed.end(), [&](const std::string& a) {
                return a == "*" || startsWith(header, a);
            });
            if (!ok) errors.push_back(where + " (" + rule->folder + " may include only the folders below it)");
        } else if (rule->standardAndGlmOnly && !startsWith(header, "glm/") &&
                   (header.find('/') != std::string::npos || header.find('.') != std::string::npos)) {
            errors.push_back(where + " (" + rule->folder + " takes only GLM and the standard library)");
        }
    }
    return errors;
}

}  // namespace

TEST_CASE("Layering: every include of the tree follows the allowed graph", "[layering]") {
    const fs::path root(TERRACAST_SOURCE_DIR);
    std::vector<std::string> errors;
    size_t files = 0;
    for (const char* top : {"heightfield", "tracer", "loaders", "cli", "python", "bench", "fuzz", "tests", "examples"})
        for (const auto& entry : fs::recursive_directory_iterator(root / top)) {
            const std::string ext = entry.path().extension().string();
            if (!entry.is_regular_file() || (ext != ".h" && ext != ".cpp")) continue;
            std::ifstream in(entry.path());
            std::stringstream text;
            text << in.rdbuf();
            const auto found = layeringViolations(fs::relative(entry.path(), root).generic_string(), text.str());
            errors.insert(errors.end(), found.begin(), found.end());
            ++files;
        }
    CHECK(files > 100);
    std::string report;
    for (const auto& e : errors) report += e + "\n";
    INFO(report);
    CHECK(errors.empty());
}

TEST_CASE("Layering: the check names each kind of crossing", "[layering]") {
    // Upwards in the tracer: the sky reaching into the terrain, the loaders into the renderers.
    CHECK(layeringViolations("tracer/sky/sky.cpp", "#include \"tracer/terrain/surface.h\"\n").size() == 1);
    CHECK(layeringViolations("loaders/scene_assets.h", "#include \"tracer/scene/scene.h\"\n").size() == 1);
    CHECK(layeringViolations("loaders/scene_assets.h", "#include \"tracer/scene/scene_description.h\"\n").empty());
    // The core of the core: heightfield/ and sampling take nothing of the project above them, and no library but GLM.
    CHECK(layeringViolations("heightfield/dda.h", "#include \"tracer/core/angles.h\"\n").size() == 1);
    CHECK(layeringViolations("heightfield/dda.h", "#include <tbb/parallel_for.h>\n").size() == 1);
    CHECK(layeringViolations("heightfield/dda.h", "#include <glm/glm.hpp>\n#include <vector>\n").empty());
    CHECK(layeringViolations("tracer/sampling/film.h", "  #  include \"tracer/core/angles.h\"\n").size() == 1);
    // Third-party libraries stay where their targets link them; nothing but cli/ includes cli/.
    CHECK(layeringViolations("tracer/terrain/surface.h", "#include <embree3/rtcore.h>\n").size() == 1);
    CHECK(layeringViolations("tracer/terrain/embree_terrain.cpp", "#include <embree3/rtcore.h>\n").empty());
    CHECK(layeringViolations("tracer/measure/bench.cpp", "#include <gdal.h>\n").size() == 1);
    CHECK(layeringViolations("tests/cli/cli_test.cpp", "#include \"cli/cli_support.h\"\n").size() == 1);
    // Messages name the file and line.
    const auto e = layeringViolations("tracer/sky/sky.cpp", "// two\n#include \"tracer/scene/scene.h\"\n");
    REQUIRE(e.size() == 1);
    CHECK(e[0].rfind("tracer/sky/sky.cpp:2: includes tracer/scene/scene.h", 0) == 0);
}
