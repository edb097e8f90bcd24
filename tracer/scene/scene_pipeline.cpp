#include "tracer/scene/scene_pipeline.h"

#include "loaders/image_io.h"
#include "loaders/output_paths.h"
#include "loaders/scene_assets.h"
#include "loaders/scene_file.h"
#include "tracer/core/errors.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/scene/scene.h"
#include "tracer/camera/camera.h"
#include "tracer/terrain/memory_model.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace terracast {

SceneRenderSettings sceneRenderSettings(const RenderDescription& r) {
    SceneRenderSettings s;
    s.width = r.width;
    s.height = r.height;
    s.samples = r.samples;
    s.maxDepth = r.maxDepth;
    s.minWeight = r.minWeight;
    s.seed = r.seed;
    s.threads = r.threads;
    s.exposure = r.exposure;
    s.pattern = r.sampler;
    s.filter = PixelFilter::defaults(r.filter);
    return s;
}

namespace {

std::string vecText(const glm::dvec3& v) { return fmt::format("({:.3f}, {:.3f}, {:.3f})", v.x, v.y, v.z); }

}  // namespace

std::string formatRayTree(int x, int y, const std::vector<RayRecord>& tree) {
    const auto rgb = [](const glm::vec3& v) { return fmt::format("({:.4g}, {:.4g}, {:.4g})", v.r, v.g, v.b); };
    std::string out = fmt::format("ray tree of pixel {},{} ({} rays; each adds its share to the light leaving its "
                                  "parent's hit)\n",
                                  x, y, tree.size());
    for (const RayRecord& r : tree) {
        out += fmt::format("{:{}}{} from {} dir {} -> {}", "", 2 * r.depth, rayKindName(r.kind), vecText(r.origin),
                           vecText(r.dir), r.hit);
        if (std::isfinite(r.t) && r.kind != RayKind::Shadow) out += fmt::format(" at {:.4g} m", r.t);
        out += fmt::format("  weight ({:.3g}, {:.3g}, {:.3g})", r.weight.r, r.weight.g, r.weight.b);
        if (r.kind == RayKind::Shadow) {
            // The fraction of the light that gets through, and the light it brings (zero when blocked).
            out += fmt::format(" transmittance {} adds {}\n", rgb(r.contribution), rgb(r.share));
            continue;
        }
        if (r.kind == RayKind::SkyVisibility) {
            out += fmt::format(" adds {}\n", rgb(r.share));
            continue;
        }
        // What the ray returns: the light leaving its hit (the sky's light without rays, plus its children's
        // shares), times what crosses the water, glass or air on the way, plus the haze the air adds.
        out += fmt::format(" returns {} = at the hit {}", rgb(r.atHit * r.passed + r.inscattered), rgb(r.atHit));
        if (r.skyLight != glm::vec3(0.0f)) out += fmt::format(" (sky light {} + the rays below)", rgb(r.skyLight));
        if (r.passed != glm::vec3(1.0f)) out += fmt::format(" x passed {}", rgb(r.passed));
        if (r.inscattered != glm::vec3(0.0f)) out += fmt::format(" + haze {}", rgb(r.inscattered));
        out += fmt::format(", adds {}{}\n", rgb(r.share), r.kind == RayKind::Primary ? " to the pixel" : "");
    }
    return out;
}

