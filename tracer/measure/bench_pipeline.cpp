#include "tracer/measure/bench_pipeline.h"

#include "heightfield/fractal_terrain.h"
#include "loaders/height_png.h"
#include "loaders/image_io.h"
#include "loaders/output_paths.h"
#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/measure/povray_scene.h"
#include "tracer/measure/reports.h"
#include "tracer/measure/whole_process.h"
#include "tracer/terrain/memory_model.h"
#include "tracer/terrain/surface.h"

#include <fmt/format.h>

#include <stdlib.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace terracast {

namespace {

// The DEMs `bench --real` adds: the GDAL rasters of a folder (GeoTIFF, SRTM .hgt), by name. PNG height maps
// are left out: they carry no cell size or height scale.
std::vector<std::string> benchRealDems(const std::string& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw InputError(fmt::format("--data: '{}' is not a folder", dir));
    std::vector<std::string> paths;
    for (const auto& e : fs::directory_iterator(dir, ec)) {
        const std::string ext = lowerExtension(e.path().string());
        if (e.is_regular_file(ec) && (ext == ".tif" || ext == ".tiff" || ext == ".hgt")) paths.push_back(e.path().string());
    }
    std::sort(paths.begin(), paths.end());
    if (paths.empty()) throw InputError(fmt::format("--data: no GeoTIFF or .hgt DEM in '{}'", dir));
    return paths;
}

// The processor's model name from /proc/cpuinfo, or empty where there is none.
std::string cpuModelName() {
    std::ifstream in("/proc/cpuinfo");
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("model name", 0) == 0) {
            const auto colon = line.find(':');
            if (colon == std::string::npos) break;
            const auto first = line.find_first_not_of(" \t", colon + 1);
            return first == std::string::npos ? std::string() : line.substr(first);
        }
    return {};
}

