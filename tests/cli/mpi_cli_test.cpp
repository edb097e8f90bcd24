// Map products and renders over the ranks of an MPI launch (Open MPI's mpirun, as root with the flags it needs
// there): two ranks write the same bytes as one process; a rank that fails ends every rank, exit non-zero, no
// output; the commands that do not share their work refuse to run under mpirun. Skipped in the sanitizer builds: Open MPI's
// own allocations are not theirs to judge.
#include "support/run_command.h"
#include "support/sanitizers.h"
#include "support/temp_dir.h"

#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
const std::string kHelens = kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
const std::string kPuget = kSamples + "puget-sound-usgs-1025x1025-16bit-heightmap.png";

// Runs `mpirun <launch>` in `dir` through the shell; the exit code and both outputs together.
CommandResult mpirun(const TempDir& dir, const std::string& launch) {
    const std::string log = dir.file("mpirun.log");
    const std::string cmd = "cd '" + dir.path().string() + "' && mpirun --allow-run-as-root --oversubscribe " + launch +
                            " >'" + log + "' 2>&1";
    const int status = std::system(cmd.c_str());
    CommandResult r;
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.err = slurp(log);
    return r;
}

std::string cli() { return std::string("'") + TERRACAST_CLI_PATH + "'"; }

// The count of rays (walks, sight lines) in a map command's summary: "in 0.25 s, 1050625 shadow walks".
std::string rayCount(const std::string& err) {
    const size_t at = err.find(" s, ");
    if (at == std::string::npos) return "";
    const size_t end = err.find(' ', at + 4);
    return err.substr(at + 4, end - at - 4);
}

}  // namespace

TEST_CASE("MPI: two ranks write a map product's bytes as one process does", "[cli][mpi]") {
    if (kSanitizedBuild) return;
    TempDir dir("mpi");
    const struct {
        std::string args;
        std::string out;
    } jobs[] = {
        {"horizon '" + kPuget + "' --azimuths 0:360:120 --threads 1", "horizon.tif"},
        {"shadow '" + kHelens + "' --sun 135,20 --threads 1 --tile-cache 500K", "shadow.tif"},
        {"viewshed '" + kHelens + "' --observer 562000,5115000 --threads 1", "viewshed.tif"},
    };
    for (const auto& job : jobs) {
        INFO(job.args);
        const CommandResult one = runTerracast(job.args + " -o '" + dir.file("one-" + job.out) + "'");
        INFO(one.err);
        REQUIRE(one.exitCode == 0);
        const CommandResult two = mpirun(dir, "-n 2 " + cli() + " " + job.args + " -o two-" + job.out);
        INFO(two.err);
        REQUIRE(two.exitCode == 0);
        CHECK(two.err.find("2 ranks share") != std::string::npos);
        // Each tile traced once over both ranks: the summed count is one process's.
        CHECK_FALSE(rayCount(one.err).empty());
        CHECK(rayCount(two.err) == rayCount(one.err));
        const std::string a = slurp(dir.file("one-" + job.out)), b = slurp(dir.file("two-" + job.out));
        CHECK(a.size() > 1000);
        CHECK(a == b);
        CHECK_FALSE(fs::exists(dir.file("two-" + job.out + ".partial")));
    }
}

TEST_CASE("MPI: two ranks render a picture's bytes as one process does", "[cli][mpi]") {
    if (kSanitizedBuild) return;
    TempDir dir("mpi-render");
    // Sky-visibility rays and shadows on: every pixel's own random directions, from a tiled DEM.
    const std::string args = "render '" + kHelens + "' --size 300x200 --sky-samples 4 --threads 1 --tile-cache 500K";
    const CommandResult one = runTerracast(args + " -o '" + dir.file("one.png") + "'");
    INFO(one.err);
    REQUIRE(one.exitCode == 0);
    const CommandResult two = mpirun(dir, "-n 2 " + cli() + " " + args + " -o two.png");
    INFO(two.err);
    REQUIRE(two.exitCode == 0);
    const std::string a = slurp(dir.file("one.png")), b = slurp(dir.file("two.png"));
    CHECK(a.size() > 1000);
    CHECK(a == b);
    // The summary's ray counts are summed over the ranks: one process's.
    const auto rays = [](const std::string& err) {
        const size_t at = err.find(" s: ");
        return at == std::string::npos ? std::string() : err.substr(at, err.find("rays, ") - at);
    };
    CHECK_FALSE(rays(one.err).empty());
    CHECK(rays(two.err) == rays(one.err));
}

