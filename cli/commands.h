// The subcommands as library functions: each takes a plain options struct and returns an exit code
// (0 success, 1 runtime failure, 2 usage or input error), printing results on stdout and diagnostics on
// stderr.
#pragma once

#include "heightfield/traversal.h"
#include "tracer/measure/bench.h"
#include "tracer/measure/compare.h"
#include "tracer/terrain/surface.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"
#include "tracer/sky/calendar.h"

#include <cstdint>
#include <string>
#include <vector>

namespace terracast {

// Options shared by every command that reads a DEM.
struct DemOptions {
    std::string path;               // DEM file
    double imageCellSizeM = 1.0;    // PNG height maps: metres between samples
    double imageHeightScale = 1.0;  // PNG height maps: metres per stored unit
    double maxMemoryBytes = 0.0;    // refuse jobs estimated to need more; 0 = 80% of physical memory
};

// Parses a byte count such as "512M", "8G", "1.5T" or "1000000" (K, M, G, T are powers of 1024).
bool parseByteCount(const std::string& text, double& bytes);

// `terracast info DEM`
struct InfoOptions {
    DemOptions dem;
};
int runInfo(const InfoOptions& options);

// `terracast render DEM -o OUT`
struct RenderOptions {
    DemOptions dem;
    std::string output;                        // .png (8-bit sRGB) or .exr (linear half float)
    int width = 1280;                          // pixels
    int height = 720;                          // pixels
    double sunAzimuthDeg = 315.0;              // clockwise from north
    double sunElevationDeg = 35.0;             // above the horizon
    double exaggeration = 1.0;                 // vertical scale factor
    std::string camera;                        // "eye=x,y,z look=x,y,z fov=deg"; empty = automatic view
    SurfaceMethod method = SurfaceMethod::Bilinear;  // cell intersector, or Embree
    int threads = 0;                           // 0 = all cores
    bool quiet = false;                        // no progress or summary on stderr
    bool mapView = false;                      // top-down orthographic map on the DEM's grid (--view map)
    double scale = 1.0;                        // map view: output pixels per DEM cell along each axis
    bool castShadows = true;                   // map view: ray-traced cast shadows
    int skySamples = -1;                       // hemisphere rays per hit (perspective) or pixel (map) for sky
                                               // visibility; -1 = default, 4 in perspective, 16 in the map view
    std::string sky = "physical";              // perspective: physical, gradient, flat or none
    double haze = 1.0;                         // physical sky: multiplies Mie (aerosol) scattering
    std::optional<UtcInstant> sunTime;         // puts the sun where it stands then over the DEM
    uint64_t seed = 0;                         // sky-visibility directions
    bool colourRamp = false;                   // map view: elevation colours instead of grey
    double hillshadeBlend = 0.0;               // map view: weight of a plain hillshade, 0..1
};
int runRender(const RenderOptions& options);

// `terracast shadow DEM --sun AZ,EL -o mask.tif`
struct ShadowOptions {
    DemOptions dem;
    std::string output;                // GeoTIFF on the DEM's grid
    double sunAzimuthDeg = 315.0;      // clockwise from north
    double sunElevationDeg = 35.0;     // above the horizon
    double sunSizeDeg = 0.0;           // angular diameter; 0 = a point (mask of 0/1), else the blocked fraction
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
int runShadow(const ShadowOptions& options);

// `terracast horizon DEM --azimuth AZ -o horizon.tif`
struct HorizonOptions {
    DemOptions dem;
    std::string output;                // GeoTIFF on the DEM's grid, degrees
    double azimuthDeg = 180.0;         // clockwise from north
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
int runHorizon(const HorizonOptions& options);

// `terracast viewshed DEM --observer X,Y -o vis.tif`
struct ViewshedOptions {
    DemOptions dem;
    std::string output;                // GeoTIFF on the DEM's grid: 1 visible, 0 hidden, 255 nodata
    double observerX = 0.0;            // in the DEM's CRS (or longitude with lonLat)
    double observerY = 0.0;            // in the DEM's CRS (or latitude with lonLat)
    bool lonLat = false;               // observer given as WGS84 longitude, latitude
    double observerHeightM = 1.7;      // above the terrain
    double targetHeightM = 0.0;        // above the terrain
    double curvatureCoeff = 0.85714;   // as gdal_viewshed's -cc; 0 = flat earth
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
int runViewshed(const ViewshedOptions& options);

// `terracast accuracy DEM`
struct AccuracyCommandOptions {
    DemOptions dem;
    int64_t rays = 100000;             // seeded rays: camera-like, grazing and shadow-like in equal parts
    uint64_t seed = 1;                 // random seed
    std::string json;                  // write the report as JSON here; empty = none
};
int runAccuracy(const AccuracyCommandOptions& options);

// `terracast compare DEM`
struct CompareCommandOptions {
    DemOptions dem;
    int width = 640;                   // pixels
    int height = 480;                  // pixels
    double sunAzimuthDeg = 315.0;      // clockwise from north
    double sunElevationDeg = 35.0;     // above the horizon
    double exaggeration = 1.0;         // vertical scale factor
    std::string camera;                // as for render; empty = automatic view
    std::vector<SurfaceMethod> methods = compareMethods();  // measured; the reference is always added
    int threads = 0;                   // 0 = all cores
    std::string json;                  // report file; empty = none
    std::string outDir;                // folder for images, heat maps and tradeoff.svg; empty = none
};
int runCompare(const CompareCommandOptions& options);

// Parses "WxH" into positive width and height; returns false on malformed input.
// `terracast scene SCENE.toml [-o OUT]`: the Whitted scene renderer. Options given here override the file's.
struct SceneCommandOptions {
    std::string path;                          // the scene file
    std::string output;                        // overrides render.output
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
    bool debugPixel = false;                   // print one pixel's ray tree on stdout
    int debugX = 0, debugY = 0;
    double maxMemoryBytes = 0.0;               // 0 = 80% of physical memory
    bool quiet = false;
};
int runScene(const SceneCommandOptions& options);

bool parseSize(const std::string& text, int& width, int& height);
// Parses "A,B" into two finite numbers; returns false on malformed input.
bool parsePair(const std::string& text, double& a, double& b);

// `terracast bench`: the direct tracer against Embree on synthetic fractal grids (and optionally the sample
// DEMs), two cameras, one shadow ray per hit, at 1 thread and at `threads`.
struct BenchCommandOptions {
    std::string sizes = "513,2049,8193";  // comma-separated synthetic grid sizes, each 2^n + 1 vertices
    int threads = 0;                      // the thread count measured beside 1; 0 = all cores
    int repeat = BenchSettings{}.repeat;  // traces per pass
    int bands = BenchSettings{}.bands;    // bands of rows per trace; each band's fastest trace is kept
    std::string json;                     // report file; empty = none
    bool large = false;                   // add a 32769 x 32769 synthetic grid
    bool real = false;                    // add the DEMs of `dataDir`
    std::string dataDir;                  // folder of real DEMs; empty = the source tree's data-samples
    uint64_t seed = 1;                    // seed of the synthetic terrain
    double maxMemoryBytes = 0.0;          // grids and methods estimated to need more are skipped; 0 = 80% of RAM
    std::string svg;                      // chart of camera rays/s against grid size; empty = none
    bool fileToPicture = false;           // also time `render` from a 16-bit PNG of the largest synthetic grid
    std::string methods;                  // comma-separated bench methods to measure; empty = all (embree always)
};
int runBench(const BenchCommandOptions& options);

}  // namespace terracast
