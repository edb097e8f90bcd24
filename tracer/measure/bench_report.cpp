#include "tracer/measure/bench_pipeline.h"

#include "tracer/core/text.h"
#include "tracer/measure/reports.h"

#include <fmt/format.h>

#include <cmath>

namespace terracast {

namespace {

std::string benchRatioJson(double primary, double shadow) {
    return fmt::format("{{\"primary\": {}, \"shadow\": {}}}", jsonNumber(primary), jsonNumber(shadow));
}

// A method the memory guard left out, as the JSON reports it.
std::string skippedMethodJson(BenchMethod method, double neededBytes) {
    return fmt::format("{{\"name\": \"{}\", \"skipped\": true, \"memory_needed_bytes\": {}}}",
                       benchMethodName(method), jsonNumber(neededBytes));
}

}  // namespace

// One grid's object in the bench report: the shape of docs/architecture.md, "Contracts", with the corner
// camera at the most threads as each method's headline numbers and every pass listed under "passes".
std::string benchGridJson(const BenchJob& job, const BenchGridResult& r, const BenchSettings& s) {
    // The agreement's reference: the first method that was measured (a skipped one has no hits).
    const char* reference = "";
    for (const auto& m : r.methods)
        if (!m.skipped) {
            reference = benchMethodName(m.method);
            break;
        }
    std::string j = fmt::format("{{\"dem\": {}, \"synthetic\": {}, \"width\": {}, \"height\": {}, \"cells\": {}, "
                                "\"image_width\": {}, \"image_height\": {}, \"rays\": {}, \"reference\": \"{}\", "
                                "\"skipped\": false,\n  \"methods\": [",
                                jsonString(job.name), job.size > 0 ? "true" : "false", r.width, r.height, r.cells,
                                s.width, s.height, int64_t(s.width) * s.height, reference);
    for (size_t k = 0; k < r.methods.size(); ++k) {
        const auto& m = r.methods[k];
        j += k ? "," : "";
        if (m.skipped) {
            j += "\n   " + skippedMethodJson(m.method, m.neededBytes);
            continue;
        }
        const BenchPass* head = nullptr;
        for (const auto& p : m.passes)
            if (p.camera == BenchCamera::Corner && (!head || p.threads > head->threads)) head = &p;
        if (!head && !m.passes.empty()) head = &m.passes.front();
        const BenchPass none{};
        if (!head) head = &none;
        j += fmt::format("\n   {{\"name\": \"{}\", \"skipped\": false, \"build_s\": {}, \"memory_bytes\": {}, "
                         "\"peak_memory_bytes\": {}, \"bytes_per_cell\": {}, \"peak_bytes_per_cell\": {}, "
                         "\"hit_agreement\": {}, \"threads\": {}, \"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, "
                         "\"ratio_to_embree\": {},\n    \"passes\": [",
                         benchMethodName(m.method), jsonNumber(m.buildSeconds), m.memoryBytes, m.peakMemoryBytes,
                         jsonNumber(m.bytesPerCell), jsonNumber(m.peakBytesPerCell), jsonNumber(m.hitAgreement),
                         head->threads, jsonNumber(head->primaryRaysPerSecond), jsonNumber(head->shadowRaysPerSecond),
                         benchRatioJson(head->ratioToEmbreePrimary, head->ratioToEmbreeShadow));
        for (size_t q = 0; q < m.passes.size(); ++q) {
            const auto& p = m.passes[q];
            j += fmt::format("{}\n     {{\"camera\": \"{}\", \"threads\": {}, \"primary_rays\": {}, \"shadow_rays\": {}, "
                             "\"primary_rays_per_s\": {}, \"shadow_rays_per_s\": {}, \"ratio_to_embree\": {}}}",
                             q ? "," : "", benchCameraName(p.camera), p.threads, p.primaryRays, p.shadowRays,
                             jsonNumber(p.primaryRaysPerSecond), jsonNumber(p.shadowRaysPerSecond),
                             benchRatioJson(p.ratioToEmbreePrimary, p.ratioToEmbreeShadow));
        }
        j += "]}";
    }
    return j + "]}";
}

std::string benchGridTable(const BenchJob& job, const HeightGrid& grid, const BenchGridResult& r, double makeSeconds,
                           double limit) {
    std::string out = fmt::format(
        "\n{} ({} x {} vertices, {} cells of {:.4g} x {:.4g} m, heights {:.0f} to {:.0f} m; {} in {:.2f} s)\n", job.name,
        grid.width(), grid.height(), r.cells, grid.cellSizeXM(), grid.cellSizeYM(), grid.minHeightM(),
        grid.maxHeightM(), job.size > 0 ? "made" : "loaded", makeSeconds);
    out += fmt::format("{:<14} {:>8} {:>8} {:>8} {:>9}  {:<8} {:>3} {:>10} {:>10} {:>7} {:>7}\n", "method", "build s",
                       "B/cell", "peak B", "agreement", "camera", "thr", "prim Mr/s", "shad Mr/s", "x prim", "x shad");
    for (const auto& m : r.methods) {
        if (m.skipped) {
            out += fmt::format("{:<14} skipped: needs about {}, more than the {} limit (--max-memory)\n",
                               benchMethodName(m.method), humanBytes(m.neededBytes), humanBytes(limit));
            continue;
        }
        for (size_t q = 0; q < m.passes.size(); ++q) {
            const auto& p = m.passes[q];
            const std::string head =
                q == 0 ? fmt::format("{:<14} {:>8.3f} {:>8.1f} {:>8.1f} {:>9.6f}", benchMethodName(m.method),
                                     m.buildSeconds, m.bytesPerCell, m.peakBytesPerCell, m.hitAgreement)
                       : fmt::format("{:<14} {:>8} {:>8} {:>8} {:>9}", "", "", "", "", "");
            out += fmt::format("{}  {:<8} {:>3} {:>10.3f} {:>10.3f} {:>7.2f} {:>7.2f}\n", head, benchCameraName(p.camera),
                               p.threads, p.primaryRaysPerSecond * 1e-6, p.shadowRaysPerSecond * 1e-6,
                               p.ratioToEmbreePrimary, p.ratioToEmbreeShadow);
        }
    }
    return out;
}

std::string fileToPictureJson(const FileToPictureResult& f) {
    std::string j = fmt::format("{{\"dem\": {}, \"width\": {}, \"height\": {}, \"cell_size_m\": {}, \"skipped\": {}",
                                jsonString(f.name), f.size, f.size, jsonNumber(f.render.dem.imageCellSizeM),
                                f.skipped ? "true" : "false");
    if (f.skipped) return j + fmt::format(", \"memory_needed_bytes\": {}, \"methods\": []}}", jsonNumber(f.neededBytes));
    j += fmt::format(", \"make_s\": {}, \"height_map_write_s\": {}, \"height_map_bytes\": {}, \"image_width\": {}, "
                     "\"image_height\": {}, \"threads\": {}, \"sky\": {}, \"sky_samples\": {},\n  \"methods\": [",
                     jsonNumber(f.makeSeconds), jsonNumber(f.heightMapSeconds), f.heightMapBytes, f.render.width,
                     f.render.height, f.threads, jsonString(skyKindName(f.render.sky)), f.render.skySamples < 0 ? 4 : f.render.skySamples);
    for (size_t k = 0; k < f.runs.size(); ++k) {
        const auto& r = f.runs[k];
        j += k ? ",\n   " : "\n   ";
        if (r.skipped) {
            j += skippedMethodJson(r.method, r.neededBytes);
            continue;
        }
        j += fmt::format("{{\"name\": \"{}\", \"skipped\": false, \"load_s\": {}, \"pyramid_s\": {}, \"build_s\": {}, "
                         "\"render_s\": {}, \"write_s\": {}, \"total_s\": {}, \"picture_bytes\": {}, \"picture_width\": {}, "
                         "\"picture_height\": {}}}",
                         benchMethodName(r.method), jsonNumber(r.seconds.load), jsonNumber(r.seconds.pyramid),
                         jsonNumber(r.seconds.build),
                         jsonNumber(r.seconds.render), jsonNumber(r.seconds.write), jsonNumber(r.seconds.total),
                         r.pictureBytes, r.pictureWidth, r.pictureHeight);
    }
    j += fmt::format("],\n  \"total_ratio_embree_to_bilinear\": {}, \"picture_mean_abs_diff\": {},\n  \"whole_process\": ",
                     jsonNumber(f.totalRatio), jsonNumber(f.pictureMeanAbsDiff));
    const WholeProcessComparison& w = f.wholeProcess;
    if (!w.ran) return j + fmt::format("{{\"ran\": false, \"why\": {}}}}}", jsonString(w.skippedWhy));
    const auto runs = [](const WholeProcessRuns& r) {
        std::string list;
        for (size_t k = 0; k < r.seconds.size(); ++k) list += (k ? ", " : "") + jsonNumber(r.seconds[k]);
        return fmt::format("{{\"seconds\": [{}], \"median_s\": {}, \"best_s\": {}, \"peak_memory_bytes\": {}}}", list,
                           jsonNumber(r.medianSeconds), jsonNumber(r.bestSeconds), jsonNumber(r.peakBytes));
    };
    return j + fmt::format("{{\"ran\": true, \"povray_version\": {}, \"terracast\": {}, \"povray\": {}, "
                           "\"speedup_over_povray\": {}, \"grid_bytes\": {}, \"picture_bytes\": {}, "
                           "\"peak_over_grid_and_picture\": {}, \"silhouette_pixels\": {}, "
                           "\"silhouette_mismatches\": {}}}}}",
                           jsonString(w.povrayVersion), runs(w.terracast), runs(w.povray), jsonNumber(w.speedup),
                           jsonNumber(w.gridBytes), jsonNumber(w.pictureBytes), jsonNumber(w.peakOverGridAndPicture),
                           w.silhouettePixels, w.silhouetteMismatches);
}

std::string fileToPictureTable(const FileToPictureResult& f, double limit) {
    std::string out;
    if (f.skipped) {
        out += fmt::format("\nfile to picture ({}): skipped: making the height map needs about {}, more than the {} limit "
                   "(--max-memory)\n",
                   f.name, humanBytes(f.neededBytes), humanBytes(limit));
        return out;
    }
    const DemRenderOptions& r = f.render;
    out += fmt::format("\nfile to picture: {} made in {:.2f} s, written as a 16-bit PNG height map ({}) in {:.2f} s; then "
               "`render FILE.png --cell-size {:g} --size {}x{} --threads {} --method M -o OUT.png` (sun {:g},{:g}, "
               "shadows, {} sky, {} sky rays per hit)\n",
               f.name, f.makeSeconds, humanBytes(double(f.heightMapBytes)), f.heightMapSeconds, r.dem.imageCellSizeM,
               r.width, r.height, f.threads, r.sunAzimuthDeg, r.sunElevationDeg, skyKindName(r.sky),
               r.skySamples < 0 ? 4 : r.skySamples);
    out += fmt::format("{:<14} {:>8} {:>10} {:>8} {:>8} {:>8} {:>8}\n", "method", "load s", "(pyramid)", "build s",
                       "render s", "write s", "total s");
    for (const auto& run : f.runs) {
        if (run.skipped) {
            out += fmt::format("{:<14} skipped: needs about {}, more than the {} limit (--max-memory)\n",
                       benchMethodName(run.method), humanBytes(run.neededBytes), humanBytes(limit));
            continue;
        }
        out += fmt::format("{:<14} {:>8.3f} {:>10.3f} {:>8.3f} {:>8.3f} {:>8.3f} {:>8.3f}\n", benchMethodName(run.method),
                   run.seconds.load, run.seconds.pyramid, run.seconds.build, run.seconds.render, run.seconds.write,
                   run.seconds.total);
    }
    if (std::isfinite(f.totalRatio))
        out += fmt::format("total embree / bilinear: {:.2f}; the two pictures differ by {:.2f} of 255 on average (8-bit sRGB)\n",
                   f.totalRatio, f.pictureMeanAbsDiff);
    const WholeProcessComparison& w = f.wholeProcess;
    if (!w.ran) return out + fmt::format("whole processes against POV-Ray: not run: {}\n", w.skippedWhy);
    const auto seconds = [](const WholeProcessRuns& r) {
        std::string list;
        for (size_t k = 0; k < r.seconds.size(); ++k) list += fmt::format("{}{:.2f}", k ? ", " : "", r.seconds[k]);
        return list;
    };
    out += fmt::format("whole processes, {} paired runs taking turns first (the same PNG, camera, {}x{} picture, sun, and "
                       "one shadow ray per hit; terracast `render --method bilinear --sky-samples 0 --no-base`, {} "
                       "`height_field {{ png smooth }}`):\n",
                       w.terracast.seconds.size(), r.width, r.height, w.povrayVersion.empty() ? "POV-Ray" : w.povrayVersion);
    out += fmt::format("{:<10} {:>10} {:>10} {:>12}   runs (s)\n", "program", "median s", "best s", "peak memory");
    // The peak comes from GNU time; without it, unknown.
    const auto peak = [](double bytes) { return std::isnan(bytes) ? std::string("unknown") : humanBytes(bytes); };
    out += fmt::format("{:<10} {:>10.3f} {:>10.3f} {:>12}   {}\n", "terracast", w.terracast.medianSeconds,
                       w.terracast.bestSeconds, peak(w.terracast.peakBytes), seconds(w.terracast));
    out += fmt::format("{:<10} {:>10.3f} {:>10.3f} {:>12}   {}\n", "POV-Ray", w.povray.medianSeconds, w.povray.bestSeconds,
                       peak(w.povray.peakBytes), seconds(w.povray));
    out += fmt::format("terracast is {:.2f} times sooner (medians); its peak is {} the grid ({}) plus the picture "
                       "({}); silhouettes of `triangles` and POV-Ray differ at {} of {} pixels on the terrain\n",
                       w.speedup,
                       std::isnan(w.peakOverGridAndPicture) ? std::string("unknown against")
                                                            : fmt::format("{:.2f} times", w.peakOverGridAndPicture),
                       humanBytes(w.gridBytes), humanBytes(w.pictureBytes), w.silhouetteMismatches, w.silhouettePixels);
    return out;
}

}  // namespace terracast
