// The memory guard, measured: each command runs once without a limit, and its peak resident memory P is read
// from the kernel (getrusage of the child). Run again with --max-memory at 90 % of P, it must refuse before
// allocating (exit 2, naming --max-memory, its own peak far below the limit): a run that went ahead would
// have crossed the limit, which means the estimate was too low. A refusal may cost no more than reading a
// PNG's header does (`info`: the libraries and the image codec, about 140 MiB), as the guard can only count
// the codec once it is loaded. Jobs are sized so that what they allocate dominates that fixed memory.
#include "support/run_command.h"
#include "support/sanitizers.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";

struct Job {
    std::string name;
    std::vector<std::string> args;
};

void checkGuard(const Job& job, double fixedBytes) {
    TempDir dir("memory-guard");
    RunSettings settings;
    settings.workDir = dir.path();
    settings.timeoutS = 120.0;
    const ArgsResult free = runTerracastArgs(job.args, settings);
    INFO(job.name << "\nunlimited run: " << free.err);
    REQUIRE(free.exitCode == 0);
    const double limit = 0.9 * free.peakBytes;
    std::vector<std::string> limited = job.args;
    limited.push_back("--max-memory");
    limited.push_back(std::to_string(int64_t(limit)));
    for (const auto& e : fs::directory_iterator(dir.path())) fs::remove_all(e.path());
    const ArgsResult guarded = runTerracastArgs(limited, settings);
    INFO("peak " << free.peakBytes / 1048576.0 << " MiB unlimited; limited to " << limit / 1048576.0
                 << " MiB: exit " << guarded.exitCode << ", peak " << guarded.peakBytes / 1048576.0 << " MiB\n"
                 << guarded.err);
    CHECK(guarded.exitCode == 2);
    CHECK(guarded.err.find("--max-memory") != std::string::npos);
    CHECK(guarded.peakBytes < std::max(limit, fixedBytes));
    CHECK(dir.entryCount() == 0);
}

}  // namespace

TEST_CASE("Memory guard: every command refuses a limit below what it would use", "[cli][memory]") {
    if (!kResidentMemoryIsMeaningful) return;  // the plain build's run of the suite measures it
    const std::string helens = kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
    const std::string puget = kSamples + "puget-sound-usgs-1025x1025-16bit-heightmap.png";
    const std::vector<Job> jobs = {
        {"render, large film", {"render", helens, "-o", "out.png", "--size", "3000x2000", "--sky-samples", "0"}},
        {"render, Embree mesh", {"render", puget, "-o", "out.png", "--size", "64x48", "--method", "embree"}},
        {"render, map view", {"render", helens, "-o", "out.png", "--view", "map", "--scale", "6", "--sky-samples", "0"}},
        {"scene, large film", {"scene", kSamples + "lake.toml", "-o", "out.png", "--size", "2000x1500"}},
        {"shadow", {"shadow", puget, "-o", "out.tif", "--threads", "2"}},
        {"horizon, 8 azimuths", {"horizon", puget, "-o", "out.tif", "--azimuths", "0:360:45", "--threads", "2"}},
        {"svf", {"svf", puget, "-o", "out.tif", "--directions", "4", "--max-distance", "100", "--threads", "2"}},
        {"viewshed", {"viewshed", puget, "-o", "out.tif", "--observer", "500,500", "--threads", "2"}},
        {"compare", {"compare", puget, "--size", "64x48", "--methods", "bilinear,embree"}},
        {"accuracy", {"accuracy", puget, "--rays", "1000000"}},
    };
    const ArgsResult header = runTerracastArgs({"info", puget});
    REQUIRE(header.exitCode == 0);
    const double fixedBytes = 1.02 * header.peakBytes;
    for (const Job& job : jobs) checkGuard(job, fixedBytes);
}
