// `accuracy` and `compare`: option parsing into typed values; the work is in measure_pipeline.
#include "cli/cli_support.h"

#include "tracer/core/errors.h"
#include "tracer/measure/measure_pipeline.h"

#include <fmt/core.h>

namespace terracast::cli {

void addMeasureCommands(CLI::App& app, Commands& commands) {
    {
        auto o = std::make_shared<AccuracyRunOptions>();
        auto* cmd = app.add_subcommand(
            "accuracy", "Measure every cell method against the long-double reference on seeded random rays");
        addDemOptions(*cmd, o->dem);
        cmd->add_option("--rays", o->rays, "Rays: camera-like, grazing and shadow-like in equal parts (default 100000)");
        cmd->add_option("--seed", o->seed, "Random seed (default 1)");
        cmd->add_option("--json", o->json, "Also write the report as JSON to this file");
        commands.push_back({cmd, [o] { return guarded([&] { runAccuracyReport(*o, ConsoleListener(false).listener()); }); }});
    }
    {
        struct Texts {
            CompareRunOptions options;
            std::string size = "640x480", sun = "315,35", methods, camera;
        };
        auto t = std::make_shared<Texts>();
        CompareRunOptions& c = t->options;
        auto* cmd = app.add_subcommand(
            "compare",
            "Trace the same rays with every method (direct and Embree) and report speed and error side by side");
        addDemOptions(*cmd, c.dem);
        cmd->add_option("--size", t->size, "Image size WxH in pixels (default 640x480)");
        cmd->add_option("--sun", t->sun, "Sun azimuth,elevation in degrees (default 315,35)");
        cmd->add_option("--exaggeration", c.exaggeration, "Vertical exaggeration factor (default 1)");
        cmd->add_option("--camera", t->camera, "As for render (default: automatic view)");
        cmd->add_option("--methods", t->methods,
                        "Comma-separated methods (default bilinear,bilinear-double,triangles,nearest,embree,embree-grid)");
        cmd->add_option("--threads", c.threads, "Worker threads, 0 = all cores (default 0)")->check(nonNegativeInteger());
        cmd->add_option("--lod", c.lodPixels,
                        "Also trace bilinear under render's --lod PIXELS level of detail, as bilinear+lodPIXELS")
            ->check(positiveNumber());
        cmd->add_option("--json", c.json, "Write the report as JSON to this file");
        cmd->add_option("--out-dir", c.outDir,
                        "Write each method's image, its difference heat map and tradeoff.svg to this folder");
        commands.push_back({cmd, [t] {
                                return guarded([&] {
                                    CompareRunOptions& o = t->options;
                                    parseSizeOption(t->size, o.width, o.height);
                                    parseSunOption(t->sun, o.sunAzimuthDeg, o.sunElevationDeg);
                                    if (!t->methods.empty()) o.methods = parseCompareMethods(t->methods);
                                    o.camera = parseCameraOption(t->camera);
                                    runCompareReport(o, ConsoleListener(false).listener());
                                });
                            }});
    }
}

}  // namespace terracast::cli
