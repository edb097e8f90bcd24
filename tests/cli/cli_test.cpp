// The command line: exit codes, one-line errors, and the outputs of info and render.
#include "loaders/image_io.h"
#include "support/run_command.h"
#include "support/sanitizers.h"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <vector>

using namespace terracast::testing;
namespace fs = std::filesystem;

namespace {

// The first match of `pattern` in `text` and its groups; empty when there is none.
std::vector<std::string> firstMatch(const std::string& text, const std::string& pattern) {
    std::smatch m;
    if (!std::regex_search(text, m, std::regex(pattern))) return {};
    return {m.begin(), m.end()};
}

// "38.3 MiB" (as the CLI prints sizes) in MiB.
double mebibytes(const std::string& text) {
    const double value = std::stod(text);
    if (text.find("GiB") != std::string::npos) return value * 1024.0;
    if (text.find("KiB") != std::string::npos) return value / 1024.0;
    return value;
}
const std::string kSamples = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/";
const std::string kStHelens = kSamples + "usgs-dem-mt-st-helens-utm10n-nad27-int16-nodata.tif";
const std::string kWhiteMountains = kSamples + "N44W072.srtm3-white-mountains-nh.hgt";

fs::path tempDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("terracast-cli-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}
}  // namespace

TEST_CASE("CLI: a missing DEM exits 2 with one line and writes nothing", "[cli]") {
    const fs::path dir = tempDir("missing");
    const auto r = runTerracast("render '" + (dir / "nope.tif").string() + "' -o '" + (dir / "out.png").string() + "'");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err == "terracast: error: " + (dir / "nope.tif").string() + ": no such file\n");
    CHECK_FALSE(fs::exists(dir / "out.png"));
    CHECK(fs::is_empty(dir));
    fs::remove_all(dir);
}

TEST_CASE("CLI: a text file passed as a DEM exits 2 with one line", "[cli]") {
    const fs::path dir = tempDir("text");
    std::ofstream(dir / "notes.txt") << "this is not an elevation model\n";
    const auto r = runTerracast("render '" + (dir / "notes.txt").string() + "' -o '" + (dir / "out.png").string() + "'");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err == "terracast: error: " + (dir / "notes.txt").string() + ": not a raster GDAL can read\n");
    CHECK_FALSE(fs::exists(dir / "out.png"));
    const auto i = runTerracast("info '" + (dir / "notes.txt").string() + "'");
    CHECK(i.exitCode == 2);
    CHECK(lineCount(i.err) == 1);
    fs::remove_all(dir);
}

TEST_CASE("CLI: an unknown option or bad value exits 2 with one line", "[cli]") {
    auto r = runTerracast("render '" + kStHelens + "' -o /tmp/x.png --no-such-option");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err.find("no-such-option") != std::string::npos);
    r = runTerracast("render '" + kStHelens + "' -o /tmp/x.png --size 12by7");
    CHECK(r.exitCode == 2);
    CHECK(lineCount(r.err) == 1);
    r = runTerracast("render '" + kStHelens + "' -o /tmp/x.png --method cubic");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("cubic") != std::string::npos);
    r = runTerracast("render '" + kStHelens + "' -o /tmp/x.gif");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find(".gif") != std::string::npos);
    r = runTerracast("");
    CHECK(r.exitCode == 2);
}

TEST_CASE("CLI: info reports size, CRS, cell size, heights and nodata", "[cli]") {
    const auto r = runTerracast("info '" + kStHelens + "'");
    REQUIRE(r.exitCode == 0);
    CHECK(r.out.find("327 x 468") != std::string::npos);
    CHECK(r.out.find("UTM zone 10N") != std::string::npos);
    CHECK(r.out.find("30.000 x 30.000 m") != std::string::npos);
    CHECK(r.out.find("682.00 .. 2543.00 m") != std::string::npos);
    CHECK(r.out.find("2.71%") != std::string::npos);  // 100 - 97.29 % valid, as gdalinfo -stats reports
}

TEST_CASE("CLI: render writes a PNG of the requested size and a one-line summary", "[cli]") {
    const fs::path dir = tempDir("render");
    const fs::path out = dir / "view.png";
    const auto r = runTerracast("render '" + kStHelens + "' -o '" + out.string() + "' --size 96x64 --threads 1");
    REQUIRE(r.exitCode == 0);
    CHECK(lineCount(r.err) == 1);
    CHECK(r.err.find("primary") != std::string::npos);
    CHECK(r.err.find("shadow") != std::string::npos);
    const auto img = terracast::readImage(out.string());
    CHECK(img.width == 96);
    CHECK(img.height == 64);
    // Only the output remains in the folder: no temporary file left behind.
    int files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    CHECK(files == 1);
    fs::remove_all(dir);
}

