// From a scene file to a picture: read the file, apply the command line's overrides, load what it names under
// the memory limit, place suns given by a time, build the scene and its camera, then render (or trace one
// pixel's ray tree) and write the picture atomically.
#pragma once

#include "tracer/core/listener.h"
#include "tracer/core/surface_method.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"
#include "tracer/scene/scene_description.h"
#include "tracer/scene/scene_renderer.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terracast {

// The renderer's settings for a scene file's [render] table.
SceneRenderSettings sceneRenderSettings(const RenderDescription& render);

// `scene SCENE.toml`: the file's settings, with these overriding them where given.
struct SceneRunOptions {
    std::string path;                          // the scene file
    std::string output;                        // overrides render.output
    bool anyPath = false;                      // the file may name paths outside its folder (--allow-paths)
    int width = 0, height = 0;                 // override render.width/height when > 0
    int samples = 0;                           // overrides render.samples when > 0
    int threads = -1;                          // overrides render.threads when >= 0
    int64_t seed = -1;                         // overrides render.seed when >= 0
    std::optional<SurfaceMethod> method;       // overrides every height field's method when set
    std::optional<SamplePattern> sampler;      // overrides render.sampler when set
    std::optional<FilterKind> filter;          // overrides render.filter when set
    bool adaptive = false;                     // adaptive sampling, up to the samples per pixel
    double adaptiveError = 0.002;              // adaptive: standard error of the luminance to reach
    bool focusPixel = false;                   // thin lens: focus on what pixel (focusX, focusY) sees
    int focusX = 0, focusY = 0;
    bool debugPixel = false;                   // print one pixel's ray tree to the listener's output
    int debugX = 0, debugY = 0;
    double maxMemoryBytes = 0.0;               // 0 = 80% of physical memory
    bool write = true;                         // false: return the picture instead of writing it (no output
                                               // needed; the Python module)
};

// Renders the scene file; the summary line goes to the listener's note, a debug pixel's ray tree to its
// output. Throws InputError for bad input, Cancelled when interrupted. Returns the picture when
// options.write is false, else an empty film.
Film renderSceneFile(const SceneRunOptions& options, const RunListener& listener);

// One pixel's ray tree, one ray per line, indented by depth.
std::string formatRayTree(int x, int y, const std::vector<RayRecord>& tree);

}  // namespace terracast
