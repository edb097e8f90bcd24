#include "loaders/crs.h"

#include "tracer/sky/sun_position.h"

#include "tracer/core/errors.h"

#include <cpl_error.h>
#include <fmt/format.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <memory>
#include <string>

namespace terracast {

void lonLatToSource(const GeoReference& geo, double lonDeg, double latDeg, double& x, double& y) {
    if (geo.crsWkt.empty()) throw InputError("--lonlat: the DEM has no CRS to convert longitude and latitude into");
    OGRSpatialReference wgs84, target;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = target.importFromWkt(geo.crsWkt.c_str()) == OGRERR_NONE;
    CPLPopErrorHandler();
    if (!ok) throw InputError("--lonlat: cannot read the DEM's CRS");
    target.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&wgs84, &target));
    x = lonDeg;
    y = latDeg;
    const bool done = t && t->Transform(1, &x, &y);
    CPLPopErrorHandler();
    if (!done || !std::isfinite(x) || !std::isfinite(y))
        throw InputError("--lonlat: cannot convert " + std::to_string(lonDeg) + ", " + std::to_string(latDeg) +
                         " into the DEM's CRS");
}

void gridCentreLonLat(const GeoReference& geo, int64_t width, int64_t height, const std::string& what, double& lonDeg,
                      double& latDeg) {
    if (!geo.georeferenced || geo.crsWkt.empty())
        throw InputError(what + ": has no CRS to tell where on the Earth it lies (expected a georeferenced DEM)");
    // Vertex (0, 0) is the south-west sample; columns run east and rows (after the flip) north.
    double x = geo.originX + 0.5 * double(width - 1) * std::abs(geo.geoTransform[1]);
    double y = geo.originY + 0.5 * double(height - 1) * std::abs(geo.geoTransform[5]);
    OGRSpatialReference source, wgs84;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = source.importFromWkt(geo.crsWkt.c_str()) == OGRERR_NONE;
    CPLPopErrorHandler();
    if (!ok) throw InputError(what + ": cannot read its CRS");
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(&source, &wgs84));
    const bool done = t && t->Transform(1, &x, &y);
    CPLPopErrorHandler();
    if (!done || !std::isfinite(x) || !std::isfinite(y) || std::abs(y) > 90.0)
        throw InputError(what + ": cannot convert its centre to longitude and latitude");
    lonDeg = x;
    latDeg = y;
}

void sourceToLocal(const LoadedDem& dem, double x, double y, double& xM, double& yM) {
    const double spx = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[1]) : 1.0;
    const double spy = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[5]) : 1.0;
    xM = (x - dem.geo.originX) / spx * dem.grid.cellSizeXM();
    yM = (y - dem.geo.originY) / spy * dem.grid.cellSizeYM();
}

std::string placeSunOverGrid(const UtcInstant& when, const GeoReference& geo, int64_t width, int64_t height,
                             const std::string& what, double& azimuthDeg, double& elevationDeg) {
    double lon = 0.0, lat = 0.0;
    gridCentreLonLat(geo, width, height, what, lon, lat);
    const SolarPosition p = solarPosition(when, lat, lon);
    azimuthDeg = p.azimuthDeg;
    elevationDeg = p.apparentElevationDeg;
    return fmt::format("sun at {} over {:.4f}, {:.4f} (lat, lon): azimuth {:.2f}, elevation {:.2f} degrees",
                       formatUtc(when), lat, lon, azimuthDeg, elevationDeg);
}

}  // namespace terracast