// A folder of its own under the system's temporary folder, removed with all it holds on destruction.
class ScratchFolder {
public:
    ScratchFolder() {
        std::string pattern = (std::filesystem::temp_directory_path() / "terracast-bench-XXXXXX").string();
        if (!mkdtemp(pattern.data())) throw std::runtime_error("cannot make a temporary folder under " + pattern);
        path_ = pattern;
    }
    ~ScratchFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchFolder(const ScratchFolder&) = delete;
    ScratchFolder& operator=(const ScratchFolder&) = delete;
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

WholeProcessRuns summarizeRuns(const std::vector<ProcessRun>& runs) {
    WholeProcessRuns w;
    for (const auto& r : runs) {
        w.seconds.push_back(r.seconds);
        w.peakBytes = std::isnan(r.peakBytes) || std::isnan(w.peakBytes) ? r.peakBytes + w.peakBytes
                                                                         : std::max(w.peakBytes, r.peakBytes);
    }
    std::vector<double> sorted = w.seconds;
    std::sort(sorted.begin(), sorted.end());
    w.bestSeconds = sorted.front();
    w.medianSeconds = sorted.size() % 2 ? sorted[sorted.size() / 2]
                                        : 0.5 * (sorted[sorted.size() / 2 - 1] + sorted[sorted.size() / 2]);
    return w;
}

// The last non-empty line of a child's log, to say why it failed.
std::string lastLogLine(const std::string& path) {
    std::ifstream in(path);
    std::string line, last;
    while (std::getline(in, line))
        if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
    return last;
}

ProcessRun runChecked(const std::vector<std::string>& argv, const std::filesystem::path& folder, const std::string& what) {
    const std::string log = (folder / "children.log").string();
    std::filesystem::remove(log);
    const ProcessRun run = runTimedProcess(argv, folder.string(), log);
    // Ctrl-C reaches the child too: the bench stops as interrupted.
    if (run.exitCode == 130 || run.exitCode == 128 + SIGINT || cancelFlag().load()) throw Cancelled();
    if (run.exitCode != 0)
        throw std::runtime_error(fmt::format("{} exited with status {}: {}", what, run.exitCode, lastLogLine(log)));
    return run;
}

// `render` and POV-Ray as whole processes on the same height map (see WholeProcessComparison): first each one's
// silhouette (terracast's `triangles` surface traced here through render's camera, against POV-Ray's picture of
// the terrain alone), then, with the bench's own copy of the grid released, the paired runs.
void runWholeProcesses(WholeProcessComparison& c, const FileToPictureOptions& o, const DemRenderOptions& render,
                       const std::string& heightMap, const std::filesystem::path& folder,
                       const std::function<void(const std::string&)>& onStep,
                       const std::function<void(const std::string&)>& onWarning) {
    const int W = render.width, H = render.height;
    const double aspect = double(W) / double(H);
    const std::string size = fmt::format("{}x{}", W, H);
    {
        const std::string log = (folder / "version.log").string();
        runTimedProcess({o.povray, "--version"}, folder.string(), log);
        std::ifstream in(log);
        std::string line;
        while (std::getline(in, line))
            if (line.rfind("POV-Ray", 0) == 0) {
                c.povrayVersion = line;
                break;
            }
    }
    {
        // The grid as `render` loads it (the PNG's whole metres): its camera, extents and memory.
        DemSource source;
        source.path = heightMap;
        source.imageCellSizeM = render.dem.imageCellSizeM;
        source.maxMemoryBytes = o.maxMemoryBytes;
        RunListener quiet;
        quiet.warning = onWarning;
        const LoadedDem dem = loadDemSource(source, quiet);
        const HeightGrid& grid = dem.grid;
        const PinholeCamera camera = autoCamera(grid, aspect);
        c.gridBytes = double(grid.memoryBytes());

        PovrayHeightFieldView view;
        view.heightMap = std::filesystem::path(heightMap).filename().string();
        view.extentXM = grid.extentXM();
        view.extentYM = grid.extentYM();
        view.camera = camera;
        view.aspect = aspect;
        view.sunAzimuthDeg = render.sunAzimuthDeg;
        view.sunElevationDeg = render.sunElevationDeg;
        writeTextFile((folder / "terrain.pov").string(), povrayHeightFieldScene(view));
        view.silhouette = true;
        writeTextFile((folder / "silhouette.pov").string(), povrayHeightFieldScene(view));

        // Silhouettes: which pixels' camera rays meet the terrain, by each.
        if (onStep) onStep("silhouettes: POV-Ray's and the triangles surface's");
        runChecked({o.povray, "+Isilhouette.pov", "+Osilhouette.png", "+FN", fmt::format("+W{}", W),
                    fmt::format("+H{}", H), "-D", "-P", "-A", fmt::format("+WT{}", o.threads)},
                   folder, "POV-Ray");
        const RgbImage theirsMask = readImage((folder / "silhouette.png").string());
        if (theirsMask.width != W || theirsMask.height != H)
            throw std::runtime_error(fmt::format("POV-Ray's silhouette is {}x{}, not {}", theirsMask.width,
                                                 theirsMask.height, size));
        const TerrainSurface triangles(grid, SurfaceMethod::Triangles, o.threads);
        c.silhouettePixels = 0;
        c.silhouetteMismatches = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                const Ray ray = camera.generate((x + 0.5) / W, (y + 0.5) / H, aspect);
                const bool ourHit = triangles.intersect(ray, Interval{}).has_value();
                const bool theirHit = theirsMask.at(x, y, 0) > 0.5f;
                c.silhouettePixels += (ourHit || theirHit) ? 1 : 0;
                c.silhouetteMismatches += ourHit != theirHit ? 1 : 0;
            }
    }