TEST_CASE("CLI: render --verbose tells each phase's seconds and splits the render's thread time", "[cli]") {
    const fs::path dir = tempDir("verbose");
    const std::string out = (dir / "view.png").string();
    struct Phases {
        double read, grid, pyramid, surface, trace, sky, camera, shadow, skyRays, shading, write, total;
    };
    const auto run = [&](int skySamples) {
        // 320 x 240: the shadow rays take a few milliseconds, so that one wait on a busy machine (a test running
        // beside this one) does not outweigh them.
        const auto r = runTerracast(fmt::format("render '{}' -o '{}' --size 320x240 --threads 2 --sky-samples {} --verbose",
                                                kWhiteMountains, out, skySamples));
        REQUIRE(r.exitCode == 0);
        CHECK(lineCount(r.err) == 2);  // the summary and the phases
        const std::vector<std::string> m = firstMatch(
            r.err, "phases: read and decode ([0-9.]+) s, grid ([0-9.]+) s, pyramid ([0-9.]+) s, surface ([0-9.]+) s, "
                   "trace and shade ([0-9.]+) s \\(sky tables ([0-9.]+) s; the work tiles' thread time: camera rays "
                   "([0-9.]+) s [0-9]+ %, shadow rays ([0-9.]+) s [0-9]+ %, sky-visibility rays ([0-9.]+) s [0-9]+ %, "
                   "shading ([0-9.]+) s [0-9]+ %\\), write ([0-9.]+) s; total ([0-9.]+) s");
        REQUIRE(m.size() == 13);
        Phases p{};
        double* fields[] = {&p.read,   &p.grid,    &p.pyramid, &p.surface, &p.trace, &p.sky,  &p.camera,
                            &p.shadow, &p.skyRays, &p.shading, &p.write,   &p.total};
        for (size_t k = 0; k < 12; ++k) *fields[k] = std::stod(m[k + 1]);
        return p;
    };
    // Each twice, keeping the run whose secondary rays took least: a run's first rays can wait on the machine.
    const auto best = [&](int skySamples) {
        const Phases a = run(skySamples), b = run(skySamples);
        return a.shadow + a.skyRays <= b.shadow + b.skyRays ? a : b;
    };
    const Phases few = best(0), many = best(16);
    for (const Phases& p : {few, many}) {
        // The phases follow one another within the whole (the rest: checks and setting the view).
        const double sum = p.read + p.grid + p.pyramid + p.surface + p.trace + p.write;
        CHECK(sum <= p.total + 0.002);
        CHECK(sum >= 0.8 * p.total - 0.002);
        CHECK(p.pyramid > 0.0);
        // Making the grid (codes, validity, height range) is a part of the load of its own.
        CHECK(p.grid > 0.0);
        CHECK(p.read > 0.0);
        // Two threads' time over the work tiles (the render less the sky's tables): at most twice their seconds,
        // and more than half of them.
        const double threadTime = p.camera + p.shadow + p.skyRays + p.shading;
        CHECK(p.sky < p.trace);
        CHECK(threadTime <= 2.0 * (p.trace - p.sky) + 0.002);
        CHECK(threadTime >= 0.5 * (p.trace - p.sky));
        CHECK(p.camera > 0.0);
        CHECK(p.shading > 0.0);
        CHECK(p.shadow > 0.0);
    }
    // No sky-visibility ray without sky samples; sixteen per hit take several times the one shadow ray's time.
    CHECK(few.skyRays == 0.0);
    CHECK(many.skyRays > 4.0 * many.shadow);
    CHECK(many.skyRays > 4.0 * few.shadow);
    // Without --verbose, the summary alone.
    const auto quietRun = runTerracast("render '" + kStHelens + "' -o '" + out + "' --size 64x48 --threads 2");
    CHECK(lineCount(quietRun.err) == 1);
    CHECK(quietRun.err.find("phases:") == std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("CLI: render writes byte-identical PNGs with 1, 2 and 8 threads, run after run", "[cli]") {
    const fs::path dir = tempDir("determinism");
    std::string first;
    int run = 0;
    for (int threads : {1, 2, 8, 8}) {
        const fs::path out = dir / (std::to_string(run++) + "-" + std::to_string(threads) + "-threads.png");
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out.string() + "' --size 96x64 --threads " +
                                    std::to_string(threads) + " -q");
        REQUIRE(r.exitCode == 0);
        const std::string bytes = slurp(out);
        REQUIRE(bytes.size() > 1000);
        if (first.empty()) first = bytes;
        CHECK(bytes == first);
    }
    fs::remove_all(dir);
}

TEST_CASE("CLI: render with --method embree and embree-grid writes the picture", "[cli][embree]") {
    const fs::path dir = tempDir("embree");
    for (const char* method : {"embree", "embree-grid", "triangles"}) {
        const fs::path out = dir / (std::string(method) + ".png");
        const auto r = runTerracast("render '" + kStHelens + "' -o '" + out.string() + "' --size 64x48 --method " + method);
        INFO(method << ": " << r.err);
        REQUIRE(r.exitCode == 0);
        CHECK(r.err.find(method) != std::string::npos);
        CHECK(terracast::readImage(out.string()).width == 64);
    }
    // The triangle surfaces render the same picture whether traced directly or by Embree (a few edge pixels
    // may differ).
    const auto a = terracast::readImage((dir / "embree.png").string()), b = terracast::readImage((dir / "triangles.png").string());
    size_t differ = 0;
    for (size_t k = 0; k < a.rgb.size(); ++k) differ += std::abs(a.rgb[k] - b.rgb[k]) > 0.02f;
    CHECK(differ <= a.rgb.size() / 100);
    fs::remove_all(dir);
}

TEST_CASE("CLI: bad view values are refused with exit 2 and name the option", "[cli]") {
    const fs::path dir = tempDir("view");
    const std::string out = (dir / "v.png").string();
    auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --camera 'eye=0,0,5000 look=0,100,5000 up=0,1,0'");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("--camera") != std::string::npos);
    r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --exaggeration 1e36");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("a vertical exaggeration of 1e+36 makes heights of up to 2543 m unusable") != std::string::npos);
    r = runTerracast("compare '" + kStHelens + "' --sun 315,200");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("--sun") != std::string::npos);
    CHECK(fs::is_empty(dir));
    // A missing DEM leaves no output folder behind.
    r = runTerracast("compare '" + (dir / "none.tif").string() + "' --out-dir '" + (dir / "cmp").string() + "'");
    CHECK(r.exitCode == 2);
    CHECK_FALSE(fs::exists(dir / "cmp"));
    // Tiny pictures still get their heat maps (the legend is clipped, not written out of bounds).
    r = runTerracast("compare '" + kStHelens + "' --size 8x8 --methods bilinear,nearest --out-dir '" + (dir / "cmp").string() + "'");
    CHECK(r.exitCode == 0);
    CHECK(terracast::readImage((dir / "cmp" / "diff-nearest.png").string()).width == 8);
    fs::remove_all(dir);
}

