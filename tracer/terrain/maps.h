// Map products on the DEM's own grid: top-down shaded relief with cast shadows and sky visibility, sun
// shadow masks, horizon angles and viewsheds. Rasters here have row 0 at the SOUTH, like HeightGrid.
#pragma once

#include "heightfield/height_grid.h"
#include "heightfield/horizon.h"
#include "heightfield/traversal.h"
#include "tracer/terrain/terrain_renderer.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace terracast {

// The surface point above local (x, y), as the hit of a vertical ray: position, normal and error bound.
std::optional<HeightFieldHit> surfacePointAt(const HeightGrid& grid, double xM, double yM, CellMethod method);

// True when the terrain blocks the direction `dir` from a surface point (ray spawned off the surface).
bool blockedFrom(const HeightGrid& grid, const HeightFieldHit& at, const glm::dvec3& dir, CellMethod method);

// True when the terrain blocks `dir` from vertex (i, j), at the vertex's own height (docs/architecture.md,
// "Map products at vertices"): the direction leaves the vertex over one cell (or along the edge between two);
// it is blocked when it goes below that cell's surface before leaving it, and past that cell the walk decides.
// For the methods whose surface passes through the vertices (all but nearest); the vertex must be a corner
// of a valid cell.
bool blockedFromVertex(const HeightGrid& grid, int64_t i, int64_t j, const glm::dvec3& dir, CellMethod method);

// What a map product tells while it runs: the share of vertices done and the rays (or horizon walks) so far.
using MapProgress = std::function<void(double fraction, int64_t rays)>;

// A rectangle of the grid's vertices: columns [i0, i1), rows [j0, j1). The default (all -1) is the whole grid.
// A map computed over a window holds the same values there as the whole grid's map (docs/architecture.md,
// "Tiled outputs"): map products are written a window at a time.
struct VertexWindow {
    int64_t i0 = -1, j0 = -1, i1 = -1, j1 = -1;
    bool whole() const { return i0 < 0; }
    // This window, or the whole grid's when it is the default; throws std::invalid_argument outside the grid.
    VertexWindow within(const HeightGrid& grid) const;
};

// A map over a window of the grid's vertices (the whole grid unless computed over a window).
struct MapRaster {
    int64_t width = 0;
    int64_t height = 0;
    int bands = 1;
    int64_t i0 = 0, j0 = 0;        // the grid vertex of value (0, 0)
    std::vector<float> values;     // row 0 south, bands interleaved by vertex; NaN where there is no value (nodata)
    float at(int64_t i, int64_t j, int band = 0) const { return values[size_t((j * width + i) * bands + band)]; }
};

// Per vertex: 1 where the sun (a direction) is blocked by terrain, 0 where visible, NaN on nodata. With
// `sunRadiusRad` > 0 the sun is a disc sampled by `samples` stratified directions and the value is the
// blocked fraction. A direction is blocked when the vertex's horizon that way lies above it (horizonAbove,
// with `search`'s radius and curvature); nearest asks an occlusion walk from the surface point under the vertex.
MapRaster shadowMask(const HeightGrid& grid, double azimuthRad, double elevationRad, CellMethod method,
                     double sunRadiusRad = 0.0, int samples = 16, int threads = 0, const HorizonSearch& search = {},
                     const MapProgress& progress = {}, const VertexWindow& window = {});

// Per vertex, for many point suns in one pass: band k is 1 where sun k (azimuth, elevation in radians) is
// blocked, 0 where it is visible, NaN on nodata; decided as shadowMask does.
MapRaster shadowMasks(const HeightGrid& grid, const std::vector<glm::dvec2>& sunsRad, CellMethod method,
                      int threads = 0, const HorizonSearch& search = {}, const MapProgress& progress = {},
                      const VertexWindow& window = {});

// Per vertex: the horizon angle in degrees towards an azimuth; NaN on nodata, -90 where no surface lies that
// way. Exact for the methods through the vertices (one horizon walk per vertex, heightfield/horizon.h); for
// nearest, bisection over occlusion tests from the surface point under the vertex (ignoring `search`).
MapRaster horizonMap(const HeightGrid& grid, double azimuthRad, CellMethod method, int threads = 0,
                     const HorizonSearch& search = {}, const MapProgress& progress = {});

// The same for many azimuths in one pass over the grid: band k holds azimuth k.
MapRaster horizonMaps(const HeightGrid& grid, const std::vector<double>& azimuthsRad, CellMethod method,
                      int threads = 0, const HorizonSearch& search = {}, const MapProgress& progress = {},
                      const VertexWindow& window = {});

// Settings of the sky-view factor and openness.
struct SkyViewSettings {
    int directions = 16;               // azimuths, evenly spaced from north
    HorizonSearch search;              // radius and curvature of each horizon
    CellMethod method = CellMethod::Bilinear;
    int threads = 0;
    MapProgress progress;
    VertexWindow window;               // the vertices computed
};

// Per vertex, from exact horizons in `directions` azimuths: band 0 the sky-view factor, 1 - mean(sin(max(0, g)))
// over the horizon angles g (Zaksek, Ostir and Kokalj 2011, "Sky-view factor as a relief visualization
// technique"); band 1 the positive openness, mean(90 - g) in degrees; band 2 the negative openness, mean(90 + n)
// with n the lowest elevation angle to the surface that way (Yokoyama, Shirasawa and Pike 2002, "Visualizing
// topography by openness"), which is minus the horizon of the terrain turned upside down. Directions in which
// no surface lies within the radius (over the grid's edge) are left out of the openness means and count as an
// open sky. NaN on nodata and for nearest (which throws).
MapRaster skyView(const HeightGrid& grid, const SkyViewSettings& settings);

