#include "loaders/points.h"
#include "loaders/input_files.h"

#include "loaders/loader_support.h"
#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/text.h"

#include <fmt/format.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

namespace terracast {

namespace {

using loader_support::QuietGdalErrors;
using loader_support::registerGdalDrivers;

// The fields of a text line: split at its first separator among commas, semicolons and tabs (empty fields
// kept, spaces around fields dropped), else at runs of spaces.
std::vector<std::string> fieldsOf(const std::string& line) {
    auto trim = [](std::string f) {
        const size_t a = f.find_first_not_of(" \r"), b = f.find_last_not_of(" \r");
        return a == std::string::npos ? std::string() : f.substr(a, b - a + 1);
    };
    std::vector<std::string> out;
    for (char sep : {',', ';', '\t'}) {
        if (line.find(sep) == std::string::npos) continue;
        size_t start = 0;
        while (true) {
            const size_t end = line.find(sep, start);
            out.push_back(trim(line.substr(start, end == std::string::npos ? std::string::npos : end - start)));
            if (end == std::string::npos) break;
            start = end + 1;
        }
        if (!out.empty() && out.back().empty()) out.pop_back();  // a trailing separator
        return out;
    }
    std::istringstream words(line);
    for (std::string w; words >> w;) out.push_back(w);
    return out;
}

// A number, +infinity for one out of double's range (so that the finiteness check names it), none for text.
std::optional<double> numberOf(const std::string& text) {
    if (text.empty()) return std::nullopt;
    try {
        size_t used = 0;
        const double v = std::stod(text, &used);
        if (used != text.size()) return std::nullopt;
        return v;
    } catch (const std::out_of_range&) {
        return std::numeric_limits<double>::infinity();
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

std::vector<SitePoint> readText(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(fmt::format("{}: cannot open the point file", path));
    std::vector<SitePoint> points;
    std::string line;
    int64_t number = 0;
    bool first = true;
    while (std::getline(in, line)) {
        ++number;
        if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
        const auto fields = fieldsOf(line);
        if (fields.empty() || (!fields[0].empty() && fields[0][0] == '#')) continue;
        std::vector<std::optional<double>> values;
        for (const auto& f : fields) values.push_back(numberOf(f));
        const bool numeric = std::all_of(values.begin(), values.end(), [](const auto& v) { return v.has_value(); });
        const bool words = std::none_of(values.begin(), values.end(), [](const auto& v) { return v.has_value(); });
        if (first && words) {  // a header: no field is a number
            first = false;
            continue;
        }
        first = false;
        const std::string where = fmt::format("{}:{}", path, number);
        if (!numeric || fields.size() < 2 || fields.size() > 3)
            throw InputError(fmt::format("{}: expected X,Y or X,Y,HEIGHT as numbers, found '{}'", where, line));
        for (const auto& v : values)
            if (!std::isfinite(*v)) throw InputError(fmt::format("{}: expected finite numbers, found '{}'", where, line));
        SitePoint p{*values[0], *values[1], std::nullopt, where};
        if (values.size() == 3) p.heightM = *values[2];
        points.push_back(p);
    }
    return points;
}

std::vector<SitePoint> readVector(const std::string& path, const GeoReference& geo) {
    registerGdalDrivers();
    QuietGdalErrors quiet;
    std::unique_ptr<GDALDataset> ds(
        GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!ds || ds->GetLayerCount() < 1)
        throw InputError(fmt::format("{}: not a vector file GDAL can read (expected points, or a .csv of X,Y)", path));
    OGRLayer* layer = ds->GetLayer(0);
    std::unique_ptr<OGRCoordinateTransformation> transform;
    const OGRSpatialReference* from = layer->GetSpatialRef();
    if (from && geo.georeferenced && !geo.crsWkt.empty()) {
        OGRSpatialReference to;
        to.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        OGRSpatialReference source(*from);
        source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        if (to.importFromWkt(geo.crsWkt.c_str()) == OGRERR_NONE && !source.IsSame(&to)) {
            transform.reset(OGRCreateCoordinateTransformation(&source, &to));
            if (!transform) throw InputError(fmt::format("{}: cannot move its points into the DEM's CRS", path));
        }
    }
    const int heightField = [&] {
        for (const char* name : {"height", "HEIGHT", "h"}) {
            const int k = layer->GetLayerDefn()->GetFieldIndex(name);
            if (k >= 0) return k;
        }
        return -1;
    }();
    std::vector<SitePoint> points;
    int64_t index = 0;
    layer->ResetReading();
    for (auto& feature : *layer) {
        ++index;
        const std::string where = fmt::format("{}: feature {}", path, index);
        const OGRGeometry* g = feature->GetGeometryRef();
        if (!g) throw InputError(fmt::format("{}: has no geometry (expected a point)", where));
        std::vector<OGRPoint> found;
        const auto type = wkbFlatten(g->getGeometryType());
        if (type == wkbPoint) found.push_back(*g->toPoint());
        else if (type == wkbMultiPoint)
            for (const OGRPoint* p : *g->toMultiPoint()) found.push_back(*p);
        else
            throw InputError(fmt::format("{}: expected a point, found a {}", where, OGRGeometryTypeToName(type)));
        for (OGRPoint& p : found) {
            double x = p.getX(), y = p.getY();
            if (transform && !transform->Transform(1, &x, &y))
                throw InputError(fmt::format("{}: cannot move ({}, {}) into the DEM's CRS", where, p.getX(), p.getY()));
            if (!std::isfinite(x) || !std::isfinite(y))
                throw InputError(fmt::format("{}: expected finite coordinates, found ({}, {})", where, x, y));
            SitePoint s{x, y, std::nullopt, where};
            if (heightField >= 0 && feature->IsFieldSetAndNotNull(heightField)) s.heightM = feature->GetFieldAsDouble(heightField);
            points.push_back(s);
        }
    }
    return points;
}

}  // namespace

std::vector<SitePoint> readSitePoints(const std::string& path, const GeoReference& geo) {
    std::error_code ec;
    // A folder may be a vector dataset (a shapefile's); anything else must be a regular file.
    if (!std::filesystem::is_directory(path, ec)) checkInputFile(path, "a point file");
    const ExitOnCancel interruptible;
    const std::string ext = lowerExtension(path);
    std::vector<SitePoint> points = ext == ".csv" || ext == ".txt" ? readText(path) : readVector(path, geo);
    if (points.empty()) throw InputError(fmt::format("{}: holds no point", path));
    for (const auto& p : points)
        if (p.heightM && !std::isfinite(*p.heightM))
            throw InputError(fmt::format("{}: expected a finite height, found {}", p.where, *p.heightM));
    return points;
}

}  // namespace terracast