TEST_CASE("CLI: an interrupted render exits promptly, says so and leaves no file", "[cli]") {
    const fs::path dir = tempDir("interrupt");
    const fs::path out = dir / "big.png";
    // A render of several seconds on one thread, stopped a second after it has installed its signal handler
    // (once the shell's child runs the executable, bit 15 of SigCgt in /proc: 4 in the 13th of its 16 hex
    // digits), so that a slow start (a loaded machine, the sanitizers) is not mistaken for a slow stop.
    // (SIGTERM: a shell starts background jobs with SIGINT ignored until the program installs its handler.)
    const std::string script =
        "'" + std::string(TERRACAST_CLI_PATH) + "' render '" + kStHelens + "' -o '" + out.string() +
        "' --size 6000x4000 --threads 1 -q 2>'" + (dir / "err.txt").string() + "' & pid=$!; n=0; "
        "while [ $n -lt 600 ]; do d=$(sed -n 's/^SigCgt:[[:space:]]*//p' /proc/$pid/status | cut -c13); "
        "[ \"$(readlink -f /proc/$pid/exe)\" = \"$(readlink -f '" + std::string(TERRACAST_CLI_PATH) + "')\" ] && "
        "case \"$d\" in [4567cdef]) break;; esac; sleep 0.05; n=$((n + 1)); done; sleep 1; "
        "t0=$(date +%s%N); kill -TERM $pid; wait $pid; echo $? > '" + (dir / "rc.txt").string() +
        "'; echo $(( ($(date +%s%N) - t0) / 1000000 )) > '" + (dir / "ms.txt").string() + "'";
    REQUIRE(std::system(script.c_str()) == 0);  // std::system runs it with sh -c
    CHECK(std::stoi(slurp(dir / "rc.txt")) == 130);
    CHECK(slurp(dir / "err.txt").find("interrupted") != std::string::npos);
    // From the signal to the exit: the work stops at the next 32-pixel tile of a render that has minutes left;
    // the exit itself (and, under the sanitizers, their check for leaks) takes a second or two on a busy machine.
    CHECK(std::stoi(slurp(dir / "ms.txt")) < (terracast::testing::kSanitizedBuild ? 8000 : 3000));
    CHECK_FALSE(fs::exists(out));
    int files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    CHECK(files == 3);  // only err.txt, rc.txt and ms.txt: no temporary image either
    fs::remove_all(dir);
}