    std::vector<std::string> terracastArgs{
        o.terracastExecutable, "render", heightMap, "--cell-size", fmt::format("{:g}", render.dem.imageCellSizeM),
        "--size", size, "--threads", std::to_string(o.threads), "--sky-samples", "0", "--no-base", "--background",
        "ground", "--quiet", "-o", (folder / "whole-terracast.png").string()};
    if (o.maxMemoryBytes > 0.0) {
        terracastArgs.push_back("--max-memory");
        terracastArgs.push_back(fmt::format("{}K", int64_t(std::ceil(o.maxMemoryBytes / 1024.0))));
    }
    const std::vector<std::string> povrayArgs{
        o.povray, "+Iterrain.pov", "+Owhole-povray.png", "+FN", fmt::format("+W{}", W), fmt::format("+H{}", H),
        "-D", "-P", "-A", fmt::format("+WT{}", o.threads)};
    std::vector<ProcessRun> ours, theirs;
    const int pairs = std::max(1, o.pairedRuns);
    for (int k = 0; k < pairs; ++k) {
        // Alternating which goes first, so that neither always finds the other's files in the page cache.
        for (int side = 0; side < 2; ++side) {
            const bool terracastNow = (side == 0) == (k % 2 == 0);
            if (onStep)
                onStep(fmt::format("whole process, pair {} of {}: {}", k + 1, pairs, terracastNow ? "terracast render" : "POV-Ray"));
            if (terracastNow) ours.push_back(runChecked(terracastArgs, folder, "terracast render"));
            else theirs.push_back(runChecked(povrayArgs, folder, "POV-Ray"));
        }
    }
    c.terracast = summarizeRuns(ours);
    c.povray = summarizeRuns(theirs);
    c.speedup = c.povray.medianSeconds / c.terracast.medianSeconds;
    c.pictureBytes = double(W) * double(H) * kFilmBytesPerPixel;
    c.peakOverGridAndPicture = c.terracast.peakBytes / (c.gridBytes + c.pictureBytes);
    c.ran = true;
}

// The comparison, or why it did not run: POV-Ray is an optional peer, so its failure (or terracast's own
// render refused) is reported, and the bench's other results stand. Ctrl-C still stops the bench.
WholeProcessComparison compareWholeProcesses(const FileToPictureOptions& o, const DemRenderOptions& render,
                                             bool bilinearSkipped, const std::string& heightMap,
                                             const std::filesystem::path& folder,
                                             const std::function<void(const std::string&)>& onStep,
                                             const std::function<void(const std::string&)>& onWarning) {
    WholeProcessComparison c;
    if (o.terracastExecutable.empty()) c.skippedWhy = "no terracast executable to run";
    else if (o.povray.empty()) c.skippedWhy = "POV-Ray is not installed (Debian's povray package)";
    else if (bilinearSkipped) c.skippedWhy = "the bilinear render would not fit in --max-memory";
    if (!c.skippedWhy.empty()) return c;
    try {
        runWholeProcesses(c, o, render, heightMap, folder, onStep, onWarning);
    } catch (const Cancelled&) {
        throw;
    } catch (const std::exception& e) {
        WholeProcessComparison failed;
        failed.skippedWhy = fmt::format("failed: {}", e.what());
        failed.povrayVersion = c.povrayVersion;
        return failed;
    }
    return c;
}

}  // namespace