TEST_CASE("MPI: two ranks sharing a tile store they fill together render one process's bytes", "[cli][mpi]") {
    if (kSanitizedBuild) return;
    TempDir dir("mpi-store");
    const std::string dem = dir.file("helens.tif");
    fs::copy_file(kHelens, dem);
    const std::string args = "render '" + dem + "' --size 200x150 --threads 1 --tile-cache 500K --tile-store";
    const CommandResult one = runTerracast("render '" + kHelens + "' --size 200x150 --threads 1 -o '" +
                                           dir.file("one.png") + "'");
    REQUIRE(one.exitCode == 0);
    // Twice: the ranks make the store and write their tiles into it at once, then both read from it.
    for (const std::string out : {"fill.png", "read.png"}) {
        const CommandResult two = mpirun(dir, "-n 2 " + cli() + " " + args + " -o " + out);
        INFO(two.err);
        REQUIRE(two.exitCode == 0);
        CHECK(slurp(dir.file(out)) == slurp(dir.file("one.png")));
        if (out == "read.png") CHECK_THAT(two.err, Catch::Contains(" written to it)"));
    }
    CHECK(fs::exists(dem + ".terracast-tiles"));
}

TEST_CASE("MPI: ranks hold a DEM that fits as tiles when the job allows, and write one process's bytes",
          "[cli][mpi]") {
    if (kSanitizedBuild) return;
    TempDir dir("mpi-tiles");
    // One process holds these DEMs whole; two ranks each read only the tiles their part reaches, except where
    // the job needs every vertex (Embree's meshes) or GDAL stores the DEM in strips (.hgt).
    const struct {
        std::string args;
        std::string out;
        bool tiles;
    } jobs[] = {
        {"render '" + kHelens + "' --size 240x160 --sky-samples 2 --threads 1", "render.png", true},
        {"render '" + kHelens + "' --size 240x160 --sky-samples 0 --threads 1 --exaggeration 2", "tall.png", true},
        {"viewshed '" + kHelens + "' --observer 562000,5115000 --curvature-coeff 0 --threads 1", "flat.tif", true},
        {"viewshed '" + kHelens + "' --observer 562000,5115000 --threads 1", "curved.tif", true},
        {"svf '" + kHelens + "' --directions 8 --max-distance 300 --threads 1", "svf.tif", true},
        {"render '" + kHelens + "' --view map --sky-samples 2 --threads 1", "map.tif", true},
        {"render '" + kHelens + "' --size 160x120 --sky-samples 0 --threads 1 --method embree", "embree.png", false},
        {"shadow '" + kHelens + "' --sun-time 2026-06-21T12:00Z/2026-06-21T20:00Z/4h --threads 1", "times.tif", true},
        {"insolation '" + kHelens + "' --date 2026-03-01 --step 2h --threads 1", "insolation.tif", true},
        // .hgt is stored in strips of whole rows: read whole, a band of rows per rank.
        {"shadow '" + kSamples + "N44W072.srtm3-white-mountains-nh.hgt' --sun 135,20 --threads 1", "hgt.tif", false},
    };
    for (const auto& job : jobs) {
        INFO(job.args);
        const CommandResult one = runTerracast(job.args + " -o '" + dir.file("one-" + job.out) + "'");
        INFO(one.err);
        REQUIRE(one.exitCode == 0);
        CHECK(one.err.find("tiles: ") == std::string::npos);
        const CommandResult two = mpirun(dir, "-n 2 " + cli() + " " + job.args + " -o two-" + job.out);
        INFO(two.err);
        REQUIRE(two.exitCode == 0);
        CHECK((two.err.find("tiles: ") != std::string::npos) == job.tiles);
        const std::string a = slurp(dir.file("one-" + job.out)), b = slurp(dir.file("two-" + job.out));
        CHECK(a.size() > 1000);
        CHECK(a == b);
    }
}

TEST_CASE("MPI: a rank that fails ends every rank without an output", "[cli][mpi]") {
    if (kSanitizedBuild) return;
    TempDir dir("mpi-fail");
    // Rank 1 cannot read its DEM (a node without the data, say); rank 0 could.
    const CommandResult r = mpirun(dir, "-n 1 " + cli() + " horizon '" + kPuget + "' --azimuths 0:360:90 -o out.tif : -n 1 " +
                                            cli() + " horizon '" + dir.file("missing.tif") + "' --azimuths 0:360:90 -o out.tif");
    INFO(r.err);
    CHECK(r.exitCode != 0);
    CHECK(r.err.find("rank 1 of 2: error: " + dir.file("missing.tif")) != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("out.tif")));
    // Commands that would each write the whole output are refused under mpirun.
    const CommandResult scene =
        mpirun(dir, "-n 2 " + cli() + " scene '" + kSamples + "lake.toml' -o s.png --size 32x24");
    CHECK(scene.exitCode == 2);
    CHECK(scene.err.find("scene: runs as one process; under mpirun only") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("s.png")));
    const CommandResult map = mpirun(dir, "-n 2 " + cli() + " render '" + kHelens + "' -o m.png --view map");
    CHECK(map.exitCode == 2);
    CHECK(map.err.find("render --view map: runs as one process as a PNG") != std::string::npos);
    CHECK_FALSE(fs::exists(dir.file("m.png")));
}
