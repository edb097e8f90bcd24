// From a DEM file to a picture: load the grid (with its warnings), check the job against the memory limit,
// set the view (exaggeration, sun, camera), build the surface, render and write the picture atomically. The
// perspective view and the top-down map view (`render --view map`) both start here, and so does `info`.
#pragma once

#include "loaders/dem_loader.h"
#include "tracer/core/listener.h"
#include "tracer/camera/camera.h"
#include "tracer/core/surface_method.h"
#include "tracer/sampling/filters.h"
#include "tracer/sampling/samplers.h"
#include "tracer/sky/calendar.h"
#include "tracer/sky/sky_description.h"
#include "tracer/terrain/camera.h"
#include "tracer/terrain/maps.h"
#include "tracer/terrain/terrain_renderer.h"
#include "tracer/terrain/tiled_product.h"

#include <cstdint>
#include <optional>
#include <string>

namespace terracast {

// Where a DEM comes from and what the job reading it may hold.
struct DemSource {
    std::string path;               // DEM file
    double imageCellSizeM = 1.0;    // PNG height maps: metres between samples
    double imageHeightScale = 1.0;  // PNG height maps: metres per stored unit
    double maxMemoryBytes = 0.0;    // refuse jobs estimated to need more; 0 = 80% of physical memory
    double tileCacheBytes = 0.0;    // > 0: hold the DEM as tiles with a cache this large (DemLoadOptions)
    bool tileStore = false;         // held as tiles: keep them decoded beside the DEM (DemLoadOptions)
};

// Loads the DEM, passing its warnings (assumed units, large geographic extents) to the listener. A job that
// never needs the whole grid in memory says so with `takesTiles`: under mpirun each rank then holds the DEM as
// tiles and reads only those its part of the work reaches (DemLoadOptions::tilesUnderRanks). Heights come
// multiplied by `exaggeration` (DemLoadOptions::exaggeration).
LoadedDem loadDemSource(const DemSource& source, const RunListener& listener, bool takesTiles = false,
                        double exaggeration = 1.0);

// `info`: size, CRS, cell size, heights, nodata and memory, as lines of text.
std::string demInfoReport(const DemSource& source, const RunListener& listener);

// For a DEM held as tiles, what the tile cache did: "tiles: 1234 loaded, 97.5 % of 50000 reads from the cache"
// (empty for a DEM held whole).
std::string tileTraffic(const HeightGrid& grid);
// For a DEM held as tiles, the thread time its cache spent loading tiles and waiting for loads (for --verbose).
std::string tileTimes(const HeightGrid& grid);

// The listener's progress, adding the tile traffic to the progress line for a DEM held as tiles.
std::function<void(double, int64_t)> progressWithTiles(const RunListener& listener, const HeightGrid& grid);

// Refuses (InputError) an exaggeration that is not a positive number or a sun elevation outside [-90, 90].
void checkViewValues(double exaggeration, double sunElevationDeg);

// The view of the loaded grid: size, sun, and the camera given or, when none is, the automatic view of the
// whole grid.
TerrainRenderSettings makeView(const HeightGrid& grid, int width, int height, double sunAzimuthDeg,
                               double sunElevationDeg, const std::optional<PinholeCamera>& camera, int threads);

// Everything `render` takes.
struct DemRenderOptions {
    DemSource dem;
    std::string output;                        // .png (8-bit sRGB) or .exr; map view: .tif (GeoTIFF) or .png
    int width = 1280;                          // pixels
    int height = 720;                          // pixels
    double sunAzimuthDeg = 315.0;              // clockwise from north
    double sunElevationDeg = 35.0;             // above the horizon
    std::optional<UtcInstant> sunTime;         // puts the sun where it stands then over the DEM's centre
    double exaggeration = 1.0;                 // vertical scale factor
    std::optional<PinholeCamera> camera;       // none = the automatic view
    SurfaceMethod method = SurfaceMethod::Bilinear;  // cell intersector, or Embree
    int threads = 0;                           // 0 = all cores
    bool mapView = false;                      // top-down orthographic map on the DEM's grid (--view map)
    CameraKind cameraKind = CameraKind::Pinhole;  // otherwise: perspective, orthographic, panorama or fisheye
    int samples = 1;                           // camera samples per pixel (--spp); 1 = the pixel's centre
    SamplePattern sampler = SamplePattern::Stratified;
    FilterKind filter = FilterKind::Box;
    bool adaptive = false;                     // adaptive sampling up to max(samples, 2) per pixel ...
    double adaptiveError = 0.002;              // ... until the standard error of a pixel's luminance is below this
    double scale = 1.0;                        // map view: output pixels per DEM cell along each axis
    double lodPixels = 0.0;                    // > 0: level of detail (TerrainSurface::setLevelOfDetail)
    bool resume = false;                       // map view GeoTIFF at scale 1: keep an interrupted run's tiles
    bool castShadows = true;                   // map view: ray-traced cast shadows
    int skySamples = -1;                       // hemisphere rays per hit (perspective) or pixel (map) for sky
                                               // visibility; -1 = default, 4 in perspective, 16 in the map view
    SkyKind sky = SkyKind::Physical;           // perspective: the sky model
    double haze = 1.0;                         // physical sky: multiplies Mie (aerosol) scattering
    uint64_t seed = 0;                         // sky-visibility directions
    bool smoothNormals = true;                 // perspective: shade with smooth normals (--normals smooth)
    bool colourRamp = false;                   // map view: elevation colours instead of grey
    // Perspective views: the terrain's colour (the elevation ramp, a plain colour, or `drape`, an image of any
    // raster GDAL reads warped onto the DEM's grid), the solid base and the backdrop.
    TerrainLook::Colouring colouring = TerrainLook::Colouring::Ramp;
    glm::vec3 plainColour{0.6f};               // linear RGB, for Colouring::Plain
    std::string drape;                         // file, for Colouring::Drape
    bool solidBase = true;
    Backdrop backdrop = Backdrop::Neutral;
    double hillshadeBlend = 0.0;               // map view: weight of a plain hillshade, 0..1
    bool verbose = false;                      // perspective: time the phases and tell them (render --verbose)
};

// The perspective view of a loaded DEM as `render` makes it (options checked, sun time, camera, look, sampling);
// the drape (options.drape) is left for the caller to load, after its memory check.
TerrainRenderSettings perspectiveSettings(const DemRenderOptions& options, const LoadedDem& dem,
                                          const RunListener& listener);

// The checks of `render`'s options that need no DEM, for a perspective view and for the map view
// (InputError naming the option).
void checkPerspectiveOptions(const DemRenderOptions& options);
void checkMapViewOptions(const DemRenderOptions& options);

// The map view's settings from `render --view map`'s options (checked), its sun placed.
MapViewSettings mapViewSettings(const DemRenderOptions& options, const LoadedDem& dem, const RunListener& listener);

// The map view on the DEM's own grid (scale 1, a method through the vertices, else InputError) as a per-vertex
// product of four Byte bands: sRGB and alpha (255 over the terrain, 0 over holes); refers to `dem`.
VertexProduct mapViewProduct(const MapViewSettings& settings, const LoadedDem& dem);

// A map view held whole as the samples its GeoTIFF holds: rows north first, four bytes a pixel (sRGB, alpha).
std::vector<uint8_t> mapViewPixels(const MapImage& image);

// Wall-clock seconds of the phases of one perspective render.
struct RenderPhaseSeconds {
    double load = 0.0;    // reading the DEM (and, for the direct tracer, making its pyramid) and setting the view
    double pyramid = 0.0; // of `load`: the whole grid's pyramid (0 for a DEM held as tiles)
    double grid = 0.0;    // of `load`: making the grid from its samples, the pyramid apart (0 as tiles)
    double build = 0.0;   // the surface: nothing more for the direct tracer, Embree's buffers and BVH
    double render = 0.0;  // tracing and shading the picture
    double write = 0.0;   // encoding and writing the picture
    double total = 0.0;   // from the first check of the options to the picture on disk
    // With DemRenderOptions::verbose, the render's thread-seconds (RenderStats): camera rays, shadow rays,
    // sky-visibility rays, and shading; 0 otherwise.
    double skySetup = 0.0;  // of `render`: the shader's set-up (the sky's tables), before any ray
    double cameraRayThreadSeconds = 0.0;
    double shadowRayThreadSeconds = 0.0;
    double skyRayThreadSeconds = 0.0;
    double shadingThreadSeconds = 0.0;
};

// `render`: checks, loads, builds, renders and writes; the summary line goes to the listener's note. Throws
// InputError for bad input, Cancelled when interrupted. Returns the phases of a perspective render (all zero
// for the map view).
RenderPhaseSeconds renderDem(const DemRenderOptions& options, const RunListener& listener);

// The line `render --verbose` tells: each phase's seconds, and the render's thread time split three ways.
std::string renderPhasesLine(const RenderPhaseSeconds& phases);

}  // namespace terracast