// Makes the fractal grid of `size`, writes it as a 16-bit PNG height map into a scratch folder, then runs
// `render` on it as a user would (--cell-size 30 --size 1024x768 --threads N) with bilinear and with embree,
// each picture written into the same folder; reads both pictures back to compare them, then removes the folder.
FileToPictureResult fileToPicture(const FileToPictureOptions& o,
                                  const std::function<void(const std::string&)>& onStep,
                                  const std::function<void(const std::string&)>& onWarning) {
    const int64_t size = o.size;
    const int threads = o.threads;
    const double limit = o.limit;
    using Clock = std::chrono::steady_clock;
    const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
    FileToPictureResult out;
    out.name = fmt::format("synthetic-{}", size);
    out.size = size;
    out.threads = threads;
    out.render.dem.imageCellSizeM = 30.0;
    out.render.dem.maxMemoryBytes = o.maxMemoryBytes;
    out.render.width = 1024;
    out.render.height = 768;
    out.render.threads = threads;
    // The terrain alone against the sky, as POV-Ray's height_field shows it: no solid base, the sky model below
    // the horizon too (the measured work is the terrain's rays; the base's walls would change the silhouette).
    out.render.solidBase = false;
    out.render.backdrop = Backdrop::Ground;
    // Camera rays and one shadow ray per hit, as POV-Ray traces them: no sky-visibility rays.
    out.render.skySamples = 0;
    const BenchMethod methods[] = {BenchMethod::Bilinear, BenchMethod::Embree};
    for (BenchMethod m : methods) {
        FileToPictureRun run;
        run.method = m;
        out.runs.push_back(run);
    }

    // While the height map is made: the grid, its scanlines and their deflated copy (at most about as big).
    const double vertices = double(size) * double(size);
    const double mapNeed = double(fractalTerrainBytes(size)) + 4.1 * vertices;
    if (mapNeed > limit) {
        out.skipped = true;
        out.neededBytes = mapNeed;
        return out;
    }
    ScratchFolder scratch;
    const std::string heightMap = (scratch.path() / "height.png").string();
    {
        if (onStep) onStep("making the grid");
        const auto made = Clock::now();
        FractalTerrainOptions fo;
        fo.size = size;
        fo.seed = o.seed;
        const HeightGrid grid = fractalTerrain(fo);
        out.makeSeconds = since(made);
        // What render will hold: the grid as loaded (as big as this one), the loader's 16-bit samples, the
        // film, and Embree's scene.
        for (auto& run : out.runs) {
            const double need = double(grid.memoryBytes()) + 2.0 * vertices + double(out.render.width) *
                                out.render.height * kFilmBytesPerPixel + embreeBytesEstimate(benchSurfaceMethod(run.method), grid);
            if (need > limit) {
                run.skipped = true;
                run.neededBytes = need;
            }
        }
        if (onStep) onStep("writing the 16-bit PNG height map");
        const auto written = Clock::now();
        const std::string png = encodeHeightPng16(grid);
        writeFileAtomically(heightMap, png);
        out.heightMapSeconds = since(written);
        out.heightMapBytes = int64_t(png.size());
    }

    std::vector<RgbImage> pictures;
    for (auto& run : out.runs) {
        if (run.skipped) continue;
        if (onStep) onStep(fmt::format("render {} with {}", std::filesystem::path(heightMap).filename().string(),
                                       benchMethodName(run.method)));
        DemRenderOptions ro = out.render;
        ro.dem.path = heightMap;
        ro.output = (scratch.path() / (std::string(benchMethodName(run.method)) + ".png")).string();
        ro.method = benchSurfaceMethod(run.method);
        RunListener quiet;  // as `render --quiet`: warnings only
        quiet.warning = onWarning;
        run.seconds = renderDem(ro, quiet);
        run.pictureBytes = int64_t(std::filesystem::file_size(ro.output));
        pictures.push_back(readImage(ro.output));
        run.pictureWidth = pictures.back().width;
        run.pictureHeight = pictures.back().height;
    }
    if (!out.runs[0].skipped && !out.runs[1].skipped) {
        out.totalRatio = out.runs[1].seconds.total / out.runs[0].seconds.total;
        const RgbImage& a = pictures[0];
        const RgbImage& b = pictures[1];
        if (a.width == b.width && a.height == b.height && !a.rgb.empty()) {
            // The 8-bit sRGB levels the PNGs store.
            const auto level = [](float v) { return std::lround(255.0f * srgbFromLinear(v)); };
            double sum = 0.0;
            for (size_t k = 0; k < a.rgb.size(); ++k) sum += double(std::labs(level(a.rgb[k]) - level(b.rgb[k])));
            out.pictureMeanAbsDiff = sum / double(a.rgb.size());
        }
    }
    pictures.clear();
    out.wholeProcess =
        compareWholeProcesses(o, out.render, out.runs[0].skipped, heightMap, scratch.path(), onStep, onWarning);
    return out;
}

