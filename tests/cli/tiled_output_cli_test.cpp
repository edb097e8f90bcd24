// Map products written tile by tile through the executable: a run interrupted by Ctrl-C or killed outright
// leaves no file at the output path and keeps its finished tiles beside it; --resume computes only the others
// and writes the same bytes as a run that was never stopped; --resume of another job is refused.
#include "support/run_command.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <csignal>
#include <filesystem>
#include <string>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kPuget = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";

size_t tilesIn(const fs::path& folder) {
    size_t n = 0;
    std::error_code ec;
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
        n += it->path().extension() == ".tif";
    return n;
}

}  // namespace

TEST_CASE("Tiled outputs: an interrupted or killed map job resumes to the same bytes", "[cli][tiles][heavy]") {
    TempDir dir("tiled-output");
    // 1025 x 1025 vertices: 3 x 3 output tiles, on one thread so that the job lasts a few tiles' time.
    const std::vector<std::string> job{"horizon", kPuget, "--azimuths", "0:360:360", "--threads", "1", "-o"};
    RunSettings settings;
    settings.workDir = dir.path();
    settings.timeoutS = 300.0;
    std::vector<std::string> args = job;
    args.push_back(dir.file("reference.tif"));
    const ArgsResult reference = runTerracastArgs(args, settings);
    INFO(reference.err);
    REQUIRE(reference.exitCode == 0);
    CHECK(reference.err.find("9 output tiles") != std::string::npos);
    const std::string expected = slurp(dir.file("reference.tif"));
    REQUIRE(expected.size() > 1000);

    const std::string out = dir.file("out.tif"), partial = out + ".partial";
    args.back() = out;
    for (const int signal : {SIGINT, SIGKILL}) {
        INFO("signal " << signal);
        fs::remove_all(partial);
        RunSettings stop = settings;
        stop.signal = signal;
        stop.interruptWhenExists = partial + "/tile-0-0.tif";  // the first tile is done
        const ArgsResult stopped = runTerracastArgs(args, stop);
        INFO(stopped.err);
        if (signal == SIGINT) {
            CHECK(stopped.exitCode == 130);
            CHECK(stopped.err.find("finished output tiles in '" + partial + "' (--resume continues") != std::string::npos);
        } else {
            CHECK(stopped.termSignal == SIGKILL);
        }
        CHECK_FALSE(fs::exists(out));
        const size_t kept = tilesIn(partial);
        CHECK(kept >= 1);
        CHECK(kept < 9);

        std::vector<std::string> resume = args;
        resume.push_back("--resume");
        const ArgsResult resumed = runTerracastArgs(resume, settings);
        INFO(resumed.err);
        REQUIRE(resumed.exitCode == 0);
        CHECK(resumed.err.find("--resume: " + std::to_string(kept) + " of 9 output tiles kept") != std::string::npos);
        CHECK(resumed.err.find("of which " + std::to_string(kept) + " resumed") != std::string::npos);
        CHECK(slurp(out) == expected);
        CHECK_FALSE(fs::exists(partial));
        fs::remove(out);
    }

    // The tiles of another job are not resumed; a fresh run removes them.
    RunSettings stop = settings;
    stop.interruptWhenExists = partial + "/tile-0-0.tif";
    REQUIRE(runTerracastArgs(args, stop).exitCode == 130);
    std::vector<std::string> other{"horizon", kPuget, "--azimuths", "0:360:180", "--threads", "1", "-o", out, "--resume"};
    const ArgsResult refused = runTerracastArgs(other, settings);
    CHECK(refused.exitCode == 2);
    CHECK(refused.err.find("--resume: the tiles in") != std::string::npos);
    CHECK(refused.err.find("belong to another job") != std::string::npos);
    CHECK(tilesIn(partial) >= 1);
    other.pop_back();
    const ArgsResult fresh = runTerracastArgs(other, settings);
    INFO(fresh.err);
    CHECK(fresh.exitCode == 0);
    CHECK(fresh.err.find("removed") != std::string::npos);
    CHECK_FALSE(fs::exists(partial));
}
