#include "loaders/crs.h"

#include "tracer/sky/sun_position.h"

#include "tracer/core/angles.h"
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
    if (!(lonDeg >= -180.0 && lonDeg <= 180.0 && latDeg >= -90.0 && latDeg <= 90.0))
        throw InputError(fmt::format("--lonlat: expected a longitude in [-180, 180] and a latitude in [-90, 90] "
                                     "(degrees), found {:g}, {:g}",
                                     lonDeg, latDeg));
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
        throw InputError(fmt::format("--lonlat: cannot convert {:g}, {:g} into the DEM's CRS", lonDeg, latDeg));
}

struct GridLonLat::Transforms {
    std::unique_ptr<OGRCoordinateTransformation> toLonLat, fromLonLat;
};

GridLonLat::GridLonLat(const GeoReference& geo, std::string what) : geo_(geo), what_(std::move(what)) {
    if (!geo.georeferenced || geo.crsWkt.empty())
        throw InputError(what_ + ": has no CRS to tell where on the Earth it lies (expected a georeferenced DEM)");
    OGRSpatialReference source, wgs84;
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool ok = source.importFromWkt(geo.crsWkt.c_str()) == OGRERR_NONE;
    CPLPopErrorHandler();
    if (!ok) throw InputError(what_ + ": cannot read its CRS");
    source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    auto t = std::make_unique<Transforms>();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    t->toLonLat.reset(OGRCreateCoordinateTransformation(&source, &wgs84));
    t->fromLonLat.reset(OGRCreateCoordinateTransformation(&wgs84, &source));
    CPLPopErrorHandler();
    if (!t->toLonLat || !t->fromLonLat) throw InputError(what_ + ": cannot transform its CRS to longitude and latitude");
    t_ = std::move(t);
}

GridLonLat::~GridLonLat() = default;

void GridLonLat::lonLat(double col, double row, double& lonDeg, double& latDeg) const {
    // Vertex (0, 0) is the south-west sample; columns run east and rows (after the flip) north.
    double x = geo_.originX + col * std::abs(geo_.geoTransform[1]);
    double y = geo_.originY + row * std::abs(geo_.geoTransform[5]);
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool done = t_->toLonLat->Transform(1, &x, &y);
    CPLPopErrorHandler();
    if (!done || !std::isfinite(x) || !std::isfinite(y) || std::abs(y) > 90.0)
        throw InputError(fmt::format("{}: cannot convert its sample {}, {} to longitude and latitude", what_, col, row));
    lonDeg = x;
    latDeg = y;
}

double GridLonLat::convergenceDeg(double col, double row) const {
    double lon = 0.0, lat = 0.0;
    lonLat(col, row, lon, lat);
    // Two points a hundredth of a degree apart along the meridian, in the source CRS: true north's direction there.
    const double d = lat > 0.0 ? -0.01 : 0.01;
    double x[2] = {lon, lon}, y[2] = {lat, lat + d};
    CPLPushErrorHandler(CPLQuietErrorHandler);
    const bool done = t_->fromLonLat->Transform(2, x, y);
    CPLPopErrorHandler();
    if (!done) throw InputError(fmt::format("{}: cannot find north at its sample {}, {}", what_, col, row));
    const double sign = d > 0.0 ? 1.0 : -1.0;
    // Local x and y run with the source's x and y (sourceToLocal), in proportion for a projected CRS; a geographic
    // one has no x displacement along a meridian.
    const double c = std::atan2(sign * (x[1] - x[0]), sign * (y[1] - y[0]));
    return std::isfinite(c) ? degrees(c) : 0.0;
}

void sourceToLocal(const LoadedDem& dem, double x, double y, double& xM, double& yM) {
    const double spx = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[1]) : 1.0;
    const double spy = dem.geo.georeferenced ? std::abs(dem.geo.geoTransform[5]) : 1.0;
    xM = (x - dem.geo.originX) / spx * dem.grid.cellSizeXM();
    yM = (y - dem.geo.originY) / spy * dem.grid.cellSizeYM();
}

std::string placeSunOverGrid(const UtcInstant& when, const GridLonLat& places, int64_t width, int64_t height,
                             double& azimuthDeg, double& elevationDeg) {
    const double col = 0.5 * double(width - 1), row = 0.5 * double(height - 1);
    double lon = 0.0, lat = 0.0;
    places.lonLat(col, row, lon, lat);
    const SolarPosition p = solarPosition(when, lat, lon);
    azimuthDeg = std::fmod(p.azimuthDeg + places.convergenceDeg(col, row) + 360.0, 360.0);
    elevationDeg = p.apparentElevationDeg;
    return fmt::format("sun at {} over {:.4f}, {:.4f} (lat, lon): azimuth {:.2f} from true north ({:.2f} from grid "
                       "north), elevation {:.2f} degrees",
                       formatUtc(when), lat, lon, p.azimuthDeg, azimuthDeg, elevationDeg);
}

std::string placeSunOverGrid(const UtcInstant& when, const GeoReference& geo, int64_t width, int64_t height,
                             const std::string& what, double& azimuthDeg, double& elevationDeg) {
    return placeSunOverGrid(when, GridLonLat(geo, what), width, height, azimuthDeg, elevationDeg);
}

}  // namespace terracast
