// Replays every input kept under tests/fuzz/regressions/<target>/ (inputs that once broke a fuzz target)
// and every seed under tests/fuzz/<target>/ through the fuzz target bodies, so a fixed finding stays fixed.
#include "fuzz/fuzz_targets.h"
#include "support/run_command.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>
#include <string>

namespace fs = std::filesystem;

namespace {

const fs::path kFuzzDir = fs::path(TERRACAST_SOURCE_DIR) / "tests" / "fuzz";

// Runs `body` on every file in `folder` (none is fine) and returns how many it ran.
int replay(const fs::path& folder, const std::function<void(const uint8_t*, size_t)>& body) {
    if (!fs::is_directory(folder)) return 0;
    int count = 0;
    for (const auto& entry : fs::directory_iterator(folder)) {
        if (!entry.is_regular_file()) continue;
        const std::string bytes = terracast::testing::slurp(entry.path());
        INFO(entry.path().string());
        CHECK_NOTHROW(body(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size()));
        ++count;
    }
    return count;
}

}  // namespace

TEST_CASE("Fuzz seeds and regressions: scene-file parser", "[fuzz]") {
    CHECK(replay(kFuzzDir / "scene_file", terracast::fuzz::sceneFile) > 0);
    replay(kFuzzDir / "regressions" / "scene_file", terracast::fuzz::sceneFile);
}

TEST_CASE("Fuzz seeds and regressions: DEM loader", "[fuzz]") {
    CHECK(replay(kFuzzDir / "dem_loader", terracast::fuzz::demLoader) > 0);
    replay(kFuzzDir / "regressions" / "dem_loader", terracast::fuzz::demLoader);
}

TEST_CASE("Fuzz seeds and regressions: bilinear cell intersector", "[fuzz]") {
    CHECK(replay(kFuzzDir / "cell_intersector", terracast::fuzz::cellIntersector) > 0);
    replay(kFuzzDir / "regressions" / "cell_intersector", terracast::fuzz::cellIntersector);
}