void runBenchReport(const BenchRunOptions& o, const RunListener& listener) {
    std::vector<int64_t> sizes = o.sizes;
    if (sizes.empty()) throw InputError("--sizes: expected at least one grid size");
    if (o.large && std::find(sizes.begin(), sizes.end(), int64_t(32769)) == sizes.end()) sizes.push_back(32769);
    if (o.threads < 0) throw InputError(fmt::format("--threads: expected 0 (all cores) or more, found {}", o.threads));
    if (!o.json.empty()) checkOutputFolder(o.json);
    if (!o.svg.empty()) checkOutputFolder(o.svg);
    std::vector<BenchJob> jobs;
    // The --large grid has whole-metre heights and so int16 storage: 2.7 bytes per cell instead of 4.7.
    for (int64_t size : sizes)
        jobs.push_back({fmt::format("synthetic-{}", size), size, "", o.large && size == 32769});
    if (o.real)
        for (const auto& path : benchRealDems(o.dataDir))
            jobs.push_back({std::filesystem::path(path).filename().string(), 0, path});

    const int hardware = std::max(1, int(std::thread::hardware_concurrency()));
    const int most = o.threads > 0 ? o.threads : hardware;
    BenchSettings settings;
    if (!o.methods.empty()) settings.methods = o.methods;
    settings.threadCounts = most > 1 ? std::vector<int>{1, most} : std::vector<int>{1};
    settings.repeat = o.repeat;
    settings.bands = o.bands;
    const double limit = memoryLimitBytes(o.maxMemoryBytes);
    // Per pixel while a pass runs: its hits, directions, shadow verdicts, picture and hit distances, plus
    // the first method's hit distances kept for the agreement.
    const double passBytes = double(settings.width) * settings.height *
                             double(sizeof(std::optional<HeightFieldHit>) + sizeof(glm::dvec3) + 1 + 12 + 8 + 8);
    const char* kernels = kernelIsaName(kernelIsa());
    const std::string cpu = cpuModelName();
    const std::string machine = fmt::format("{}{} hardware thread{}", cpu.empty() ? "" : cpu + ", ", hardware,
                                            hardware == 1 ? "" : "s");

    listener.print(fmt::format("terracast bench: {} x {} camera rays per view (corner: south-west, 30 degrees down; grazing: above "
               "the highest peak, 8 degrees down), sun at azimuth {:g}, elevation {:g} degrees, one shadow ray per "
               "hit facing it; {} thread{} ({}); FTZ/DAZ on for every method; direct kernels: {}; {} trace{} per "
               "pass after one untimed, in {} band{} of rows, each band taken in turn with the other methods in "
               "alternating order; a pass's time is the sum of each band's fastest\n",
               settings.width, settings.height, settings.sunAzimuthDeg, settings.sunElevationDeg,
               most > 1 ? fmt::format("1 and {}", most) : "1", most > 1 ? "s" : "", machine,
               kernels, settings.repeat, settings.repeat == 1 ? "" : "s", settings.bands,
               settings.bands == 1 ? "" : "s"));
    std::string json = fmt::format("{{\"image_width\": {}, \"image_height\": {}, \"sun_azimuth_deg\": {}, "
                                   "\"sun_elevation_deg\": {}, \"cpu\": {}, \"hardware_threads\": {}, "
                                   "\"kernels\": {}, \"threads\": [{}], \"repeat\": {}, \"bands\": {},\n \"grids\": [",
                                   settings.width, settings.height, jsonNumber(settings.sunAzimuthDeg),
                                   jsonNumber(settings.sunElevationDeg), jsonString(cpu), hardware,
                                   jsonString(kernels),
                                   most > 1 ? fmt::format("1, {}", most) : "1", settings.repeat, settings.bands);
    std::vector<BenchGridResult> plotted;  // the synthetic grids measured, for --svg
    const auto start = std::chrono::steady_clock::now();
    for (size_t g = 0; g < jobs.size(); ++g) {
        const BenchJob& job = jobs[g];
        json += g ? ",\n " : "\n ";
        if (job.size > 0) {
            // The grid alone (its heights and the pyramid) must fit with one pass's buffers, and while it is
            // made, with the float heights it is generated in.
            const double gridBytes = double(fractalTerrainBytes(job.size, job.integer));
            const double need =
                std::max(gridBytes + passBytes, gridBytes + (job.integer ? 4.0 * double(job.size) * double(job.size) : 0.0));
            if (need > limit) {
                listener.print(fmt::format("\n{} ({} x {} vertices): skipped: needs about {} (grid {}), more than the "
                                           "{} limit (--max-memory)\n",
                                           job.name, job.size, job.size, humanBytes(need), humanBytes(gridBytes),
                                           humanBytes(limit)));
                json += fmt::format("{{\"dem\": {}, \"synthetic\": true, \"width\": {}, \"height\": {}, \"cells\": {}, "
                                    "\"skipped\": true, \"memory_needed_bytes\": {}, \"methods\": []}}",
                                    jsonString(job.name), job.size, job.size, (job.size - 1) * (job.size - 1),
                                    jsonNumber(need));
                continue;
            }
        }
        listener.at(fmt::format("bench: {}: making the grid", job.name));
        const auto made = std::chrono::steady_clock::now();
        HeightGrid grid;
        if (job.size > 0) {
            FractalTerrainOptions fo;
            fo.size = job.size;
            fo.seed = o.seed;
            fo.integerHeights = job.integer;
            grid = fractalTerrain(fo);
        } else {
            DemSource dem;
            dem.path = job.path;
            dem.maxMemoryBytes = o.maxMemoryBytes;
            grid = std::move(loadDemSource(dem, listener).grid);
        }
        const double makeSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - made).count();

        settings.refuse = [&](BenchMethod m) -> std::optional<double> {
            const double need = double(grid.memoryBytes()) + passBytes + embreeBytesEstimate(benchSurfaceMethod(m), grid);
            if (need > limit) return need;
            return std::nullopt;
        };
        if (listener.step)
            settings.onStep = [&](const std::string& step) {
                listener.at(fmt::format("bench: {} ({} of {}): {}", job.name, g + 1, jobs.size(), step));
            };
        const BenchGridResult r = benchGrid(grid, settings);
        listener.at("");
        listener.print(benchGridTable(job, grid, r, makeSeconds, limit));

        json += benchGridJson(job, r, settings);
        if (job.size > 0) plotted.push_back(r);
    }
    json += "\n ],\n \"file_to_picture\": ";
    if (o.fileToPicture) {
        const int64_t largest = *std::max_element(sizes.begin(), sizes.end());
        std::function<void(const std::string&)> onStep;
        if (listener.step)
            onStep = [&](const std::string& step) {
                listener.at(fmt::format("bench: file to picture, synthetic-{}: {}", largest, step));
            };
        FileToPictureOptions fo;
        fo.size = largest;
        fo.seed = o.seed;
        fo.threads = most;
        fo.maxMemoryBytes = o.maxMemoryBytes;
        fo.limit = limit;
        fo.terracastExecutable = o.terracastExecutable;
        fo.povray = o.povray;
        fo.pairedRuns = o.pairedRuns;
        const FileToPictureResult f = fileToPicture(fo, onStep, listener.warning);
        listener.at("");
        listener.print(fileToPictureTable(f, limit));
        json += fileToPictureJson(f);
    } else {
        json += "null";
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    listener.print(fmt::format("\n({:.1f} s in all, peak memory {}; agreement: share of corner-camera rays with {}'s hit/miss "
               "verdict; x prim / x shad: rays per second over embree's in the same pass)\n",
               seconds, humanBytes(peakResidentBytes()),
               settings.methods.empty() ? "" : benchMethodName(settings.methods.front())));
    if (!o.svg.empty()) {
        std::sort(plotted.begin(), plotted.end(),
                  [](const BenchGridResult& a, const BenchGridResult& b) { return a.width < b.width; });
        writeTextFile(o.svg, benchRatesSvg(plotted, machine));
    }
    // The report goes last: its presence says the run completed.
    if (!o.json.empty()) writeTextFile(o.json, json + "}\n");
}

}  // namespace terracast
