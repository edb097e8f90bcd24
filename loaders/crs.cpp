#include "loaders/crs.h"

#include "loaders/errors.h"

#include <cpl_error.h>
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

void sourceToLocal(const LoadedDem& dem, double x, double y, double& xM, double& yM) {
    const double spx = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[1]) : 1.0;
    const double spy = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[5]) : 1.0;
    xM = (x - dem.geo.originX) / spx * dem.grid.cellSizeXM();
    yM = (y - dem.geo.originY) / spy * dem.grid.cellSizeYM();
}

}  // namespace terracast
