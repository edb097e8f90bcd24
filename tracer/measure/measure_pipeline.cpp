#include "tracer/measure/measure_pipeline.h"

#include "loaders/image_io.h"
#include "loaders/output_paths.h"
#include "heightfield/height_tile.h"
#include "tracer/core/errors.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/measure/accuracy.h"
#include "tracer/measure/reports.h"
#include "tracer/terrain/memory_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

namespace terracast {

namespace fs = std::filesystem;

void runAccuracyReport(const AccuracyRunOptions& o, const RunListener& listener) {
    if (o.rays < 3 || o.rays > 100000000)
        throw InputError(fmt::format("--rays: expected 3 .. 100000000, found {}", o.rays));
    if (!o.json.empty()) checkReportPath(o.json, o.dem.path);
    const LoadedDem dem = loadDemSource(o.dem, listener);
    // Per ray: the ray and its interval (growing by doubling), the reference's answer and one method's at a
    // time, and two error lists: under 200 bytes.
    checkMemory(o.dem.path, o.dem.maxMemoryBytes, dem.grid, 200.0 * double(o.rays),
                fmt::format("measuring {} rays", o.rays));
    AccuracyOptions options;
    options.rays = o.rays;
    options.seed = o.seed;
    const auto start = std::chrono::steady_clock::now();
    const AccuracyReport r = measureAccuracy(dem.grid, options);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::string table =
        fmt::format("{}: {} x {} vertices, {} rays ({} camera, {} grazing, {} shadow), seed {}\n", dem.path,
                    dem.grid.width(), dem.grid.height(), r.rays, r.cameraRays, r.grazingRays, r.shadowRays, o.seed);
    table += fmt::format("reference: bilinear patch in long double; {} hits; {} rays ({:.3f}%) flagged ambiguous "
                         "(grazing within {:.2g} m)\n",
                         r.referenceHits, r.ambiguousRays, 100.0 * double(r.ambiguousRays) / double(r.rays),
                         r.grazingToleranceM);
    table += fmt::format("{:<16} {:>10} {:>11} {:>9} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}\n", "method", "Mrays/s",
                         "agreement", "unamb.dis", "t mean m", "t p99 m", "t max m", "rel mean", "rel p99", "rel max");
    for (const auto& m : r.methods)
        table += fmt::format(
            "{:<16} {:>10.3f} {:>11.6f} {:>9} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g} {:>10.3g}\n",
            cellMethodName(m.method), m.raysPerSecond * 1e-6, double(m.agreements) / double(r.rays),
            m.unambiguousDisagreements, m.tErrorM.mean, m.tErrorM.p99, m.tErrorM.max, m.tErrorRel.mean,
            m.tErrorRel.p99, m.tErrorRel.max);
    listener.print(table);
    listener.tell(fmt::format("accuracy of {} methods on {} rays each (plus the reference) in {:.2f} s, peak memory {}",
                              r.methods.size(), r.rays, seconds, humanBytes(peakResidentBytes())));
    if (!o.json.empty())
        writeTextFile(o.json, accuracyJson({dem.path, dem.grid.width(), dem.grid.height()}, o.seed, r));
}

void runCompareReport(const CompareRunOptions& o, const RunListener& listener) {
    std::error_code ec;
    if (!o.json.empty()) checkReportPath(o.json, o.dem.path);
    checkViewValues(o.exaggeration, o.sunElevationDeg);
    LoadedDem dem = loadDemSource(o.dem, listener, false, o.exaggeration);
    CompareSettings cs;
    cs.methods = o.methods;
    cs.lodPixels = o.lodPixels;
    cs.render = makeView(dem.grid, o.width, o.height, o.sunAzimuthDeg, o.sunElevationDeg, o.camera, o.threads);
    {
        // Every method keeps its picture and hit distances (12 + 8 bytes per pixel) plus per-pass buffers;
        // the largest acceleration structure is alive one at a time.
        double embree = 0.0;
        for (SurfaceMethod m : cs.methods) embree = std::max(embree, embreeBytesEstimate(m, dem.grid));
        const double pixels = double(o.width) * o.height;
        checkMemory(o.dem.path, o.dem.maxMemoryBytes, dem.grid,
                    pixels * (20.0 * double(cs.methods.size() + 1) + 120.0) + embree +
                        (o.lodPixels > 0.0 ? levelOfDetailBytes(dem.grid) : 0.0),
                    fmt::format("comparing {} methods at {}x{}", cs.methods.size(), o.width, o.height));
    }
    // No file compare writes may be the DEM, however the paths are spelt (links, "..", hard links).
    if (!o.outDir.empty()) {
        for (SurfaceMethod m : cs.methods)
            for (const char* prefix : {"", "diff-"})
                checkNotInput((fs::path(o.outDir) / (prefix + std::string(surfaceMethodName(m)) + ".png")).string(),
                              o.dem.path, "--out-dir file");
        checkNotInput((fs::path(o.outDir) / "tradeoff.svg").string(), o.dem.path, "--out-dir file");
    }
    // The output folder is made only once the input has loaded, so a bad input leaves nothing behind; a folder
    // made here is removed again if the run ends without writing into it (a failure, Ctrl-C).
    struct MadeFolder {
        fs::path path;
        ~MadeFolder() {
            std::error_code ignored;
            if (!path.empty()) fs::remove(path, ignored);  // only while empty
        }
    } madeFolder;
    if (!o.outDir.empty() && !fs::is_directory(o.outDir, ec)) {
        if (!fs::create_directories(o.outDir, ec))
            throw InputError(fmt::format("--out-dir: cannot create folder '{}' ({})", o.outDir, ec.message()));
        madeFolder.path = o.outDir;
    }

    if (listener.step)
        cs.onMethod = [&](SurfaceMethod m, size_t k, size_t n) {
            listener.at(fmt::format("compare: tracing {} ({} of {})", surfaceMethodName(m), k + 1, n));
        };
    const auto start = std::chrono::steady_clock::now();
    const CompareReport r = compareSurfaces(dem.grid, cs);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    listener.at("");

    std::string table = fmt::format(
        "{}: {} x {} vertices; {} x {} camera rays plus one shadow ray per lit-facing hit; reference {}\n", dem.path,
        dem.grid.width(), dem.grid.height(), r.width, r.height, surfaceMethodName(r.reference));
    table += fmt::format("{:<16} {:>8} {:>11} {:>9} {:>9} {:>10} {:>10} {:>10} {:>10} {:>9} {:>8} {:>7} {:>7}\n",
                         "method", "build s", "memory", "prim M/s", "shad M/s", "agreement", "t mean m", "t p99 m",
                         "t max m", "rmse", "psnr dB", "x prim", "x shad");
    for (const auto& m : r.methods)
        table += fmt::format("{:<16} {:>8.3f} {:>11} {:>9.3f} {:>9.3f} {:>10.6f} {:>10.3g} {:>10.3g} {:>10.3g} "
                             "{:>9.5f} {:>8.1f} {:>7.2f} {:>7.2f}\n",
                             comparisonName(m), m.buildSeconds, humanBytes(double(m.memoryBytes)),
                             m.primaryRaysPerSecond * 1e-6, m.shadowRaysPerSecond * 1e-6, m.hitAgreement,
                             m.tErrorM.mean, m.tErrorM.p99, m.tErrorM.max, m.imageRmse, m.imagePsnrDb,
                             m.ratioToEmbreePrimary, m.ratioToEmbreeShadow);
    table += fmt::format("({:.1f} s in all, peak memory {}; x prim / x shad: rays per second over embree's, this run)\n",
                         seconds, humanBytes(peakResidentBytes()));
    if (dem.grid.tiled()) {
        // A DEM held as tiles: what each method read of it (a level of detail's coarser grids read every tile once).
        table += "tiles read from the DEM:";
        for (const auto& m : r.methods) table += fmt::format(" {} {}{}", comparisonName(m), m.tileLoads, &m == &r.methods.back() ? "" : ",");
        table += fmt::format(" (of {} tiles, a cache of {})\n", TileLayout{dem.grid.width(), dem.grid.height()}.tileCount(),
                             humanBytes(double(dem.grid.tileSource()->cacheBudgetBytes())));
    }
    listener.print(table);

    if (!o.outDir.empty()) {
        const MethodComparison* ref = nullptr;
        for (const auto& m : r.methods)
            if (m.method == r.reference && m.lodPixels == 0.0) ref = &m;
        for (const auto& m : r.methods) {
            const std::string name = comparisonName(m);
            writeImage((fs::path(o.outDir) / (name + ".png")).string(), RgbImage{m.image.width, m.image.height, m.image.rgb});
            if (&m == ref) continue;
            const Film heat = differenceHeatMap(m, *ref);
            writeImage((fs::path(o.outDir) / ("diff-" + name + ".png")).string(), RgbImage{heat.width, heat.height, heat.rgb});
        }
        writeTextFile((fs::path(o.outDir) / "tradeoff.svg").string(), tradeoffSvg(r));
    }
    // The report goes last: its presence says the run completed.
    if (!o.json.empty()) writeTextFile(o.json, compareJson({dem.path, dem.grid.width(), dem.grid.height()}, r));
}

}  // namespace terracast
