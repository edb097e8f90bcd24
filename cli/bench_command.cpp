// `bench`: option parsing into typed values; the work is runBenchReport.
#include "cli/cli_support.h"

#include "tracer/core/errors.h"
#include "tracer/measure/bench_pipeline.h"
#include "tracer/measure/whole_process.h"

#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>

namespace terracast::cli {

namespace {

// --povray: empty for povray on PATH (or none there), "none" to skip, a name on PATH, or a path.
std::string povrayExecutable(const std::string& given) {
    if (given.empty()) return findOnPath("povray");
    if (given == "none") return {};
    const std::string found = given.find('/') == std::string::npos ? findOnPath(given) : given;
    if (found.empty() || ::access(found.c_str(), X_OK) != 0 || !std::filesystem::is_regular_file(found))
        throw InputError(fmt::format("--povray: expected an executable (a path, a name on PATH, or none), found '{}'", given));
    return std::filesystem::absolute(found).string();
}

}  // namespace

void addBenchCommand(CLI::App& app, Commands& commands) {
    struct Texts {
        BenchRunOptions options;
        std::string sizes = "513,2049,8193", methods, povray;
    };
    auto t = std::make_shared<Texts>();
    BenchRunOptions& bench = t->options;
    auto* cmd = app.add_subcommand(
        "bench", "Measure the direct tracer against Embree on synthetic fractal grids (and the sample DEMs)");
    cmd->add_option("--sizes", t->sizes, "Synthetic grid sizes, 2^n + 1 vertices each (default 513,2049,8193)");
    cmd->add_option("--threads", bench.threads, "Thread count measured beside 1 thread, 0 = all cores (default 0)")
        ->check(CLI::Range(0, 4096));
    cmd->add_option("--repeat", bench.repeat,
                    "Trace each pass this many times (default " + std::to_string(BenchSettings{}.repeat) + ")")
        ->check(CLI::Range(1, 100));
    cmd->add_option("--bands", bench.bands,
                    "Trace each pass in this many bands of rows, each band in turn with the other methods; a "
                    "pass's time is the sum of each band's fastest (default " +
                        std::to_string(BenchSettings{}.bands) + ")")
        ->check(CLI::Range(1, BenchSettings{}.height));
    cmd->add_option("--json", bench.json, "Write the report as JSON to this file");
    cmd->add_option("--methods", t->methods,
                    "Methods to measure, comma-separated: bilinear, bilinear-flat, triangles, embree, embree-grid "
                    "(default all; embree is always measured, as the reference of the ratios)");
    cmd->add_option("--svg", bench.svg,
                    "Write an SVG chart of camera rays per second against grid size (synthetic grids, both "
                    "cameras, the most threads) to this file");
    cmd->add_flag("--file-to-picture", bench.fileToPicture,
                  "Also time `render FILE.png --cell-size 30 --size 1024x768` with bilinear and with embree, "
                  "from the largest synthetic grid written as a 16-bit PNG height map");
    cmd->add_option("--povray", t->povray,
                    "With --file-to-picture: POV-Ray's executable, timed as a whole process beside `render` on the "
                    "same height map (default: povray on PATH, if any; none: skip)");
    cmd->add_option("--paired-runs", bench.pairedRuns,
                    "With --file-to-picture: whole-process runs of each program, taking turns (default 3)")
        ->check(CLI::Range(1, 100));
    cmd->add_flag("--large", bench.large, "Add a 32769 x 32769 synthetic grid (skipped when over --max-memory)");
    cmd->add_flag("--real", bench.real, "Add the GeoTIFF and .hgt DEMs of --data");
    cmd->add_option("--data", bench.dataDir, "Folder of the DEMs --real adds (default: the sample DEMs)");
    cmd->add_option("--seed", bench.seed, "Seed of the synthetic terrain (default 1)");
    addMaxMemoryOption(
        *cmd, bench.maxMemoryBytes,
        "Skip grids and methods estimated to need more memory than this, e.g. 8G (default: 80% of physical memory)");
    commands.push_back({cmd, [t] {
                            return guarded([&] {
                                t->options.sizes = parseBenchSizes(t->sizes);
                                if (t->options.dataDir.empty()) t->options.dataDir = TERRACAST_DATA_DIR;
                                if (!t->methods.empty()) t->options.methods = parseBenchMethods(t->methods);
                                t->options.terracastExecutable = selfExecutablePath();
                                t->options.povray = povrayExecutable(t->povray);
                                runBenchReport(t->options, ConsoleListener(false).listener());
                            });
                        }});
}

}  // namespace terracast::cli
