// `bench` from options to report: the synthetic fractal grids (and the sample DEMs) measured with benchGrid,
// tables on the listener's output as each grid completes, the SVG chart, the JSON report last, and the
// file-to-picture run (`render` on a 16-bit PNG height map, with bilinear and with embree, in paired runs).
#pragma once

#include "tracer/core/listener.h"
#include "tracer/measure/bench.h"
#include "tracer/terrain/dem_pipeline.h"

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace terracast {

struct BenchRunOptions {
    std::vector<int64_t> sizes{513, 2049, 8193};  // synthetic grid sizes, each 2^n + 1 vertices
    int threads = 0;                      // the thread count measured beside 1; 0 = all cores
    int repeat = BenchSettings{}.repeat;  // traces per pass
    int bands = BenchSettings{}.bands;    // bands of rows per trace; each band's fastest trace is kept
    std::string json;                     // report file; empty = none
    bool large = false;                   // add a 32769 x 32769 synthetic grid
    bool real = false;                    // add the DEMs of `dataDir`
    std::string dataDir;                  // folder of real DEMs (with `real`)
    uint64_t seed = 1;                    // seed of the synthetic terrain
    double maxMemoryBytes = 0.0;          // grids and methods estimated to need more are skipped; 0 = 80% of RAM
    std::string svg;                      // chart of camera rays/s against grid size; empty = none
    bool fileToPicture = false;           // also time `render` from a 16-bit PNG of the largest synthetic grid
    std::vector<BenchMethod> methods;     // the methods to measure, in report order; empty = all
    // With fileToPicture, whole processes: this terracast executable's `render` (empty = none) and POV-Ray
    // (a path, or empty when it is not installed), each run `pairedRuns` times, one after the other.
    std::string terracastExecutable;
    std::string povray;
    int pairedRuns = 3;
};

// Runs the whole bench. Throws InputError for bad options, Cancelled when interrupted.
void runBenchReport(const BenchRunOptions& options, const RunListener& listener);

// One grid of `bench`: a synthetic fractal of some size, or a DEM file.
struct BenchJob {
    std::string name;   // as reported: "synthetic-513" or the file's name (no folder: reports name no machine paths)
    int64_t size = 0;   // synthetic: vertices per side; 0 for a file
    std::string path;   // file: the DEM
    bool integer = false;  // synthetic: heights in whole metres, so the grid is held as int16
};

// `bench --file-to-picture`: the whole `render FILE.png` job with one method.
struct FileToPictureRun {
    BenchMethod method = BenchMethod::Bilinear;
    bool skipped = false;       // estimated over --max-memory; nothing below is measured
    double neededBytes = 0.0;   // when skipped
    RenderPhaseSeconds seconds;
    int64_t pictureBytes = 0;   // the PNG written
    int pictureWidth = 0;       // as read back
    int pictureHeight = 0;
};

// One program of the whole-process comparison, over its paired runs.
struct WholeProcessRuns {
    std::vector<double> seconds;  // each run's wall time, from the spawn to the exit
    double medianSeconds = 0.0;
    double bestSeconds = 0.0;
    double peakBytes = 0.0;       // the largest of the runs' peak resident memory
};

// `render FILE.png` and POV-Ray 3.7 on the same height map, camera, picture size and sun, as whole processes.
struct WholeProcessComparison {
    bool ran = false;
    std::string skippedWhy;             // when not run: "POV-Ray is not installed", ...
    std::string povrayVersion;          // its banner's first line
    WholeProcessRuns terracast;         // `render --method bilinear --sky-samples 0`
    WholeProcessRuns povray;            // height_field, smooth, one parallel light with shadows
    double speedup = std::numeric_limits<double>::quiet_NaN();  // POV-Ray's median time / terracast's
    double gridBytes = 0.0;             // the grid `render` holds, and its picture (film and 8-bit copy)
    double pictureBytes = 0.0;
    double peakOverGridAndPicture = std::numeric_limits<double>::quiet_NaN();  // terracast's peak over the two
    int64_t silhouettePixels = 0;       // pixels where terracast's `triangles` or POV-Ray meet the terrain
    int64_t silhouetteMismatches = -1;  // pixels where only one of the two does; -1 = not compared
};

struct FileToPictureResult {
    std::string name;                  // "synthetic-8193"
    int64_t size = 0;                  // vertices per side
    bool skipped = false;              // the height map itself would not fit; nothing below is measured
    double neededBytes = 0.0;
    double makeSeconds = 0.0;          // the fractal grid
    double heightMapSeconds = 0.0;     // encoding and writing the 16-bit PNG
    int64_t heightMapBytes = 0;
    int threads = 1;
    DemRenderOptions render;           // as run, less the paths
    std::vector<FileToPictureRun> runs;
    double totalRatio = std::numeric_limits<double>::quiet_NaN();          // total(embree) / total(bilinear)
    double pictureMeanAbsDiff = std::numeric_limits<double>::quiet_NaN();  // 8-bit levels, over all channels
    WholeProcessComparison wholeProcess;
};

// What the file-to-picture run makes and measures.
struct FileToPictureOptions {
    int64_t size = 8193;             // vertices per side of the synthetic grid
    uint64_t seed = 1;
    int threads = 2;
    double maxMemoryBytes = 0.0;     // as --max-memory, passed to each render
    double limit = 0.0;              // the resolved limit in bytes
    std::string terracastExecutable; // whole-process runs of `render`; empty = none
    std::string povray;              // POV-Ray's executable; empty = not installed
    int pairedRuns = 3;
};


// The file-to-picture run for the synthetic grid of `size`: see runBenchReport. `onStep` hears the steps,
// `onWarning` the loader's warnings about the height map.
FileToPictureResult fileToPicture(const FileToPictureOptions& options,
                                  const std::function<void(const std::string&)>& onStep,
                                  const std::function<void(const std::string&)>& onWarning = {});

// The report's pieces: a grid's object and table, and the file-to-picture object and table.
std::string benchGridJson(const BenchJob& job, const BenchGridResult& r, const BenchSettings& s);
std::string benchGridTable(const BenchJob& job, const HeightGrid& grid, const BenchGridResult& r, double makeSeconds,
                           double limit);
std::string fileToPictureJson(const FileToPictureResult& f);
std::string fileToPictureTable(const FileToPictureResult& f, double limit);

}  // namespace terracast
