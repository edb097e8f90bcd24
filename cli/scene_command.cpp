// `scene`: option parsing into typed values; the work is renderSceneFile.
#include "cli/cli_support.h"

#include "tracer/core/errors.h"
#include "tracer/scene/scene_pipeline.h"

#include <fmt/core.h>

#include <cstdint>

namespace terracast::cli {

void addSceneCommand(CLI::App& app, Commands& commands) {
    struct Texts {
        SceneRunOptions options;
        std::string debugPixel, size, focusPixel, method, sampler, filter;
        bool quiet = false;
        CLI::Option* adaptive = nullptr;
    };
    auto t = std::make_shared<Texts>();
    SceneRunOptions& scene = t->options;
    auto* cmd =
        app.add_subcommand("scene", "Render a TOML scene: terrain, spheres, boxes, polygons, water, mirrors, glass");
    cmd->add_option("SCENE", scene.path, "Scene file (TOML); see docs/scene-format.md")->required();
    cmd->add_option("-o,--output", scene.output, "Output image .png or .exr (overrides render.output)");
    cmd->add_flag("--allow-paths", scene.anyPath,
                  "Let the scene file name files outside its own folder, absolute paths and GDAL virtual or network "
                  "paths (refused by default: a scene file may come from anyone)");
    cmd->add_option("--size", t->size, "Image size WxH (overrides render.width and render.height)");
    cmd->add_option("--spp", scene.samples, "Samples per pixel (overrides render.samples)")->check(CLI::Range(1, 65536));
    cmd->add_option("--threads", scene.threads, "Worker threads, 0 = all cores")->check(nonNegativeInteger());
    cmd->add_option("--seed", scene.seed, "Random seed (overrides render.seed)")
        ->check(nonNegativeInteger(int64_t(1) << 53));
    cmd->add_option("--method", t->method, "Height-field method for every terrain (overrides the file)");
    cmd->add_option("--debug-pixel", t->debugPixel, "Print the ray tree of pixel X,Y (and render only with -o)");
    cmd->add_option("--sampler", t->sampler, "Sample pattern: regular, random, stratified, poisson, best-candidate");
    cmd->add_option("--filter", t->filter, "Pixel filter: box, tent, gaussian");
    cmd->add_option("--focus", t->focusPixel, "Thin lens: focus on what pixel X,Y sees");
    t->adaptive = cmd->add_option("--adaptive", scene.adaptiveError,
                                  "Adaptive sampling up to --spp samples, until the standard error of a "
                                  "pixel's luminance is below this (e.g. 0.002)");
    addMaxMemoryOption(*cmd, scene.maxMemoryBytes,
                       "Refuse scenes estimated to need more memory than this (default: 80% of physical memory)");
    cmd->add_flag("-q,--quiet", t->quiet, "No progress or summary on stderr");
    commands.push_back({cmd, [t] {
                            return guarded([&] {
                                SceneRunOptions& s = t->options;
                                if (!t->debugPixel.empty()) {
                                    parsePixelOption(t->debugPixel, "--debug-pixel", s.debugX, s.debugY);
                                    s.debugPixel = true;
                                }
                                if (!t->focusPixel.empty()) {
                                    parsePixelOption(t->focusPixel, "--focus", s.focusX, s.focusY);
                                    s.focusPixel = true;
                                }
                                if (!t->size.empty()) parseSizeOption(t->size, s.width, s.height);
                                if (!t->method.empty()) s.method = parseMethodOption(t->method);
                                if (!t->sampler.empty())
                                    s.sampler = parseNamedOption(t->sampler, "--sampler", parseSamplePattern,
                                                                 samplePatternList());
                                if (!t->filter.empty())
                                    s.filter = parseNamedOption(t->filter, "--filter", parseFilterKind, filterKindList());
                                s.adaptive = t->adaptive->count() > 0;
                                const ConsoleListener console(t->quiet);
                                renderSceneFile(s, console.listener());
                            });
                        }});
}

}  // namespace terracast::cli
