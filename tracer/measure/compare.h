// `compare`: the same camera rays and one shadow ray per hit, traced by every method, measured side by side
// against the reference (the bilinear patch in double).
#pragma once

#include "heightfield/height_grid.h"
#include "tracer/measure/accuracy.h"
#include "tracer/sampling/film.h"
#include "tracer/terrain/surface.h"
#include "tracer/terrain/terrain_renderer.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace terracast {

// The methods `compare` runs, in report order.
const std::vector<SurfaceMethod>& compareMethods();
// Parses "bilinear,embree" into surface methods, in the order given; throws InputError naming --methods.
std::vector<SurfaceMethod> parseCompareMethods(const std::string& text);

struct CompareSettings {
    TerrainRenderSettings render;                          // size, camera, sun, threads (method unused)
    std::vector<SurfaceMethod> methods = compareMethods();  // measured in this order
    SurfaceMethod reference = SurfaceMethod::BilinearDouble;  // compared against; measured too
    // > 0: also the bilinear method under this level of detail (TerrainSurface::setLevelOfDetail), seen from the
    // camera, as the last entry.
    double lodPixels = 0.0;
    // Called before each method is traced, with its position and the number of methods (for progress).
    std::function<void(SurfaceMethod, size_t index, size_t count)> onMethod;
};

struct MethodComparison {
    SurfaceMethod method = SurfaceMethod::Bilinear;
    double lodPixels = 0.0;            // > 0: traced under this level of detail
    double buildSeconds = 0.0;         // Embree's BVH build, or the direct tracer's pyramids
    int64_t memoryBytes = 0;           // ours from our allocations; Embree's from its memory monitor
    int64_t primaryRays = 0;
    int64_t shadowRays = 0;
    double primaryRaysPerSecond = 0.0;
    double shadowRaysPerSecond = 0.0;
    double primarySeconds = 0.0;       // the timed pass of camera rays
    double shadowSeconds = 0.0;        // the timed pass of shadow rays
    double hitAgreement = 0.0;         // share of primary rays with the reference's hit/miss verdict
    ErrorSummary tErrorM;              // |t - t_ref| in metres over pixels both hit
    ErrorSummary tErrorRel;            // the same over t_ref
    double imageRmse = 0.0;            // against the reference image, linear RGB clamped to [0, 1]
    double imagePsnrDb = 0.0;          // 20 log10(1 / rmse); infinite for identical images
    double ratioToEmbreePrimary = 0.0; // primary rays/s over Embree's, this run (NaN when Embree was not run)
    double ratioToEmbreeShadow = 0.0;  // the same for shadow rays
    int64_t tileLoads = -1;            // DEM tiles read while built and traced (-1: the DEM is held in memory)
    Film image;                        // the method's picture
    std::vector<double> hitT;          // primary hit distance per pixel, NaN for a miss
};

struct CompareReport {
    int width = 0;
    int height = 0;
    int64_t rays = 0;                  // camera rays per method
    SurfaceMethod reference = SurfaceMethod::BilinearDouble;
    std::vector<MethodComparison> methods;
};

// Traces one built surface the way compareSurfaces traces each method: a timed pass of camera rays, a timed
// pass of one shadow ray per hit facing the sun, then shading (skipped, leaving the picture empty, when `shade`
// is false). Fills in everything but the comparisons with the reference and Embree (agreement, errors, image
// RMSE and PSNR, ratios). Only the picture's rows [rowBegin, rowEnd) are traced when given (rowEnd < 0: to the
// last row); hitT stays one entry per pixel of the whole picture, NaN outside them, and the picture stays black
// there.
MethodComparison traceSurface(const HeightGrid& grid, const TerrainSurface& surface, const TerrainRenderSettings& settings,
                              bool shade = true, int rowBegin = 0, int rowEnd = -1);

// The entry's name in reports: the method's, with "+lodP" under a level of detail of P pixels.
std::string comparisonName(const MethodComparison& m);

// Traces and measures every method of `settings` (the reference is added when missing).
CompareReport compareSurfaces(const HeightGrid& grid, const CompareSettings& settings);

// A heat map of |t - t_ref| per pixel on a log colour scale, with a legend strip below it giving the scale
// in metres. Pixels where one hits and the other misses are magenta; where both miss, dark grey.
Film differenceHeatMap(const MethodComparison& method, const MethodComparison& reference);

// An SVG chart of primary rays/s (x) against p99 hit-distance error (y), log axes, one labelled point each.
std::string tradeoffSvg(const CompareReport& report);

}  // namespace terracast
