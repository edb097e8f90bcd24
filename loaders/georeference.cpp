// Samples sit at pixel centres, following GDAL's geotransform (pixel-is-area; for SRTM .hgt GDAL already shifts
// the origin half a pixel so that centres fall on whole degrees). Geographic rasters are mapped to metres on the
// tangent plane at their centre latitude, using the WGS84 meridional and prime-vertical radii of curvature
// (Snyder 1987, "Map Projections: A Working Manual", USGS Professional Paper 1395).
#include "loaders/georeference.h"

#include "tracer/core/angles.h"
#include "tracer/core/errors.h"

#include <cpl_conv.h>
#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <cmath>

namespace terracast {
namespace {

constexpr double kLargeExtentDeg = 5.0;                              // wider geographic extents get a warning
// Geographic DEMs whose east-west scale at the north or south edge differs from the centre's by more are refused
// (a 1-degree tile stays under it up to 80 degrees of latitude).
constexpr double kMaxFrameDistortion = 0.05;
constexpr double kFootM = 0.3048;                                    // international foot
constexpr double kUsSurveyFootM = 1200.0 / 3937.0;                   // US survey foot

std::string toLower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return s;
}

}  // namespace

// Interprets a band's unit type ("m", "ft", "US survey foot", ...); an empty or unknown unit means metres.
VerticalUnit verticalUnit(const std::string& path, const std::string& unitType) {
    const std::string unit = toLower(unitType);
    if (unit.empty()) return {1.0, path + ": no vertical unit, assuming metres"};
    if (unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters") return {1.0, ""};
    if (unit == "ft" || unit == "foot" || unit == "feet" || unit == "international foot")
        return {kFootM, path + ": heights in feet, converted to metres"};
    if (unit == "us survey foot" || unit == "ftus" || unit == "us-ft" || unit == "us_survey_foot")
        return {kUsSurveyFootM, path + ": heights in US survey feet, converted to metres"};
    return {1.0, fmt::format("{}: unknown vertical unit '{}', assuming metres", path, unitType)};
}

// True for the identity transform GDAL reports for rasters without georeferencing.
bool isDefaultGeoTransform(const double gt[6]) {
    return gt[0] == 0.0 && gt[1] == 1.0 && gt[2] == 0.0 && gt[3] == 0.0 && gt[4] == 0.0 && std::abs(gt[5]) == 1.0;
}

// A width x height raster's geotransform and CRS (null or empty: none) into `geo`, and its metric lattice.
Lattice placeRaster(const std::string& path, const double gt[6], const OGRSpatialReference* srs, int64_t width,
                    int64_t height, GeoReference& geo, std::vector<std::string>& warnings) {
    for (int k = 0; k < 6; ++k)
        if (!std::isfinite(gt[k]) || std::abs(gt[k]) > 1e15)
            throw InputError(fmt::format("{}: geotransform term {} is {}, expected a finite coordinate within 1e15",
                                         path, k, gt[k]));
    if (gt[2] != 0.0 || gt[4] != 0.0)
        throw InputError(fmt::format("{}: rotated geotransform (terms {} and {}) is not supported; warp the raster "
                                     "north-up first (gdalwarp)",
                                     path, gt[2], gt[4]));
    if (gt[1] == 0.0 || gt[5] == 0.0 || !std::isfinite(gt[1]) || !std::isfinite(gt[5]))
        throw InputError(fmt::format("{}: geotransform has pixel size {} x {}", path, gt[1], gt[5]));

    std::copy(gt, gt + 6, geo.geoTransform);
    geo.georeferenced = true;
    Lattice lattice;
    lattice.flipRows = gt[5] < 0.0;
    lattice.flipColumns = gt[1] < 0.0;
    // Vertex (0, 0) is the centre of the south-west pixel.
    const double westColumn = lattice.flipColumns ? static_cast<double>(width - 1) : 0.0;
    const double southRow = lattice.flipRows ? static_cast<double>(height - 1) : 0.0;
    geo.originX = gt[0] + (westColumn + 0.5) * gt[1];
    geo.originY = gt[3] + (southRow + 0.5) * gt[5];

    const double pixelX = std::abs(gt[1]);
    const double pixelY = std::abs(gt[5]);
    if (srs == nullptr || srs->IsEmpty()) {
        warnings.push_back(path + ": no CRS, assuming metres");
        lattice.cellSizeXM = pixelX;
        lattice.cellSizeYM = pixelY;
        return lattice;
    }
    geo.crsName = srs->GetName() ? srs->GetName() : "";
    char* wkt = nullptr;
    const char* const wktOptions[] = {"FORMAT=WKT2_2019", nullptr};
    if (srs->exportToWkt(&wkt, wktOptions) == OGRERR_NONE && wkt != nullptr) geo.crsWkt = wkt;
    CPLFree(wkt);

    if (srs->IsGeographic()) {
        geo.geographic = true;
        const double degreesPerUnit = degrees(srs->GetAngularUnits(nullptr));
        const double centreLatDeg = (gt[3] + 0.5 * static_cast<double>(height) * gt[5]) * degreesPerUnit;
        // Meridians converge at a pole, so no flat local frame holds a raster that reaches one.
        const double edgeLat0 = gt[3] * degreesPerUnit, edgeLat1 = (gt[3] + static_cast<double>(height) * gt[5]) * degreesPerUnit;
        if (!(std::max(std::abs(edgeLat0), std::abs(edgeLat1)) < 90.0))
            throw InputError(fmt::format("{}: latitudes {:g} .. {:g} reach or cross a pole, which a local metric frame "
                                         "cannot hold; expected a raster within -90..90 degrees (reproject polar data "
                                         "first, e.g. gdalwarp -t_srs EPSG:3413 or EPSG:3031)",
                                         path, std::min(edgeLat0, edgeLat1), std::max(edgeLat0, edgeLat1)));
        geo.centreLatDeg = centreLatDeg;
        const double extentXDeg = static_cast<double>(width) * pixelX * degreesPerUnit;
        const double extentYDeg = static_cast<double>(height) * pixelY * degreesPerUnit;
        // The local frame gives every row the centre's metres per degree of longitude: at the north and south
        // edges a cell's true width is cos(edge) / cos(centre) of that. Beyond kMaxFrameDistortion the DEM
        // needs a projected CRS.
        const double distortion = std::max(std::abs(std::cos(radians(edgeLat0)) / std::cos(radians(centreLatDeg)) - 1.0),
                                           std::abs(std::cos(radians(edgeLat1)) / std::cos(radians(centreLatDeg)) - 1.0));
        if (distortion > kMaxFrameDistortion) {
            const double centreLonDeg = (gt[0] + 0.5 * static_cast<double>(width) * gt[1]) * degreesPerUnit;
            const int zone = std::clamp(int(std::floor((centreLonDeg + 180.0) / 6.0)) + 1, 1, 60);
            throw InputError(fmt::format(
                "{}: a geographic DEM of {:.2f} x {:.2f} degrees is too tall for one local metre frame (east-west "
                "distances at its northern or southern edge would be {:.1f} % off; expected at most {:.0f} %); "
                "reproject it first, e.g. gdalwarp -t_srs EPSG:{} -r bilinear {} dem-utm.tif (UTM zone {}{} holds "
                "its centre) or into an equal-area or conformal CRS of the region",
                path, extentXDeg, extentYDeg, 100.0 * distortion, 100.0 * kMaxFrameDistortion,
                (centreLatDeg >= 0.0 ? 32600 : 32700) + zone, path, zone, centreLatDeg >= 0.0 ? "N" : "S"));
        }
        if (extentXDeg > kLargeExtentDeg || extentYDeg > kLargeExtentDeg)
            warnings.push_back(fmt::format("{}: extent {:.2f} x {:.2f} degrees; the local tangent-plane approximation "
                                           "at latitude {:.2f} distorts distances far from the centre",
                                           path, extentXDeg, extentYDeg, centreLatDeg));
        const MetresPerDegree metres = metresPerDegree(centreLatDeg);
        lattice.cellSizeXM = pixelX * degreesPerUnit * metres.lon;
        lattice.cellSizeYM = pixelY * degreesPerUnit * metres.lat;
        return lattice;
    }
    const double metresPerUnit = srs->GetLinearUnits(nullptr);
    lattice.cellSizeXM = pixelX * metresPerUnit;
    lattice.cellSizeYM = pixelY * metresPerUnit;
    return lattice;
}

// Reads the dataset's geotransform and CRS into `geo` and returns the metric lattice.
Lattice georeference(const std::string& path, GDALDataset& dataset, const DemLoadOptions& options,
                     GeoReference& geo, std::vector<std::string>& warnings) {
    double gt[6] = {0, 1, 0, 0, 0, 1};
    if (dataset.GetGeoTransform(gt) != CE_None || isDefaultGeoTransform(gt)) {
        // Without a geotransform the raster is a picture: row 0 at the top, samples a fixed distance apart.
        warnings.push_back(fmt::format("{}: no geotransform, assuming {} m between samples", path,
                                       options.imageCellSizeM));
        return {options.imageCellSizeM, options.imageCellSizeM, true, false};
    }
    // GDAL reports a pixel-is-point raster's geotransform in the pixel-is-area convention already; the flag only
    // travels to the outputs, so that they declare what the source declares.
    const char* areaOrPoint = dataset.GetMetadataItem(GDALMD_AREA_OR_POINT);
    geo.pixelIsPoint = areaOrPoint != nullptr && EQUAL(areaOrPoint, GDALMD_AOP_POINT);
    return placeRaster(path, gt, dataset.GetSpatialRef(), dataset.GetRasterXSize(), dataset.GetRasterYSize(), geo,
                       warnings);
}

MetresPerDegree metresPerDegree(double latDeg) {
    constexpr double a = 6378137.0;            // WGS84 semi-major axis (m)
    constexpr double f = 1.0 / 298.257223563;  // WGS84 flattening
    constexpr double e2 = f * (2.0 - f);       // first eccentricity squared
    const double phi = radians(latDeg);
    const double s = std::sin(phi);
    const double w = 1.0 - e2 * s * s;
    const double meridionalM = a * (1.0 - e2) / (w * std::sqrt(w));
    const double primeVerticalM = a / std::sqrt(w);
    const double radiansPerDegree = radians(1.0);
    return {meridionalM * radiansPerDegree, primeVerticalM * std::cos(phi) * radiansPerDegree};
}

}  // namespace terracast