TEST_CASE("CLI: --max-memory refuses jobs estimated above it, before any work", "[cli]") {
    const fs::path dir = tempDir("memory");
    // Removed however the test ends (its REQUIREs leave early).
    const std::unique_ptr<const fs::path, void (*)(const fs::path*)> cleanup(&dir, [](const fs::path* p) {
        std::error_code ignored;
        fs::remove_all(*p, ignored);
    });
    const std::string out = (dir / "m.png").string();
    // The grid itself: 327 x 468 vertices need about 2 MiB to load and trace.
    auto r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --max-memory 1M");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("--max-memory") != std::string::npos);
    CHECK(r.err.find("327 x 468 raster needs about 1.7 MiB to load and trace") != std::string::npos);
    CHECK(r.err.find("more than the 1.0 MiB limit") != std::string::npos);
    // The grid fits but an Embree scene does not: Embree's mesh of 1025^2 vertices adds over 200 MiB to what the
    // process holds, and the direct method renders within a limit halfway between the two. What a process holds
    // at start (its libraries; several times more under a sanitizer) is read from the refusals themselves, so
    // the limit sits about 100 MiB from either side whatever the build.
    const std::string puget = std::string(TERRACAST_SOURCE_DIR) + "/data-samples/puget-sound-usgs-1025x1025-16bit-heightmap.png";
    r = runTerracast("render '" + puget + "' -o '" + out + "' --max-memory 1M --method embree");
    REQUIRE(r.exitCode == 2);
    const std::vector<std::string> load = firstMatch(r.err, "raster needs about ([0-9.]+ [KMG]iB) to load and trace \\(([0-9.]+ [KMG]iB) held already");
    REQUIRE(load.size() == 3);
    const double loadMiB = mebibytes(load[1]) + mebibytes(load[2]);
    r = runTerracast(fmt::format("render '{}' -o '{}' --max-memory {}M --method embree", puget, out, int(loadMiB) + 64));
    REQUIRE(r.exitCode == 2);
    const std::vector<std::string> embree = firstMatch(r.err, "with embree needs about ([0-9.]+ [KMG]iB) \\(([0-9.]+ [KMG]iB) held already");
    REQUIRE(embree.size() == 3);
    const double needMiB = mebibytes(embree[1]), heldMiB = mebibytes(embree[2]);
    CHECK(needMiB - heldMiB > 200.0);  // 230 bytes per cell in Embree's mesh and BVH
    const std::string limit = fmt::format("--max-memory {}M", int(std::lround(heldMiB + 0.5 * (needMiB - heldMiB))));
    r = runTerracast("render '" + puget + "' -o '" + out + "' " + limit + " --method embree");
    CHECK(r.exitCode == 2);
    CHECK(r.err.find("embree") != std::string::npos);
    CHECK(lineCount(r.err) == 1);
    CHECK_FALSE(fs::exists(out));
    r = runTerracast("render '" + puget + "' -o '" + out + "' " + limit + " --size 64x48");
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(out));
    fs::remove(out);
    // Enough memory: the same job runs.
    r = runTerracast("render '" + kStHelens + "' -o '" + out + "' --max-memory 2G --method embree --size 64x48");
    CHECK(r.exitCode == 0);
    r = runTerracast("info '" + kStHelens + "' --max-memory 12X");
    CHECK(r.exitCode == 2);
    fs::remove_all(dir);
}
