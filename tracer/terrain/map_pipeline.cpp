#include "tracer/terrain/map_pipeline.h"

#include "loaders/crs.h"
#include "loaders/output_paths.h"
#include "loaders/points.h"
#include "loaders/raster_writer.h"
#include "tracer/core/angles.h"
#include "tracer/core/cancel.h"
#include "tracer/core/errors.h"
#include "tracer/core/ranks.h"
#include "tracer/core/resources.h"
#include "tracer/core/text.h"
#include "tracer/sky/sun_position.h"
#include "tracer/terrain/insolation.h"
#include "tracer/terrain/maps.h"
#include "tracer/terrain/memory_model.h"
#include "tracer/terrain/sight_bounds.h"
#include "tracer/terrain/tiled_product.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <functional>
#include <future>
#include <optional>
#include <sstream>

namespace terracast {

namespace {

// The earth's radius the curvature options use (WGS 84's semi-major axis, as gdal_viewshed).
constexpr double kEarthRadiusM = 6378137.0;

// The search radius and curvature options as a HorizonSearch.
HorizonSearch searchFrom(double maxDistanceM, double curvatureCoeff, const char* command) {
    if (!(maxDistanceM >= 0.0) || !std::isfinite(maxDistanceM))
        throw InputError(fmt::format("{} --max-distance: expected metres >= 0, found {}", command, maxDistanceM));
    if (!std::isfinite(curvatureCoeff) || curvatureCoeff < 0.0 || curvatureCoeff > 2.0)
        throw InputError(fmt::format("{} --curvature-coeff: expected a number in [0, 2], found {}", command,
                                     curvatureCoeff));
    HorizonSearch search;
    if (maxDistanceM > 0.0) search.maxDistanceM = maxDistanceM;
    search.dropPerSquareM = curvatureCoeff / (2.0 * kEarthRadiusM);
    return search;
}

std::string number(double v) { return fmt::format("{}", v); }

// "30m", "1h", "90s", "1d" in seconds; nothing when it is not one (or longer than a leap year).
std::optional<int64_t> durationSeconds(const std::string& text) {
    int64_t count = 0;
    size_t used = 0;
    try {
        count = std::stoll(text, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    const std::string unit = text.substr(used);
    const int64_t per = unit == "s" ? 1 : unit == "m" ? 60 : unit == "h" ? 3600 : unit == "d" ? 86400 : 0;
    if (per == 0 || count <= 0 || count > 366 * 86400 / per) return std::nullopt;
    return count * per;
}

}  // namespace

std::vector<double> parseAzimuthRange(const std::string& text, const std::string& option) {
    double a = 0.0, b = 0.0, step = 0.0;
    char c1 = 0, c2 = 0;
    std::istringstream in(text);
    if (!(in >> a >> c1 >> b >> c2 >> step) || c1 != ':' || c2 != ':' || !in.eof() || !std::isfinite(a) ||
        !std::isfinite(b) || !(step > 0.0) || !(b > a))
        throw InputError(fmt::format("{}: expected START:END:STEP in degrees with END > START and STEP > 0 (END "
                                     "excluded), found '{}'",
                                     option, text));
    std::vector<double> out;
    for (int64_t k = 0;; ++k) {
        const double az = a + double(k) * step;
        if (az >= b - 1e-9 * step) break;
        if (out.size() >= 3600)
            throw InputError(fmt::format("{}: '{}' gives more than 3600 azimuths", option, text));
        out.push_back(az);
    }
    return out;
}

std::vector<UtcInstant> parseSunTimeRange(const std::string& text, const std::string& option) {
    auto fail = [&](const std::string& why) {
        return InputError(fmt::format("{}: expected an ISO 8601 time such as 2026-06-21T15:00Z or START/END/STEP such "
                                      "as 2026-06-21T04:00Z/2026-06-21T20:00Z/30m, found '{}' ({})",
                                      option, text, why));
    };
    std::string why;
    if (text.find('/') == std::string::npos) {
        // One instant.
        const auto when = parseIsoTime(text, why);
        if (!when) throw fail(why);
        return {*when};
    }
    const size_t a = text.find('/'), b = a == std::string::npos ? a : text.find('/', a + 1);
    if (b == std::string::npos || text.find('/', b + 1) != std::string::npos) throw fail("three parts separated by /");
    const auto start = parseIsoTime(text.substr(0, a), why);
    if (!start) throw fail("START: " + why);
    const auto end = parseIsoTime(text.substr(a + 1, b - a - 1), why);
    if (!end) throw fail("END: " + why);
    const std::optional<int64_t> step = durationSeconds(text.substr(b + 1));
    if (!step) throw fail("STEP: a whole number > 0 with a unit s, m, h or d");
    const int64_t t0 = unixSeconds(*start), t1 = unixSeconds(*end);
    if (t1 < t0) throw fail("END is before START");
    if ((t1 - t0) / *step + 1 > 3600) throw fail("more than 3600 times");
    std::vector<UtcInstant> times;
    for (int64_t t = t0; t <= t1; t += *step) times.push_back(*instantFromUnixSeconds(t));
    return times;
}

int64_t parseDurationSeconds(const std::string& text, const std::string& option) {
    const std::optional<int64_t> s = durationSeconds(text);
    if (!s) throw InputError(fmt::format("{}: expected a whole number > 0 with a unit s, m, h or d (such as 30m), "
                                         "found '{}'", option, text));
    return *s;
}

DateSpan parseDateSpan(const std::string& text, const std::string& option) {
    const auto fail = [&](const std::string& why) {
        return InputError(fmt::format("{}: expected a date YYYY-MM-DD or START/END such as 2026-01-01/2026-12-31, "
                                      "found '{}' ({})", option, text, why));
    };
    const auto date = [&](const std::string& part, const char* which) {
        int y = 0, m = 0, d = 0, used = 0;
        if (std::sscanf(part.c_str(), "%4d-%2d-%2d%n", &y, &m, &d, &used) != 3 || used != int(part.size()) ||
            part.size() != 10)
            throw fail(fmt::format("{} is not YYYY-MM-DD", which));
        if (y < 1 || m < 1 || m > 12 || d < 1 || d > daysInMonth(y, m)) throw fail(fmt::format("{} is no such day", which));
        return daysFromCivil(y, m, d);
    };
    const size_t slash = text.find('/');
    DateSpan span;
    if (slash == std::string::npos) {
        span.firstDay = span.lastDay = date(text, "the date");
    } else {
        span.firstDay = date(text.substr(0, slash), "START");
        span.lastDay = date(text.substr(slash + 1), "END");
        if (span.lastDay < span.firstDay) throw fail("END is before START");
    }
    return span;
}

namespace {

// The checks of `shadow`'s options that need no DEM.
void checkShadowOptions(const ShadowMapOptions& o) {
    if (!o.sunTimes.empty()) {
        if (o.sunSizeDeg != 0.0)
            throw InputError("shadow: --sun-size applies to one sun; --sun-time ranges use a point sun");
    } else {
        checkViewValues(1.0, o.sunElevationDeg);
        if (!(o.sunSizeDeg >= 0.0 && o.sunSizeDeg < 30.0))
            throw InputError(fmt::format("--sun-size: expected degrees in [0, 30), found {}", o.sunSizeDeg));
    }
    searchFrom(o.maxDistanceM, o.curvatureCoeff, "shadow");
    requireDirectMethod(o.method, "shadow");
}

// Sun disc samples of a shadow mask with --sun-size.
constexpr int kSunDiscSamples = 16;

}  // namespace

VertexProduct shadowProduct(const ShadowMapOptions& o, const LoadedDem& dem, const RunListener& listener) {
    checkShadowOptions(o);
    const HorizonSearch search = searchFrom(o.maxDistanceM, o.curvatureCoeff, "shadow");
    const CellMethod method = requireDirectMethod(o.method, "shadow");
    const int threads = o.threads;
    RasterLabels labels;
    labels.units = {"1"};
    if (!o.sunTimes.empty()) {
        // --sun-time START/END/STEP: one Byte band per time, in one pass over the grid.
        std::vector<glm::dvec2> suns;
        std::string times;
        int up = 0;
        const GridLonLat places(dem.geo, dem.path + ": --sun-time");
        for (const UtcInstant& when : o.sunTimes) {
            double az = 0.0, el = 0.0;
            placeSunOverGrid(when, places, dem.grid.width(), dem.grid.height(), az, el);
            suns.push_back({radians(az), radians(el)});
            up += el > 0.0;
            labels.bands.push_back(fmt::format("sun shadow at {} (azimuth {:.2f}, elevation {:.2f} degrees): 1 "
                                               "shadowed, 0 lit", formatUtc(when), az, el));
            if (!times.empty()) times += ',';
            times += formatUtc(when);
        }
        labels.metadata = {{"TERRACAST_PRODUCT", "shadow"},
                           {"TERRACAST_SUN_TIMES", times},
                           {"TERRACAST_MAX_DISTANCE_M", number(o.maxDistanceM)},
                           {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                           {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
        listener.tell(fmt::format("{} sun times from {} to {}, the sun above the horizon at {} of them",
                                  o.sunTimes.size(), formatUtc(o.sunTimes.front()), formatUtc(o.sunTimes.back()), up));
        const int bands = int(suns.size());
        return {bands, RasterType::Byte, 255.0, std::move(labels),
                [&grid = dem.grid, suns = std::move(suns), method, threads, search](const VertexWindow& w,
                                                                                   const MapProgress& progress) {
                    return shadowMasks(grid, suns, method, threads, search, progress, w);
                }};
    }
    const bool point = o.sunSizeDeg == 0.0;
    labels.bands = {point ? "sun shadow: 1 shadowed, 0 lit" : "share of the sun's disc hidden by terrain"};
    labels.metadata = {{"TERRACAST_PRODUCT", "shadow"},
                       {"TERRACAST_SUN_AZIMUTH_DEG", number(o.sunAzimuthDeg)},
                       {"TERRACAST_SUN_ELEVATION_DEG", number(o.sunElevationDeg)},
                       {"TERRACAST_SUN_SIZE_DEG", number(o.sunSizeDeg)},
                       {"TERRACAST_MAX_DISTANCE_M", number(o.maxDistanceM)},
                       {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                       {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
    // A point sun gives 0 or 1: bytes, 255 for nodata; a disc gives fractions.
    const double az = radians(o.sunAzimuthDeg), el = radians(o.sunElevationDeg), radius = radians(0.5 * o.sunSizeDeg);
    return {1, point ? RasterType::Byte : RasterType::Float32, point ? 255.0 : -9999.0, std::move(labels),
            [&grid = dem.grid, az, el, radius, method, threads, search](const VertexWindow& w, const MapProgress& progress) {
                return shadowMask(grid, az, el, method, radius, kSunDiscSamples, threads, search, progress, w);
            }};
}

void writeShadowMap(const ShadowMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkShadowOptions(o);
    MapPhaseClock phases;
    const LoadedDem dem = loadDemSource(o.dem, listener, true);
    phases.demLoaded();
    VertexProduct product = shadowProduct(o, dem, listener);
    checkRasterJob(dem, o.dem.maxMemoryBytes, product.bands, product.type, 0.0,
                   o.sunTimes.empty() ? std::string("a shadow mask") : fmt::format("{} shadow bands", product.bands));
    phases.productPlanned();
    listener.at("shadow");
    const auto start = std::chrono::steady_clock::now();
    const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
    const bool disc = o.sunTimes.empty() && o.sunSizeDeg != 0.0;
    tellRasterSummary(listener, o.sunTimes.empty() ? "shadow mask" : "shadow masks", o.output, count,
                      count.valid * (disc ? kSunDiscSamples : 1), "shadow walks", start);
    if (o.verbose) listener.tell(mapPhasesLine(phases, count));
}

namespace {

void checkHorizonOptions(const HorizonMapOptions& o) {
    if (o.azimuthsDeg.empty()) throw InputError("horizon: no azimuth given (--azimuth or --azimuths)");
    for (double a : o.azimuthsDeg)
        if (!std::isfinite(a)) throw InputError(fmt::format("horizon --azimuth: expected degrees, found {}", a));
    searchFrom(o.maxDistanceM, o.curvatureCoeff, "horizon");
    requireDirectMethod(o.method, "horizon");
}

}  // namespace

VertexProduct horizonProduct(const HorizonMapOptions& o, const LoadedDem& dem) {
    checkHorizonOptions(o);
    const HorizonSearch search = searchFrom(o.maxDistanceM, o.curvatureCoeff, "horizon");
    const CellMethod method = requireDirectMethod(o.method, "horizon");
    std::vector<double> azimuths;
    RasterLabels labels;
    for (double a : o.azimuthsDeg) {
        azimuths.push_back(radians(a));
        labels.bands.push_back(fmt::format("horizon angle towards azimuth {} degrees", a));
    }
    labels.units = {"degree"};
    labels.metadata = {{"TERRACAST_PRODUCT", "horizon"},
                       {"TERRACAST_AZIMUTH_CONVENTION", "degrees clockwise from grid north"},
                       {"TERRACAST_MAX_DISTANCE_M", number(o.maxDistanceM)},
                       {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                       {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
    const int bands = int(azimuths.size());
    return {bands, RasterType::Float32, -9999.0, std::move(labels),
            [&grid = dem.grid, azimuths = std::move(azimuths), method, threads = o.threads, search](
                const VertexWindow& w, const MapProgress& progress) {
                return horizonMaps(grid, azimuths, method, threads, search, progress, w);
            }};
}

void writeHorizonMap(const HorizonMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkHorizonOptions(o);
    MapPhaseClock phases;
    const LoadedDem dem = loadDemSource(o.dem, listener, true);
    phases.demLoaded();
    listener.at("horizon");
    const auto start = std::chrono::steady_clock::now();
    VertexProduct product = horizonProduct(o, dem);
    checkRasterJob(dem, o.dem.maxMemoryBytes, product.bands, RasterType::Float32, 0.0,
                   fmt::format("{} horizon bands", product.bands));
    phases.productPlanned();
    const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
    tellRasterSummary(listener, "horizon angles", o.output, count, count.rays, "horizon walks", start);
    if (o.verbose) listener.tell(mapPhasesLine(phases, count));
}

namespace {

void checkSkyViewOptions(const SkyViewMapOptions& o) {
    if (o.directions < 1 || o.directions > 3600)
        throw InputError(fmt::format("svf --directions: expected 1 to 3600, found {}", o.directions));
    searchFrom(o.maxDistanceM, o.curvatureCoeff, "svf");
    requireDirectMethod(o.method, "svf");
}

// The search radius of the sky view: the option, or 10 cells (the Relief Visualization Toolbox's default).
double skyViewRadius(const SkyViewMapOptions& o, const HeightGrid& grid) {
    return o.maxDistanceM > 0.0 ? o.maxDistanceM : 10.0 * std::max(grid.cellSizeXM(), grid.cellSizeYM());
}

}  // namespace

VertexProduct skyViewProduct(const SkyViewMapOptions& o, const LoadedDem& dem) {
    checkSkyViewOptions(o);
    SkyViewSettings s;
    s.search = searchFrom(o.maxDistanceM, o.curvatureCoeff, "svf");
    s.method = requireDirectMethod(o.method, "svf");
    const double radius = skyViewRadius(o, dem.grid);
    s.search.maxDistanceM = radius;
    s.directions = o.directions;
    s.threads = o.threads;
    RasterLabels labels;
    labels.bands = {"sky-view factor (share of the sky visible)", "positive openness", "negative openness"};
    labels.units = {"1", "degree", "degree"};
    labels.metadata = {{"TERRACAST_PRODUCT", "svf"},
                       {"TERRACAST_DIRECTIONS", std::to_string(o.directions)},
                       {"TERRACAST_MAX_DISTANCE_M", number(radius)},
                       {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                       {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
    // The terrain upside down is a copy of the grid: for tiles, a second tile cache over the same source.
    return {3, RasterType::Float32, -9999.0, std::move(labels), skyViewMaker(dem.grid, s)};
}

void writeSkyViewMap(const SkyViewMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkSkyViewOptions(o);
    MapPhaseClock phases;
    const LoadedDem dem = loadDemSource(o.dem, listener, true);
    phases.demLoaded();
    checkRasterJob(dem, o.dem.maxMemoryBytes, 3, RasterType::Float32, 0.0, "sky-view factor and openness");
    listener.at("svf");
    const auto start = std::chrono::steady_clock::now();
    VertexProduct product = skyViewProduct(o, dem);
    phases.productPlanned();
    const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
    listener.tell(fmt::format("sky-view factor and openness: {} directions, search radius {:.1f} m", o.directions,
                              skyViewRadius(o, dem.grid)));
    tellRasterSummary(listener, "sky view", o.output, count, count.width * count.height * 2 * o.directions,
                      "horizon walks", start);
    if (o.verbose) listener.tell(mapPhasesLine(phases, count));
}

namespace {

void checkInsolationOptions(const InsolationMapOptions& o) {
    if (!(o.linkeTurbidity >= 0.5 && o.linkeTurbidity <= 10.0))
        throw InputError(fmt::format("insolation --linke: expected a Linke turbidity in [0.5, 10], found {}", o.linkeTurbidity));
    if (!(o.albedo >= 0.0 && o.albedo <= 1.0))
        throw InputError(fmt::format("insolation --albedo: expected a ground reflectance in [0, 1], found {}", o.albedo));
    if (o.stepSeconds < 10 || o.stepSeconds > 86400)
        throw InputError(fmt::format("insolation --step: expected 10 s to 1 d, found {} s", o.stepSeconds));
    if (o.dayStep < 1 || o.dayStep > 366)
        throw InputError(fmt::format("insolation --day-step: expected 1 to 366 days, found {}", o.dayStep));
    if (o.dates.lastDay < o.dates.firstDay) throw InputError("insolation --date: END is before START");
    const int64_t perDay = (86400 + o.stepSeconds - 1) / o.stepSeconds;
    const int64_t days = (o.dates.lastDay - o.dates.firstDay) / o.dayStep + 1;
    if (days * perDay > 200000)
        throw InputError(fmt::format("insolation: {} days of {} steps is {} sun positions, more than 200000; use a "
                                     "longer --step or --day-step", days, perDay, days * perDay));
    searchFrom(o.maxDistanceM, o.curvatureCoeff, "insolation");
    requireDirectMethod(o.method, "insolation");
}

// What an insolation product's windows share: the options, the DEM's places, and the settings whose stepsAt
// gives the sun's positions seen from any vertex.
struct InsolationPlan {
    InsolationPlan(const InsolationMapOptions& options, const LoadedDem& dem)
        : o(options), places(dem.geo, dem.path + ": insolation"),
          perDay((86400 + o.stepSeconds - 1) / o.stepSeconds) {}

    // The sun's positions seen from vertex position (col, row): each computed day starts at local mean solar
    // midnight there; its steps sample the middle of each interval (the last one shorter when the step does not
    // divide the day) and stand for dayStep days, or for the days left at the end of the span.
    std::vector<SunStep> sunSteps(double col, double row, int64_t* up) const {
        double lon = 0.0, lat = 0.0;
        places.lonLat(col, row, lon, lat);
        const double convergence = places.convergenceDeg(col, row);
        std::vector<SunStep> steps;
        for (int64_t day = o.dates.firstDay; day <= o.dates.lastDay; day += o.dayStep) {
            const double weight = double(std::min<int64_t>(o.dayStep, o.dates.lastDay - day + 1));
            const CivilDate date = civilFromDays(day);
            const double g0 =
                extraterrestrialIrradiance(double(day - daysFromCivil(date.year, 1, 1) + 1), s.sky.solarConstant);
            const double midnight = double(day) * 86400.0 - lon / 15.0 * 3600.0;
            for (int64_t k = 0; k < perDay; ++k) {
                const double a = double(k * o.stepSeconds), b = std::min(86400.0, double((k + 1) * o.stepSeconds));
                const double t = midnight + 0.5 * (a + b);
                const double whole = std::floor(t);
                std::optional<UtcInstant> when = instantFromUnixSeconds(int64_t(whole));
                if (!when) throw InputError("insolation --date: expected days within the years 0001 to 9999");
                when->second += t - whole;
                const SolarPosition p = solarPosition(*when, lat, lon);
                SunStep step;
                step.azimuthRad = radians(p.azimuthDeg + convergence);
                step.elevationRad = radians(p.elevationDeg);
                step.apparentElevationRad = radians(p.apparentElevationDeg);
                step.extraterrestrial = g0;
                step.hours = (b - a) / 3600.0 * weight;
                if (up) *up += p.elevationDeg > 0.0;
                steps.push_back(step);
            }
        }
        return steps;
    }

    InsolationMapOptions o;
    GridLonLat places;
    int64_t perDay;
    InsolationSettings s;
};

std::string dateSpanText(const DateSpan& d) {
    const CivilDate first = civilFromDays(d.firstDay), last = civilFromDays(d.lastDay);
    return fmt::format("{:04}-{:02}-{:02}/{:04}-{:02}-{:02}", first.year, first.month, first.day, last.year,
                       last.month, last.day);
}

}  // namespace

VertexProduct insolationProduct(const InsolationMapOptions& o, const LoadedDem& dem, const RunListener& listener,
                                int64_t* sunUpSteps) {
    checkInsolationOptions(o);
    auto plan = std::make_shared<InsolationPlan>(o, dem);
    InsolationSettings& s = plan->s;
    s.search = searchFrom(o.maxDistanceM, o.curvatureCoeff, "insolation");
    s.method = requireDirectMethod(o.method, "insolation");
    s.sky.linkeTurbidity = o.linkeTurbidity;
    s.sky.albedo = o.albedo;
    s.threads = o.threads;
    s.stepsAt = [p = plan.get()](double col, double row) { return p->sunSteps(col, row, nullptr); };
    const double centreCol = 0.5 * double(dem.grid.width() - 1), centreRow = 0.5 * double(dem.grid.height() - 1);
    int64_t up = 0;
    const size_t positions = plan->sunSteps(centreCol, centreRow, &up).size();
    if (sunUpSteps) *sunUpSteps = up;
    double lon = 0.0, lat = 0.0;
    plan->places.lonLat(centreCol, centreRow, lon, lat);
    const double convergence = plan->places.convergenceDeg(centreCol, centreRow);
    const std::string span = dateSpanText(o.dates);
    const int64_t days = (o.dates.lastDay - o.dates.firstDay) / o.dayStep + 1;
    const int64_t blocks = ((dem.grid.width() + InsolationSettings::kSunBlock - 1) / InsolationSettings::kSunBlock) *
                           ((dem.grid.height() + InsolationSettings::kSunBlock - 1) / InsolationSettings::kSunBlock);
    listener.tell(fmt::format("insolation over {} ({} days, {} computed), {} sun positions ({} with the sun up) over "
                              "the centre, {:.4f}, {:.4f} (lat, lon; grid north {:.2f} degrees from true north), and "
                              "over each of {} blocks of {} x {} vertices",
                              span, o.dates.lastDay - o.dates.firstDay + 1, days, positions, up, lat, lon, -convergence,
                              blocks, InsolationSettings::kSunBlock, InsolationSettings::kSunBlock));
    RasterLabels labels;
    labels.bands = {"beam (direct) irradiation", "diffuse irradiation", "ground-reflected irradiation",
                    "global irradiation", "hours of direct sun"};
    labels.units = {"Wh/m2", "Wh/m2", "Wh/m2", "Wh/m2", "h"};
    labels.metadata = {{"TERRACAST_PRODUCT", "insolation"},
                       {"TERRACAST_DATES", span},
                       {"TERRACAST_STEP_S", std::to_string(o.stepSeconds)},
                       {"TERRACAST_DAY_STEP", std::to_string(o.dayStep)},
                       {"TERRACAST_LINKE_TURBIDITY", number(o.linkeTurbidity)},
                       {"TERRACAST_ALBEDO", number(o.albedo)},
                       {"TERRACAST_SUN_PLACED", fmt::format("per block of {} x {} vertices, at its centre",
                                                            InsolationSettings::kSunBlock, InsolationSettings::kSunBlock)},
                       {"TERRACAST_MAX_DISTANCE_M", number(o.maxDistanceM)},
                       {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                       {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
    return {kInsolationBands, RasterType::Float32, -9999.0, std::move(labels),
            [&grid = dem.grid, plan](const VertexWindow& w, const MapProgress& progress) {
                InsolationSettings tile = plan->s;
                tile.window = w;
                tile.progress = progress;
                return insolationMap(grid, tile);
            }};
}

void writeInsolationMap(const InsolationMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkInsolationOptions(o);
    MapPhaseClock phases;
    const LoadedDem dem = loadDemSource(o.dem, listener, true);
    phases.demLoaded();
    int64_t up = 0;
    VertexProduct product = insolationProduct(o, dem, listener, &up);
    checkRasterJob(dem, o.dem.maxMemoryBytes, kInsolationBands, RasterType::Float32, 0.0, "insolation bands");
    phases.productPlanned();
    listener.at("insolation");
    const auto start = std::chrono::steady_clock::now();
    const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
    tellRasterSummary(listener, "insolation", o.output, count, count.width * count.height * up,
                      "vertex-sun positions", start);
    if (o.verbose) listener.tell(mapPhasesLine(phases, count));
}

namespace {

// An observer's position in local metres: within the raster's footprint (half a cell beyond the outermost
// vertices, where it stands on the nearest edge of the surface), else InputError naming `what`.
void observerToLocal(const LoadedDem& dem, double x, double y, const std::string& what, double& xM, double& yM) {
    sourceToLocal(dem, x, y, xM, yM);
    const double halfX = 0.5 * dem.grid.cellSizeXM(), halfY = 0.5 * dem.grid.cellSizeYM();
    if (!(xM >= -halfX && yM >= -halfY && xM <= dem.grid.extentXM() + halfX && yM <= dem.grid.extentYM() + halfY))
        throw InputError(fmt::format("{}: {}, {} lies outside the DEM (x {:.3f} .. {:.3f}, y {:.3f} .. {:.3f} in its CRS)",
                                     what, x, y, dem.geo.originX - 0.5 * sourcePixelSizeX(dem.geo),
                                     dem.geo.originX + (double(dem.grid.cellsX()) + 0.5) * sourcePixelSizeX(dem.geo),
                                     dem.geo.originY - 0.5 * sourcePixelSizeY(dem.geo),
                                     dem.geo.originY + (double(dem.grid.cellsY()) + 0.5) * sourcePixelSizeY(dem.geo)));
    xM = std::clamp(xM, 0.0, dem.grid.extentXM());
    yM = std::clamp(yM, 0.0, dem.grid.extentYM());
}

}  // namespace

ViewshedValues parseViewshedValues(const std::string& text, const std::string& option) {
    if (text == "visible") return ViewshedValues::Visible;
    if (text == "angle") return ViewshedValues::Angle;
    if (text == "height") return ViewshedValues::Height;
    throw InputError(fmt::format("{}: expected visible, angle or height, found '{}'", option, text));
}

namespace {

void checkViewshedOptions(const ViewshedMapOptions& o) {
    if (!o.observersFile.empty() && o.values != ViewshedValues::Visible)
        throw InputError("viewshed --values: angle and height are for one --observer; --observers counts visibility");
    if (!std::isfinite(o.observerHeightM) || !std::isfinite(o.targetHeightM) || !std::isfinite(o.curvatureCoeff))
        throw InputError("--observer-height, --target-height and --curvature-coeff must be finite numbers");
    if (!(o.maxDistanceM >= 0.0) || !std::isfinite(o.maxDistanceM))
        throw InputError(fmt::format("viewshed --max-distance: expected metres >= 0, found {}", o.maxDistanceM));
    requireDirectMethod(o.method, "viewshed");
}

// What a viewshed product's windows share: each observer's settings and place, and (unless each would hold a
// curved copy of the grid) the makers of their viewsheds, kept for the whole run.
struct ViewshedPlan {
    std::vector<ViewshedSettings> observers;
    std::vector<std::string> where;
    bool keepMakers = true;
    std::vector<std::function<MapRaster(const VertexWindow&, const MapProgress&)>> makers;

    std::function<MapRaster(const VertexWindow&, const MapProgress&)> makerFor(const HeightGrid& grid, size_t k) const {
        try {
            return viewshedMaker(grid, observers[k]);
        } catch (const GridError& e) {
            throw InputError(fmt::format("{}: {}", where[k], e.what()));
        }
    }
};

}  // namespace

VertexProduct viewshedProduct(const ViewshedMapOptions& o, const LoadedDem& dem, int64_t* observerCount) {
    checkViewshedOptions(o);
    ViewshedSettings s;
    s.method = requireDirectMethod(o.method, "viewshed");
    s.targetHeightM = o.targetHeightM;
    s.values = o.values;
    s.curvatureCoeff = o.curvatureCoeff;
    s.maxDistanceM = o.maxDistanceM;
    s.threads = o.threads;
    // The observers: one from --observer, or every point of --observers.
    std::vector<SitePoint> sites;
    if (!o.observersFile.empty()) {
        sites = readSitePoints(o.observersFile, dem.geo);
    } else {
        double x = o.observerX, y = o.observerY;
        if (o.lonLat) lonLatToSource(dem.geo, o.observerX, o.observerY, x, y);
        sites.push_back({x, y, std::nullopt, "--observer"});
    }
    auto plan = std::make_shared<ViewshedPlan>();
    for (const SitePoint& p : sites) {
        ViewshedSettings one = s;
        observerToLocal(dem, p.x, p.y, p.where, one.observerXM, one.observerYM);
        one.observerHeightM = p.heightM.value_or(o.observerHeightM);
        plan->observers.push_back(one);
        plan->where.push_back(p.where);
    }
    const size_t n = plan->observers.size();
    if (observerCount) *observerCount = int64_t(n);
    // With many observers, each one's raster beside the running count; with curvature, a lowered copy of the
    // grid (heights as floats, their validity and pyramid; for tiles, a second cache).
    const double loweredBytes =
        o.curvatureCoeff == 0.0 ? 0.0
        : dem.grid.tiled()      ? double(dem.grid.tileSource()->cacheBudgetBytes())
                                : double(dem.grid.memoryBytes()) + 5.0 * double(dem.grid.width()) * double(dem.grid.height());
    // Each observer's viewshed a window at a time. Makers are kept for the whole run, unless each would hold a
    // curved copy of the grid: then one is made per window and observer, one copy at a time.
    plan->keepMakers = n == 1 || s.curvatureCoeff == 0.0;
    // Each kept maker holds its observer's sight bounds (sight_bounds.h): while all of them together take no
    // more than the grid itself (or one observer's alone). A maker made per window would build them for the
    // whole grid each time, which costs more than it saves.
    double boundsBytes = 0.0;
    if (plan->keepMakers) {
        for (const ViewshedSettings& one : plan->observers)
            if (viewshedUsesSightBounds(dem.grid, one))
                boundsBytes += SightBounds::bytesFor(dem.grid, one.observerXM, one.observerYM);
        if (n > 1 && boundsBytes > double(dem.grid.memoryBytes())) boundsBytes = 0.0;
    }
    for (ViewshedSettings& one : plan->observers) one.boundSightLines = boundsBytes > 0.0;
    checkRasterJob(dem, o.dem.maxMemoryBytes, n > 1 ? 2 : 1, RasterType::Float32, loweredBytes + boundsBytes,
                   "the viewshed");
    if (plan->keepMakers)
        for (size_t k = 0; k < n; ++k) plan->makers.push_back(plan->makerFor(dem.grid, k));
    const auto cumulative = [&grid = dem.grid, plan](const VertexWindow& w, const MapProgress& progress) {
        MapRaster count;
        const size_t n = plan->observers.size();
        const int64_t vertices = (w.i1 - w.i0) * (w.j1 - w.j0);
        for (size_t k = 0; k < n; ++k) {
            const MapProgress one = [&, k](double f, int64_t rays) {
                progress((double(k) + f) / double(n), int64_t(k) * vertices + rays);
            };
            MapRaster seen = plan->keepMakers ? plan->makers[k](w, one) : plan->makerFor(grid, k)(w, one);
            if (k == 0) count = std::move(seen);
            else
                for (size_t v = 0; v < count.values.size(); ++v) count.values[v] += seen.values[v];
        }
        return count;
    };
    const bool many = !o.observersFile.empty();
    RasterLabels labels;
    labels.bands = {many ? "observers that see the vertex" : "visible from the observer: 1 visible, 0 hidden"};
    labels.units = {"1"};
    if (o.values == ViewshedValues::Angle) {
        labels.bands = {"elevation angle from the observer's eye to the visible target (nodata where hidden)"};
        labels.units = {"degree"};
    } else if (o.values == ViewshedValues::Height) {
        labels.bands = {"height above the ground a target needs to be seen from the observer"};
        labels.units = {"m"};
    }
    labels.metadata = {{"TERRACAST_PRODUCT", "viewshed"},
                       {"TERRACAST_OBSERVERS", many ? o.observersFile : fmt::format("{},{}", o.observerX, o.observerY)},
                       {"TERRACAST_OBSERVER_COUNT", std::to_string(n)},
                       {"TERRACAST_OBSERVER_HEIGHT_M", many ? number(o.observerHeightM) + " unless the file gives one"
                                                             : number(o.observerHeightM)},
                       {"TERRACAST_TARGET_HEIGHT_M", number(o.targetHeightM)},
                       {"TERRACAST_MAX_DISTANCE_M", number(o.maxDistanceM)},
                       {"TERRACAST_CURVATURE_COEFF", number(o.curvatureCoeff)},
                       {"TERRACAST_METHOD", surfaceMethodName(o.method)}};
    labels.metadata.emplace_back("TERRACAST_VALUES", o.values == ViewshedValues::Visible ? "visible"
                                                     : o.values == ViewshedValues::Angle ? "angle" : "height");
    // Counts up to 254 fit a byte beside the nodata value 255.
    const bool bytes = n <= 254 && o.values == ViewshedValues::Visible;
    return {1, bytes ? RasterType::Byte : RasterType::Float32, bytes ? 255.0 : -9999.0, std::move(labels), cumulative};
}

void writeViewshedMap(const ViewshedMapOptions& o, const RunListener& listener) {
    checkOutputPath(o.output, o.dem.path, {".tif", ".tiff"});
    checkViewshedOptions(o);
    // The curved earth traces a lowered copy of the grid (for tiles, a second tile cache over the same source);
    // either reads only the tiles it needs.
    MapPhaseClock phases;
    const LoadedDem dem = loadDemSource(o.dem, listener, true);
    phases.demLoaded();
    int64_t n = 1;
    VertexProduct product = viewshedProduct(o, dem, &n);  // checks the job's memory
    phases.productPlanned();
    listener.at("viewshed");
    const auto start = std::chrono::steady_clock::now();
    const bool many = !o.observersFile.empty();
    const ProductCount count = writeVertexProduct(o.output, o.resume, dem, std::move(product), o.threads, listener);
    if (many) listener.tell(fmt::format("{} observers from {}", n, o.observersFile));
    tellRasterSummary(listener, many ? "cumulative viewshed" : "viewshed", o.output, count, count.valid * n,
                      "sight lines", start);
    if (o.verbose) listener.tell(mapPhasesLine(phases, count));
}

}  // namespace terracast
