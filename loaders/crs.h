// Coordinates between WGS84 longitude/latitude, a DEM's source CRS and the grid's local metres.
#pragma once

#include "loaders/dem_loader.h"
#include "tracer/sky/calendar.h"

#include <memory>
#include <string>

namespace terracast {

// Converts WGS84 (lon, lat) in degrees to the DEM's source CRS. Throws InputError when the DEM has no CRS
// or the transformation fails.
void lonLatToSource(const GeoReference& geo, double lonDeg, double latDeg, double& x, double& y);

// Where the sun stands at `when` over the centre of a grid of `width` x `height` vertices placed by `geo`, by
// NOAA's equations: sets the azimuth (in the grid's frame: from true north plus the meridian convergence) and the
// apparent elevation and returns a line saying so. Throws InputError naming `what` when the grid has no CRS.
std::string placeSunOverGrid(const UtcInstant& when, const GeoReference& geo, int64_t width, int64_t height,
                             const std::string& what, double& azimuthDeg, double& elevationDeg);

// Longitude, latitude and meridian convergence at any vertex position of a grid placed by `geo`, with the CRS
// transformations made once (for many points). Throws InputError naming `what` when the grid has no CRS or a
// point cannot be converted.
class GridLonLat {
public:
    GridLonLat(const GeoReference& geo, std::string what);
    ~GridLonLat();
    GridLonLat(const GridLonLat&) = delete;
    GridLonLat& operator=(const GridLonLat&) = delete;
    // At vertex position (col, row), row 0 at the south (fractions allowed).
    void lonLat(double col, double row, double& lonDeg, double& latDeg) const;
    // The meridian convergence there: the angle from the grid's north (its rows' +y) to true north, clockwise, in
    // degrees; an azimuth from true north plus this is the azimuth in the grid's frame. Zero for geographic grids,
    // whose local frame is east and north.
    double convergenceDeg(double col, double row) const;

private:
    struct Transforms;
    const GeoReference& geo_;
    std::string what_;
    std::unique_ptr<Transforms> t_;
};

// The same with the grid's CRS transformations made already (for many instants).
std::string placeSunOverGrid(const UtcInstant& when, const GridLonLat& places, int64_t width, int64_t height,
                             double& azimuthDeg, double& elevationDeg);

// Source-CRS coordinates to the grid's local metres (x east, y north, origin at the south-west sample).
void sourceToLocal(const LoadedDem& dem, double x, double y, double& xM, double& yM);

}  // namespace terracast
