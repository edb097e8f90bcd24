// Output-path checks: an output may never name an input, however it is spelt, and a bad path is refused before
// any work.
#include "loaders/output_paths.h"

#include "support/temp_dir.h"
#include "tracer/core/errors.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>

using namespace terracast;
using terracast::testing::TempDir;
namespace fs = std::filesystem;

TEST_CASE("Output paths: the input is refused under any spelling", "[loaders]") {
    const TempDir dir("output-paths");
    const std::string input = dir.file("dem.png");
    std::ofstream(input) << "not really a PNG";
    fs::create_directories(dir.path() / "sub");
    fs::create_symlink(input, dir.file("link.png"));
    fs::create_hard_link(input, dir.file("hard.png"));
    for (const std::string& spelling : {input, dir.file("sub/../dem.png"), dir.file("./dem.png"), dir.file("link.png"),
                                        dir.file("hard.png")}) {
        INFO(spelling);
        CHECK_THROWS_AS(checkNotInput(spelling, input, "output path"), InputError);
        CHECK_THROWS_AS(checkOutputPath(spelling, input), InputError);
        CHECK_THROWS_AS(checkReportPath(spelling, input), InputError);
    }
    // Another file, or one that does not exist yet, is fine.
    std::ofstream(dir.file("other.png")) << "x";
    CHECK_NOTHROW(checkNotInput(dir.file("other.png"), input, "output path"));
    CHECK_NOTHROW(checkOutputPath(dir.file("new.png"), input));
    CHECK_NOTHROW(checkReportPath(dir.file("report.json"), input));
}

TEST_CASE("Output paths: format and folder are checked before any work", "[loaders]") {
    const TempDir dir("output-paths");
    const std::string input = dir.file("dem.tif");
    try {
        checkOutputPath(dir.file("out.jpg"), input, {".tif", ".tiff"});
        FAIL("a .jpg output was accepted");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) == dir.file("out.jpg") + ": unsupported output format '.jpg' (expected .tif or .tiff)");
    }
    CHECK_NOTHROW(checkOutputPath(dir.file("OUT.TIF"), input, {".tif", ".tiff"}));
    try {
        checkOutputFolder(dir.file("missing/out.json"));
        FAIL("an output in a missing folder was accepted");
    } catch (const InputError& e) {
        CHECK(std::string(e.what()) ==
              dir.file("missing/out.json") + ": output folder '" + dir.file("missing") + "' does not exist");
    }
    CHECK(dir.entryCount() == 0);  // the checks leave nothing behind
}