// The same a window at a time: the returned function computes the sky view over any window (telling its
// progress to the function given with it, not settings.progress), with the terrain
// turned upside down once. It refers to `grid`, which must outlive it; throws as skyView does.
std::function<MapRaster(const VertexWindow&, const MapProgress&)> skyViewMaker(const HeightGrid& grid, const SkyViewSettings& settings);

// What a viewshed raster holds per vertex.
enum class ViewshedValues {
    Visible,  // 1 visible, 0 hidden
    Angle,    // the elevation angle in degrees from the eye to the target where visible (NaN where hidden)
    Height,   // the metres above the ground a target needs to be seen (0 where the ground itself is)
};

// Observer and target settings of a viewshed.
struct ViewshedSettings {
    ViewshedValues values = ViewshedValues::Visible;
    double observerXM = 0.0;           // local metres
    double observerYM = 0.0;
    double observerHeightM = 1.7;      // above the terrain
    double targetHeightM = 0.0;        // above the terrain at each vertex
    double curvatureCoeff = 0.85714;   // as gdal_viewshed: 1 - refraction coefficient; 0 = flat earth
    double maxDistanceM = 0.0;         // targets farther (horizontally) are not seen; 0 = no limit
    double earthRadiusM = 6378137.0;
    CellMethod method = CellMethod::Bilinear;
    // Settle sight lines by bounds on the surface's slope around the eye where they can (sight_bounds.h), and
    // walk the rest from where the bounds stop: the same verdicts as walking every line whole (false), faster.
    bool boundSightLines = true;
    int threads = 0;
    MapProgress progress;
    VertexWindow window;               // the vertices computed (see also viewshedMaker)
};

// Per vertex: 1 when a target at targetHeightM above it is visible from the observer, 0 when hidden, NaN on
// nodata (or with `values`, the angle at which a visible target is seen, or the height a target needs). Earth
// curvature lowers terrain and target by coeff * d^2 / (2 R) at horizontal distance d from the observer.
// Beyond maxDistanceM a vertex is hidden (0), or NaN for angles and heights. The height is exact: D s + z_eye -
// h(target), with s the horizon's tangent from the eye towards the target within its distance D
// (horizonTangentFrom), at least 0. Throws GridError when the observer is not over the grid's surface.
MapRaster viewshed(const HeightGrid& grid, const ViewshedSettings& settings);

// The same viewshed a window at a time: the returned function computes settings' viewshed over any window
// (telling its progress to the function given with it, not settings.progress),
// with the observer's ground and the curved grid (for curvatureCoeff != 0) found once. It refers to `grid`,
// which must outlive it; throws as viewshed does.
std::function<MapRaster(const VertexWindow&, const MapProgress&)> viewshedMaker(const HeightGrid& grid, const ViewshedSettings& settings);

// True when viewshedMaker builds sight bounds for `settings` on `grid`: asked for, a grid held whole (the table
// reads every cell), and values other than heights (which need each line's horizon).
bool viewshedUsesSightBounds(const HeightGrid& grid, const ViewshedSettings& settings);

// Settings of the top-down shaded relief.
struct MapViewSettings {
    double scale = 1.0;                // output pixels per cell along each axis
    Sun sun;                           // the light
    bool castShadows = true;           // ray-traced cast shadows
    int skySamples = 16;               // hemisphere rays per pixel for sky visibility (0 = off, constant sky)
    bool colourRamp = false;           // elevation colour ramp instead of grey
    double hillshadeBlend = 0.0;       // 0..1: weight of a plain Lambert hillshade (no shadows, no sky)
    float ambient = 0.25f;             // sky light weight
    CellMethod method = CellMethod::Bilinear;
    uint64_t seed = 1;                 // sky sampling seed
    int threads = 0;
    MapProgress progress;
};

// A top-down picture and what it covers.
struct MapImage {
    Film film;                     // row 0 at the NORTH
    std::vector<uint8_t> covered;  // per pixel, 1 where the terrain has a surface, 0 over holes (black there)
    int64_t shadowRays = 0;        // sun visibility tests
    int64_t skyRays = 0;           // sky visibility tests
};

// A top-down orthographic picture on the DEM's own raster: round(width * scale) x round(height * scale) pixels
// over the footprint of the DEM's samples (each sample a pixel, half a cell beyond the outermost vertices). At
// scale 1 pixel (px, py) is vertex (px, height - 1 - py), shaded at the vertex itself: the normal averaged
// over its valid cells, the sun and the sky directions blocked when the vertex's horizon lies above them (as
// `shadow`). At other scales each pixel is shaded at the surface under its centre (clamped to the vertices'
// extent), found by a vertical probe, with rays spawned off it.
MapImage renderMapView(const HeightGrid& grid, const MapViewSettings& settings);

// The map view at scale 1 as a per-vertex product: for a window of vertices, four bands per vertex, the linear
// colour renderMapView gives its pixel (red, green, blue) and 1 where the surface passes through the vertex,
// all 0 over holes. For output tile by tile (and over the ranks); refers to `grid`, which must outlive it.
// Throws GridError for the nearest method (no surface through the vertices).
std::function<MapRaster(const VertexWindow&, const MapProgress&)> mapViewMaker(const HeightGrid& grid,
                                                                               const MapViewSettings& settings);

}  // namespace terracast