Film renderSceneFile(const SceneRunOptions& o, const RunListener& listener) {
    SceneDescription d = loadSceneFile(o.path, o.anyPath);
    RenderDescription& r = d.render;
    if (!o.output.empty()) r.output = o.output;
    if (o.width > 0) r.width = o.width;
    if (o.height > 0) r.height = o.height;
    if (o.samples > 0) r.samples = o.samples;
    if (o.threads >= 0) r.threads = o.threads;
    if (o.seed >= 0) r.seed = uint64_t(o.seed);
    if (o.method)
        for (auto& obj : d.objects) obj.method = *o.method;
    if (o.sampler) r.sampler = *o.sampler;
    if (o.filter) r.filter = *o.filter;
    if (o.adaptive && !(o.adaptiveError > 0.0))
        throw InputError(fmt::format("--adaptive: expected an error > 0, found {}", o.adaptiveError));
    if (o.focusPixel && d.camera.kind != CameraKind::ThinLens)
        throw InputError(o.path + ": --focus needs a thin-lens camera (type = \"thin-lens\" in [camera])");
    if (o.focusPixel && (o.focusX < 0 || o.focusY < 0 || o.focusX >= r.width || o.focusY >= r.height))
        throw InputError(fmt::format("--focus: expected a pixel inside {}x{}, found {},{}", r.width, r.height, o.focusX,
                                     o.focusY));
    // With --debug-pixel only an output named on the command line is rendered, never the file's own.
    const bool writesImage = o.write && (!o.debugPixel || !o.output.empty());
    if (r.output.empty() && writesImage)
        throw InputError(o.path + ": no output image: give -o OUT or set output in [render]");
    if (o.debugPixel && (o.debugX < 0 || o.debugY < 0 || o.debugX >= r.width || o.debugY >= r.height))
        throw InputError(fmt::format("--debug-pixel: expected a pixel inside {}x{}, found {},{}", r.width, r.height,
                                     o.debugX, o.debugY));
    if (writesImage) {
        checkOutputPath(r.output, o.path, {".png", ".exr"}, "the scene file");
        for (const auto& obj : d.objects)
            if (obj.kind == ObjectKind::HeightField) checkNotInput(r.output, obj.filePath, "output path", "a height field's DEM");
        for (const auto& m : d.materials)
            if (!m.drapePath.empty()) checkNotInput(r.output, m.drapePath, "output path", "a material's drape");
        for (const auto& m : d.materials)
            if (!m.texturePath.empty()) checkNotInput(r.output, m.texturePath, "output path", "a material's texture");
        if (!d.sky.imagePath.empty()) checkNotInput(r.output, d.sky.imagePath, "output path", "the sky's image");
    }

    const double limit = memoryLimitBytes(o.maxMemoryBytes);
    const LoadedSceneAssets loaded = loadSceneAssets(d, limit);
    for (const auto& w : d.warnings) listener.warn(w);
    for (const auto& w : loaded.warnings) listener.warn(w);
    for (const auto& line : placeTimedSuns(d, loaded)) listener.tell(line);
    double embreeBytes = 0.0;
    for (size_t k = 0, g = 0; k < d.objects.size(); ++k)
        if (d.objects[k].kind == ObjectKind::HeightField)
            embreeBytes += embreeBytesEstimate(d.objects[k].method, *loaded.assets.grids[g++]);
    // What the process holds now (libraries, the loaded assets), Embree's scenes, the film and the picture's
    // encoding.
    if (writesImage) prepareImageWriter(r.output);
    const double held = currentResidentBytes();
    const double need = held + embreeBytes + double(r.width) * r.height * (kFilmBytesPerPixel + kEncodeBytesPerPixel);
    if (need > limit)
        throw InputError(fmt::format("{}: rendering {}x{} needs about {} ({} held already), more than the {} limit "
                                     "(--max-memory)",
                                     o.path, r.width, r.height, humanBytes(need), humanBytes(held), humanBytes(limit)));

    const Scene scene(d, loaded.assets);
    const double aspect = double(r.width) / double(r.height);
    ViewCamera camera = makeSceneCamera(scene, d.camera, aspect);
    if (o.focusPixel) {
        const auto focus = focusDistanceAt(scene, camera, o.focusX, o.focusY, r.width, r.height);
        if (!focus)
            throw InputError(fmt::format("--focus: pixel {},{} sees the sky; pick a pixel on an object", o.focusX,
                                         o.focusY));
        d.camera.focusDistanceM = *focus;
        camera = makeSceneCamera(scene, d.camera, aspect);
        listener.tell(fmt::format("focus distance {:.2f} m (pixel {},{})", *focus, o.focusX, o.focusY));
    }
    SceneRenderSettings s = sceneRenderSettings(r);
    static_cast<PixelSampling&>(s) = PixelSampling::make(r.samples, r.sampler, r.filter, o.adaptive, o.adaptiveError);

    if (o.debugPixel) {
        std::vector<RayRecord> tree;
        const glm::vec3 v = tracePixel(scene, camera, s, o.debugX, o.debugY, &tree);
        listener.print(formatRayTree(o.debugX, o.debugY, tree));
        listener.print(fmt::format("pixel value ({:.4g}, {:.4g}, {:.4g})\n", v.r, v.g, v.b));
        if (!writesImage && o.write) return {};
    }

    s.progress = listener.progress;
    SceneRayStats stats;
    Film film = renderScene(scene, camera, s, &stats);
    if (!o.write) return film;
    writeImage(r.output, RgbImage{film.width, film.height, std::move(film.rgb)});
    listener.tell(fmt::format(
        "rendered {} ({}x{}, {} spp{}) in {:.2f} s: {} primary, {} shadow, {} reflection, {} refraction, {} "
        "sky-visibility rays ({} camera, reflection and refraction rays met no object), {:.2f} Mrays/s, peak memory {}",
        r.output, r.width, r.height,
        s.adaptive ? fmt::format("{:.1f}", double(stats.samples) / (double(r.width) * r.height))
                   : std::to_string(std::max(1, s.samples)),
        s.adaptive ? fmt::format(" on average, adaptive up to {}", s.rule.maxSamples) : "", stats.seconds, stats.primary,
        stats.shadow, stats.reflection, stats.refraction, stats.skyVisibility, stats.skyRays,
        stats.seconds > 0 ? double(stats.total()) / stats.seconds * 1e-6 : 0.0, humanBytes(peakResidentBytes())));
    return {};
}

}  // namespace terracast
