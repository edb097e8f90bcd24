// Whole processes timed from outside (bench --file-to-picture): a child's peak memory is its own, however
// large the process that starts it, and its exit status and output come through.
#include "tracer/measure/whole_process.h"

#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

using namespace terracast;
using namespace terracast::testing;

TEST_CASE("Whole processes: a child's peak memory is its own, not its parent's", "[measure]") {
    const std::string python = findOnPath("python3");
    if (python.empty()) {
        WARN("no python3 on PATH: skipped");
        return;
    }
    TempDir dir("whole-process");
    const std::string log = (dir.path() / "log.txt").string();
    // This process holds 300 MiB, touched; the child fills 120 MiB of its own. The kernel's count for a
    // direct child (wait4) carries the spawning process's peak across exec: it would read over 300 MiB.
    const size_t held = size_t(300) << 20;
    std::unique_ptr<char[]> big(new char[held]);
    std::memset(big.get(), 1, held);
    const ProcessRun run = runTimedProcess({python, "-c", "b = b'x' * (120 * 2**20); print(len(b))"}, dir.path().string(), log);
    CHECK(run.exitCode == 0);
    CHECK(run.seconds > 0.0);
    if (std::isnan(run.peakBytes)) {
        WARN("GNU time (/usr/bin/time) is not installed: the peak is unknown");
    } else {
        const double mib = run.peakBytes / double(1 << 20);
        INFO("child's peak: " << mib << " MiB");
        CHECK(mib > 120.0);
        CHECK(mib < 200.0);  // Python itself takes about 10 MiB
    }
    volatile char keep = big[held - 1];
    (void)keep;
    std::ifstream in(log);
    std::stringstream text;
    text << in.rdbuf();
    CHECK(text.str().find(std::to_string(120 << 20)) != std::string::npos);  // its output went to the log

    const ProcessRun failed = runTimedProcess({python, "-c", "import sys; sys.exit(7)"}, dir.path().string(), log);
    CHECK(failed.exitCode == 7);
    CHECK_THROWS(runTimedProcess({(dir.path() / "no-such-program").string()}, dir.path().string(), log));
}

TEST_CASE("Whole processes: executables are found on PATH by name", "[measure]") {
    CHECK(findOnPath("sh").find("/sh") != std::string::npos);
    CHECK(findOnPath("no-such-program-anywhere").empty());
    CHECK_FALSE(selfExecutablePath().empty());
}
