// From a DEM file to a map product on the DEM's own grid, written tile by tile as a Cloud Optimized GeoTIFF with its georeference (and the
// source's pixel-is-point or pixel-is-area declaration), band descriptions, units and the settings in its
// metadata: the sun shadow mask, horizon angles, sky-view factor and openness, and the viewshed of an
// observer. Progress goes to the listener while it runs, and one summary line (seconds, rays or horizon walks,
// peak memory) at the end.
#pragma once

#include "tracer/core/listener.h"
#include "tracer/core/surface_method.h"
#include "tracer/sky/calendar.h"
#include "tracer/terrain/dem_pipeline.h"
#include "tracer/terrain/maps.h"
#include "tracer/terrain/tiled_product.h"

#include <string>
#include <vector>

namespace terracast {

// Each product is planned on a loaded DEM (xxxProduct: its options checked, all but the output path and the DEM
// source; its sample type, labels and per-window computation, which refers to `dem`: the DEM must outlive it),
// then written (writeXxxMap: load, plan, write tile by tile, summary) or computed into arrays by the Python
// module, so that both hold the same samples.

// `shadow`: 1 blocked, 0 lit per vertex (or the blocked fraction of the sun's disc).
struct ShadowMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    bool resume = false;               // keep the output tiles an interrupted run of the same job finished
    bool verbose = false;              // also tell each phase's seconds (tellMapPhases)
    double sunAzimuthDeg = 315.0;      // clockwise from north
    double sunElevationDeg = 35.0;     // above the horizon
    double sunSizeDeg = 0.0;           // angular diameter; 0 = a point (Byte mask of 0/1), else the blocked fraction
    std::vector<UtcInstant> sunTimes;  // when not empty: one band per time, the sun where it stands then over the
                                       // DEM's centre (replaces the azimuth and elevation; a point sun)
    double maxDistanceM = 0.0;         // terrain farther than this casts no shadow; 0 = the whole DEM
    double curvatureCoeff = 0.0;       // earth curvature less refraction, as viewshed's; 0 = flat earth
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
VertexProduct shadowProduct(const ShadowMapOptions& options, const LoadedDem& dem, const RunListener& listener);
void writeShadowMap(const ShadowMapOptions& options, const RunListener& listener);

// `horizon`: the horizon's elevation angle in degrees per vertex towards one azimuth, or one band per azimuth.
struct HorizonMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid, degrees
    bool resume = false;
    bool verbose = false;
    std::vector<double> azimuthsDeg{180.0};  // clockwise from north, one band each
    double maxDistanceM = 0.0;         // search radius; 0 = the whole DEM
    double curvatureCoeff = 0.0;       // earth curvature less refraction, as viewshed's; 0 = flat earth
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};

// Parses one ISO 8601 time, or "START/END/STEP": ISO 8601 times and a step such as 30m, 1h, 90s or 1d (END
// included when the steps land on it). Throws InputError naming `option`.
std::vector<UtcInstant> parseSunTimeRange(const std::string& text, const std::string& option);

// Parses "START:END:STEP" (degrees, END excluded, STEP > 0) into azimuths; throws InputError naming `option`.
std::vector<double> parseAzimuthRange(const std::string& text, const std::string& option);

// `svf`: sky-view factor, positive and negative openness per vertex, three bands.
struct SkyViewMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    bool resume = false;
    bool verbose = false;
    int directions = 16;               // azimuths
    double maxDistanceM = 0.0;         // search radius; 0 = 10 cells (the Relief Visualization Toolbox's default)
    double curvatureCoeff = 0.0;
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
VertexProduct skyViewProduct(const SkyViewMapOptions& options, const LoadedDem& dem);
void writeSkyViewMap(const SkyViewMapOptions& options, const RunListener& listener);
VertexProduct horizonProduct(const HorizonMapOptions& options, const LoadedDem& dem);
void writeHorizonMap(const HorizonMapOptions& options, const RunListener& listener);

// A span of whole days, both ends included, as days since 1970-01-01.
struct DateSpan {
    int64_t firstDay = 0;
    int64_t lastDay = 0;
};

// Parses "YYYY-MM-DD" (one day) or "START/END" (dates, END included); throws InputError naming `option`.
DateSpan parseDateSpan(const std::string& text, const std::string& option);

// Parses a duration such as 30m, 1h, 90s or 1d into seconds; throws InputError naming `option`.
int64_t parseDurationSeconds(const std::string& text, const std::string& option);

// `insolation`: clear-sky beam, diffuse, reflected and global irradiation (Wh/m^2 over the dates) and hours of
// direct sun per vertex, five bands.
struct InsolationMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    bool resume = false;
    bool verbose = false;
    DateSpan dates;                    // local solar days (of each block of vertices)
    int64_t stepSeconds = 1800;        // time step within a day (r.sun's default half hour)
    int dayStep = 1;                   // every n-th day is computed and stands for the n days from it
    double linkeTurbidity = 3.0;
    double albedo = 0.2;
    double maxDistanceM = 0.0;         // terrain farther than this casts no shadow; 0 = the whole DEM
    double curvatureCoeff = 0.0;
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
// `sunUpSteps`, when given, receives the sun positions above the horizon over the DEM's centre.
VertexProduct insolationProduct(const InsolationMapOptions& options, const LoadedDem& dem, const RunListener& listener,
                                int64_t* sunUpSteps = nullptr);
void writeInsolationMap(const InsolationMapOptions& options, const RunListener& listener);

// `viewshed`: 1 visible, 0 hidden, 255 nodata per vertex.
struct ViewshedMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    bool resume = false;
    bool verbose = false;
    double observerX = 0.0;            // in the DEM's CRS (or longitude with lonLat)
    double observerY = 0.0;            // in the DEM's CRS (or latitude with lonLat)
    bool lonLat = false;               // observer given as WGS84 longitude, latitude
    double observerHeightM = 1.7;      // above the terrain
    double targetHeightM = 0.0;        // above the terrain
    double curvatureCoeff = 0.85714;   // as gdal_viewshed's -cc; 0 = flat earth
    double maxDistanceM = 0.0;         // targets farther are not seen; 0 = no limit
    std::string observersFile;         // when set: many observers (readSitePoints), the count that see each vertex
    ViewshedValues values = ViewshedValues::Visible;  // or the angle seen at, or the height needed (one observer)
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};

// Parses "visible", "angle" or "height"; throws InputError naming `option`.
ViewshedValues parseViewshedValues(const std::string& text, const std::string& option);
// Checks the job against options.dem.maxMemoryBytes (a curved copy of the grid, the running count) before it
// makes the observers' viewsheds; `observerCount`, when given, receives the number of observers.
VertexProduct viewshedProduct(const ViewshedMapOptions& options, const LoadedDem& dem, int64_t* observerCount = nullptr);
void writeViewshedMap(const ViewshedMapOptions& options, const RunListener& listener);

}  // namespace terracast
