// From a DEM file to a map product on the DEM's own grid, written as a GeoTIFF with its georeference: the sun
// shadow mask, the horizon angle towards an azimuth, and the viewshed of an observer. One summary line each
// goes to the listener's note.
#pragma once

#include "tracer/core/listener.h"
#include "tracer/core/surface_method.h"
#include "tracer/terrain/dem_pipeline.h"

#include <string>

namespace terracast {

// `shadow`: 1 blocked, 0 lit per vertex (or the blocked fraction of the sun's disc).
struct ShadowMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    double sunAzimuthDeg = 315.0;      // clockwise from north
    double sunElevationDeg = 35.0;     // above the horizon
    double sunSizeDeg = 0.0;           // angular diameter; 0 = a point (mask of 0/1), else the blocked fraction
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
void writeShadowMap(const ShadowMapOptions& options, const RunListener& listener);

// `horizon`: the horizon's elevation angle in degrees per vertex towards an azimuth.
struct HorizonMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid, degrees
    double azimuthDeg = 180.0;         // clockwise from north
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
void writeHorizonMap(const HorizonMapOptions& options, const RunListener& listener);

// `viewshed`: 1 visible, 0 hidden, 255 nodata per vertex.
struct ViewshedMapOptions {
    DemSource dem;
    std::string output;                // GeoTIFF on the DEM's grid
    double observerX = 0.0;            // in the DEM's CRS (or longitude with lonLat)
    double observerY = 0.0;            // in the DEM's CRS (or latitude with lonLat)
    bool lonLat = false;               // observer given as WGS84 longitude, latitude
    double observerHeightM = 1.7;      // above the terrain
    double targetHeightM = 0.0;        // above the terrain
    double curvatureCoeff = 0.85714;   // as gdal_viewshed's -cc; 0 = flat earth
    SurfaceMethod method = SurfaceMethod::Bilinear;
    int threads = 0;
};
void writeViewshedMap(const ViewshedMapOptions& options, const RunListener& listener);

}  // namespace terracast
