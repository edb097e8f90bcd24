// From a DEM file to the measurements of `accuracy` and `compare`: load, measure, print the table to the
// listener's output, and write the JSON report (and compare's pictures) last, so that their presence says
// the run completed.
#pragma once

#include "tracer/core/listener.h"
#include "tracer/core/surface_method.h"
#include "tracer/measure/compare.h"
#include "tracer/terrain/camera.h"
#include "tracer/terrain/dem_pipeline.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace terracast {

// `accuracy DEM`
struct AccuracyRunOptions {
    DemSource dem;
    int64_t rays = 100000;             // seeded rays: camera-like, grazing and shadow-like in equal parts
    uint64_t seed = 1;                 // random seed
    std::string json;                  // write the report as JSON here; empty = none
};
void runAccuracyReport(const AccuracyRunOptions& options, const RunListener& listener);

// `compare DEM`
struct CompareRunOptions {
    DemSource dem;
    int width = 640;                   // pixels
    int height = 480;                  // pixels
    double sunAzimuthDeg = 315.0;      // clockwise from north
    double sunElevationDeg = 35.0;     // above the horizon
    double exaggeration = 1.0;         // vertical scale factor
    std::optional<PinholeCamera> camera;  // none = the automatic view
    std::vector<SurfaceMethod> methods = compareMethods();  // measured; the reference is always added
    int threads = 0;                   // 0 = all cores
    double lodPixels = 0.0;            // > 0: also the bilinear method under this level of detail
    std::string json;                  // report file; empty = none
    std::string outDir;                // folder for images, heat maps and tradeoff.svg; empty = none
};
void runCompareReport(const CompareRunOptions& options, const RunListener& listener);

}  // namespace terracast
