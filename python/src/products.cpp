// Every product of a height field as NumPy arrays: the per-vertex maps (shadow, horizon, viewshed, sky view,
// insolation, the map view), planned by the same functions as the CLI's commands (tracer/terrain/map_pipeline.h)
// so that an array holds the samples the command's GeoTIFF holds, and perspective renders.
#include "python/src/core.h"

#include "loaders/crs.h"
#include "loaders/image_io.h"
#include "loaders/scene_assets.h"
#include "tracer/core/errors.h"
#include "tracer/sky/calendar.h"
#include "tracer/terrain/dem_pipeline.h"
#include "tracer/terrain/map_pipeline.h"
#include "tracer/terrain/memory_model.h"
#include "tracer/terrain/tiled_product.h"

#include <pybind11/stl.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace terracast::python {

// The DEM a view is made of: the height field's own, or exaggerated: a file opened again as `--exaggeration`
// opens it, an array's heights multiplied in a copy.
std::shared_ptr<const LoadedDem> exaggerated(PyHeightField& hf, double k) {
    if (!(k > 0.0) || !std::isfinite(k))
        throw py::value_error("exaggeration: expected a positive number, found " + std::to_string(k));
    if (k == 1.0) return std::shared_ptr<const LoadedDem>(std::shared_ptr<const LoadedDem>{}, &hf.dem());
    if (hf.fromFile()) {
        DemLoadOptions options = hf.loadOptions();
        options.exaggeration = k;
        return std::make_shared<const LoadedDem>(loadDem(hf.dem().path, options));
    }
    return std::make_shared<const LoadedDem>(exaggeratedDem(hf.dem(), k));
}

py::array pictureArray(const Film& film, bool linear) {
    const std::vector<py::ssize_t> shape{film.height, film.width, 3};
    if (linear) {
        py::array_t<float> out(shape);
        std::copy(film.rgb.begin(), film.rgb.end(), out.mutable_data());
        return out;
    }
    py::array_t<uint8_t> out(shape);
    uint8_t* p = out.mutable_data();
    for (size_t k = 0; k < film.rgb.size(); ++k) p[k] = srgbByte(film.rgb[k]);
    return out;
}

namespace {

// ---- Arguments as the CLI's options take them, or in Python's own types ----

// (azimuth, elevation) in degrees, or "AZ,EL" as --sun.
void sunOf(const py::object& sun, double& az, double& el) {
    if (py::isinstance<py::str>(sun)) {
        const std::string text = sun.cast<std::string>();
        char comma = 0;
        std::istringstream in(text);
        if (!(in >> az >> comma >> el) || comma != ',' || !(in >> std::ws).eof() || !std::isfinite(az) ||
            !std::isfinite(el))
            throw py::value_error("sun: expected (azimuth, elevation) in degrees or 'AZ,EL', found '" + text + "'");
        return;
    }
    std::vector<double> v;
    try {
        v = sun.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
        v.clear();
    }
    if (v.size() != 2)
        throw py::value_error("sun: expected (azimuth, elevation) in degrees, found " + py::repr(sun).cast<std::string>());
    az = v[0];
    el = v[1];
    if (!std::isfinite(az) || !std::isfinite(el))
        throw py::value_error("sun: expected finite degrees, found " + py::repr(sun).cast<std::string>());
}

// An instant: ISO 8601 text with a zone (as --sun-time) or a timezone-aware datetime.
UtcInstant instantOf(const py::object& when, const char* what) {
    std::string text;
    if (py::isinstance<py::str>(when)) {
        text = when.cast<std::string>();
    } else if (py::hasattr(when, "utcoffset") && py::hasattr(when, "astimezone")) {
        if (when.attr("utcoffset")().is_none())
            throw py::value_error(std::string(what) + ": expected a timezone-aware datetime (tzinfo set), found " +
                                  py::repr(when).cast<std::string>());
        const py::object utc = py::module_::import("datetime").attr("timezone").attr("utc");
        text = when.attr("astimezone")(utc).attr("strftime")("%Y-%m-%dT%H:%M:%SZ").cast<std::string>();
    } else {
        throw py::value_error(std::string(what) + ": expected ISO 8601 text such as 2026-06-21T19:30Z or a datetime, "
                                                  "found " + py::repr(when).cast<std::string>());
    }
    std::string why;
    const auto utc = parseIsoTime(text, why);
    if (!utc) throw py::value_error(std::string(what) + ": expected an ISO 8601 time such as 2026-06-21T19:30Z, found '" + text + "' (" + why + ")");
    return *utc;
}

// sun_time of `shadow`: one instant (a 2-D mask), 'START/END/STEP' as --sun-time, or a list of instants.
std::vector<UtcInstant> sunTimesOf(const py::object& times, bool& single) {
    single = false;
    if (py::isinstance<py::str>(times)) {
        const std::string text = times.cast<std::string>();
        if (text.find('/') != std::string::npos) return parseSunTimeRange(text, "sun_time");
        single = true;
        return {instantOf(times, "sun_time")};
    }
    if (py::isinstance<py::sequence>(times)) {
        std::vector<UtcInstant> out;
        for (const py::handle h : times) out.push_back(instantOf(py::reinterpret_borrow<py::object>(h), "sun_time"));
        if (out.empty() || out.size() > 3600)
            throw py::value_error("sun_time: expected 1 to 3600 instants, found " + std::to_string(out.size()));
        return out;
    }
    single = true;
    return {instantOf(times, "sun_time")};
}

int threadsOf(int threads) {
    if (threads < 0 || threads > 4096)
        throw py::value_error("threads: expected 0 (all cores) to 4096, found " + std::to_string(threads));
    return threads;
}

// The options every terrain map takes: its search radius and curvature, the method and the threads.
template <class Options>
void searchOptions(Options& o, double maxDistance, double curvatureCoeff, const std::string& method, int threads) {
    o.maxDistanceM = maxDistance;
    o.curvatureCoeff = curvatureCoeff;
    o.method = methodOf(method);
    o.threads = threadsOf(threads);
}

// ---- Products ----

// A per-vertex product computed whole into a new array of the samples its GeoTIFF holds: uint8 (nodata as the
// product's value, 255) or float32 (NaN where the file holds nodata), shape (rows, columns) for one band and
// (rows, columns, bands) otherwise, row 0 north.
py::array productArray(const LoadedDem& dem, const VertexProduct& product, const py::object& progress,
                       bool oneBand) {
    // The array and a band of rows beside it, against 80 % of the machine's memory, as the command checks its job.
    checkRasterJob(dem, 0.0, product.bands, product.type, 0.0, "the array");
    const HeightGrid& grid = dem.grid;
    std::vector<py::ssize_t> shape{py::ssize_t(grid.height()), py::ssize_t(grid.width())};
    if (!(oneBand && product.bands == 1)) shape.push_back(product.bands);
    py::array out = product.type == RasterType::Byte ? py::array(py::dtype::of<uint8_t>(), shape)
                                                     : py::array(py::dtype::of<float>(), shape);
    void* data = out.mutable_data();
    runWatched<int64_t>(progress, [&](WorkProgress& state) {
        return computeVertexProduct(grid, product, data, [&](double f, int64_t rays) { state(f, rays); });
    });
    return out;
}

DemSource sourceOf(const PyHeightField& hf) {
    DemSource s;
    s.path = hf.dem().path;
    return s;
}

py::array shadow(PyHeightField& hf, const py::object& sun, double sunSize, const py::object& sunTime,
                 double maxDistance, double curvatureCoeff, const std::string& method, int threads,
                 const py::object& progress) {
    ShadowMapOptions o;
    o.dem = sourceOf(hf);
    sunOf(sun, o.sunAzimuthDeg, o.sunElevationDeg);
    o.sunSizeDeg = sunSize;
    bool single = true;
    if (!sunTime.is_none()) o.sunTimes = sunTimesOf(sunTime, single);
    searchOptions(o, maxDistance, curvatureCoeff, method, threads);
    const VertexProduct product = shadowProduct(o, hf.dem(), RunListener{});
    return productArray(hf.dem(), product, progress, single);
}

py::array horizon(PyHeightField& hf, const py::object& azimuth, const py::object& azimuths, double maxDistance,
                  double curvatureCoeff, const std::string& method, int threads, const py::object& progress) {
    HorizonMapOptions o;
    o.dem = sourceOf(hf);
    if (azimuth.is_none() == azimuths.is_none())
        throw py::value_error("horizon: give azimuth=DEGREES or azimuths='START:END:STEP' (or a list), one of them");
    bool single = false;
    if (!azimuth.is_none()) {
        o.azimuthsDeg = {azimuth.cast<double>()};
        single = true;
    } else if (py::isinstance<py::str>(azimuths)) {
        o.azimuthsDeg = parseAzimuthRange(azimuths.cast<std::string>(), "azimuths");
    } else {
        o.azimuthsDeg = azimuths.cast<std::vector<double>>();
    }
    searchOptions(o, maxDistance, curvatureCoeff, method, threads);
    const VertexProduct product = horizonProduct(o, hf.dem());
    return productArray(hf.dem(), product, progress, single);
}

py::array skyView(PyHeightField& hf, int directions, double maxDistance, double curvatureCoeff,
                  const std::string& method, int threads, const py::object& progress) {
    SkyViewMapOptions o;
    o.dem = sourceOf(hf);
    o.directions = directions;
    searchOptions(o, maxDistance, curvatureCoeff, method, threads);
    const VertexProduct product = skyViewProduct(o, hf.dem());
    return productArray(hf.dem(), product, progress, false);
}

py::array insolation(PyHeightField& hf, const std::string& date, const std::string& step, int dayStep, double linke,
                     double albedo, double maxDistance, double curvatureCoeff, const std::string& method, int threads,
                     const py::object& progress) {
    InsolationMapOptions o;
    o.dem = sourceOf(hf);
    o.dates = parseDateSpan(date, "date");
    o.stepSeconds = parseDurationSeconds(step, "step");
    o.dayStep = dayStep;
    o.linkeTurbidity = linke;
    o.albedo = albedo;
    searchOptions(o, maxDistance, curvatureCoeff, method, threads);
    const VertexProduct product = insolationProduct(o, hf.dem(), RunListener{});
    return productArray(hf.dem(), product, progress, false);
}

py::array viewshed(PyHeightField& hf, const py::object& observer, const py::object& observers, bool lonlat,
                   double observerHeight, double targetHeight, const std::string& values, double curvatureCoeff,
                   double maxDistance, const std::string& method, int threads, const py::object& progress) {
    ViewshedMapOptions o;
    o.dem = sourceOf(hf);
    if (observer.is_none() == observers.is_none())
        throw py::value_error("viewshed: give observer=(x, y) or observers=FILE, one of them");
    if (!observer.is_none()) {
        const auto xy = observer.cast<std::vector<double>>();
        if (xy.size() != 2) throw py::value_error("observer: expected (x, y) in the DEM's CRS (lon, lat with lonlat=True)");
        o.observerX = xy[0];
        o.observerY = xy[1];
    } else {
        o.observersFile = py::str(observers).cast<std::string>();
    }
    o.lonLat = lonlat;
    o.observerHeightM = observerHeight;
    o.targetHeightM = targetHeight;
    o.values = parseViewshedValues(values, "values");
    searchOptions(o, maxDistance, curvatureCoeff, method, threads);
    const VertexProduct product = viewshedProduct(o, hf.dem());
    return productArray(hf.dem(), product, progress, true);
}

// The options render and map_view share.
DemRenderOptions viewOptions(PyHeightField& hf, const py::object& sun, const py::object& sunTime,
                             double exaggeration, const std::string& method, int threads, int skySamples) {
    DemRenderOptions o;
    o.dem = sourceOf(hf);
    sunOf(sun, o.sunAzimuthDeg, o.sunElevationDeg);
    if (!sunTime.is_none()) o.sunTime = instantOf(sunTime, "sun_time");
    o.exaggeration = exaggeration;
    o.method = methodOf(method);
    o.threads = threadsOf(threads);
    o.skySamples = skySamples;
    return o;
}

py::array mapView(PyHeightField& hf, const py::object& sun, const py::object& sunTime, double scale,
                  bool noShadows, int skySamples, const std::string& colour, double hillshadeBlend,
                  double exaggeration, const std::string& method, int threads, const py::object& progress) {
    DemRenderOptions o = viewOptions(hf, sun, sunTime, exaggeration, method, threads, skySamples);
    o.mapView = true;
    o.scale = scale;
    o.castShadows = !noShadows;
    if (colour != "grey" && colour != "ramp")
        throw py::value_error("colour: expected grey or ramp, found '" + colour + "'");
    o.colourRamp = colour == "ramp";
    o.hillshadeBlend = hillshadeBlend;
    checkMapViewOptions(o);
    const std::shared_ptr<const LoadedDem> dem = exaggerated(hf, exaggeration);
    MapViewSettings m = mapViewSettings(o, *dem, RunListener{});
    if (scale == 1.0 && o.method != SurfaceMethod::Nearest) {
        // The map view on the DEM's own grid: the samples of `render --view map -o MAP.tif`.
        const VertexProduct product = mapViewProduct(m, *dem);
        return productArray(*dem, product, progress, false);
    }
    // Any other scale: one picture held whole, as `render --view map` writes it at that scale (its film, its
    // coverage and the array).
    const double area = std::ceil(double(dem->grid.width()) * scale) * std::ceil(double(dem->grid.height()) * scale);
    checkMemory(dem->path, 0.0, dem->grid, area * (kFilmBytesPerPixel + 1.0 + 8.0),
                "the map view at scale " + std::to_string(scale));
    const MapImage image = runWatched<MapImage>(progress, [&](WorkProgress& state) {
        m.progress = [&](double f, int64_t r) { state(f, r); };
        return renderMapView(dem->grid, m);
    });
    const std::vector<uint8_t> pixels = mapViewPixels(image);
    py::array_t<uint8_t> out({py::ssize_t(image.film.height), py::ssize_t(image.film.width), py::ssize_t(4)});
    std::copy(pixels.begin(), pixels.end(), out.mutable_data());
    return out;
}

void sizeOf(const py::object& size, int& width, int& height) {
    if (py::isinstance<py::str>(size)) {
        const std::string text = size.cast<std::string>();
        char x = 0;
        std::istringstream in(text);
        if (!(in >> width >> x >> height) || x != 'x' || !(in >> std::ws).eof())
            throw py::value_error("size: expected (width, height) or 'WxH' in pixels, found '" + text + "'");
        return;
    }
    const auto wh = size.cast<std::vector<int>>();
    if (wh.size() != 2) throw py::value_error("size: expected (width, height) in pixels");
    width = wh[0];
    height = wh[1];
}

py::array render(PyHeightField& hf, const py::object& size, const py::object& sun, const py::object& sunTime,
                 double exaggeration, const py::object& camera, const std::string& view, const std::string& method,
                 int threads, int spp, const std::string& sampler, const std::string& filter,
                 const py::object& adaptive, const std::string& sky, double haze, int skySamples, uint64_t seed,
                 const std::string& normals, const py::object& colour, const py::object& drape, bool noBase,
                 const std::string& background, bool linear, const py::object& progress) {
    DemRenderOptions o = viewOptions(hf, sun, sunTime, exaggeration, method, threads, skySamples);
    sizeOf(size, o.width, o.height);
    if (view == "perspective") o.cameraKind = CameraKind::Pinhole;
    else if (view == "orthographic") o.cameraKind = CameraKind::Orthographic;
    else if (view == "panorama") o.cameraKind = CameraKind::Panorama;
    else if (view == "fisheye") o.cameraKind = CameraKind::Fisheye;
    else
        throw py::value_error("view: expected perspective, orthographic, panorama or fisheye (the map view is "
                              "HeightField.map_view), found '" + view + "'");
    if (!camera.is_none()) {
        PinholeCamera c;
        if (auto err = parseCamera(camera.cast<std::string>(), c, o.cameraKind == CameraKind::Fisheye))
            throw py::value_error("camera: " + *err);
        o.camera = c;
    }
    o.samples = spp;
    const auto pattern = parseSamplePattern(sampler);
    if (!pattern) throw py::value_error("sampler: expected one of " + std::string(samplePatternList()) + ", found '" + sampler + "'");
    o.sampler = *pattern;
    const auto kind = parseFilterKind(filter);
    if (!kind) throw py::value_error("filter: expected one of " + std::string(filterKindList()) + ", found '" + filter + "'");
    o.filter = *kind;
    if (!adaptive.is_none()) {
        o.adaptive = true;
        o.adaptiveError = adaptive.cast<double>();
    }
    const auto skyKind = parseSkyKind(sky);
    if (!skyKind) throw py::value_error("sky: expected physical, gradient, flat or none, found '" + sky + "'");
    o.sky = *skyKind;
    o.haze = haze;
    o.seed = seed;
    if (normals != "smooth" && normals != "facet")
        throw py::value_error("normals: expected smooth or facet, found '" + normals + "'");
    o.smoothNormals = normals == "smooth";
    if (!drape.is_none()) {
        if (!colour.is_none()) throw py::value_error("drape and colour both set the terrain's colour: give one");
        o.drape = py::str(drape).cast<std::string>();
        o.colouring = TerrainLook::Colouring::Drape;
    } else if (!colour.is_none()) {
        const std::string c = colour.cast<std::string>();
        const std::optional<glm::vec3> hex = parseHexColour(c);
        if (c == "grey") o.colouring = TerrainLook::Colouring::Plain;
        else if (hex) {
            o.colouring = TerrainLook::Colouring::Plain;
            o.plainColour = *hex;
        } else if (c != "ramp")
            throw py::value_error("colour: expected ramp, grey or a colour as #rrggbb, found '" + c + "'");
    }
    o.solidBase = !noBase;
    const auto backdrop = parseBackdrop(background);
    if (!backdrop) throw py::value_error("background: expected neutral, sky or ground, found '" + background + "'");
    o.backdrop = *backdrop;

    checkPerspectiveOptions(o);
    const std::shared_ptr<const LoadedDem> dem = exaggerated(hf, exaggeration);
    TerrainRenderSettings s = perspectiveSettings(o, *dem, RunListener{});
    // The film and the array, Embree's scene and a drape's three floats a vertex, as `render` checks its job.
    const double drapeBytes =
        o.drape.empty() ? 0.0 : 12.0 * double(dem->grid.width()) * double(dem->grid.height());
    checkMemory(dem->path, 0.0, dem->grid,
                double(o.width) * o.height * (kFilmBytesPerPixel + (linear ? 12.0 : 3.0)) +
                    embreeBytesEstimate(o.method, dem->grid) + drapeBytes,
                "rendering " + std::to_string(o.width) + "x" + std::to_string(o.height));
    if (!o.drape.empty())
        s.look.drape = std::make_shared<const DrapeImage>(loadDrape(o.drape, dem->geo, dem->grid.width(), dem->grid.height()));
    const Film film = runWatched<Film>(progress, [&](WorkProgress& watched) {
        s.progress = [&](double f, int64_t r) { watched(f, r); };
        const TerrainSurface surface(dem->grid, o.method, o.threads);
        return renderTerrain(dem->grid, surface, s);
    });
    return pictureArray(film, linear);
}

py::tuple sunAt(PyHeightField& hf, const py::object& when) {
    double az = 0.0, el = 0.0;
    placeSunOverGrid(instantOf(when, "when"), hf.dem().geo, hf.grid().width(), hf.grid().height(),
                     hf.dem().path + ": sun_at", az, el);
    return py::make_tuple(az, el);
}

}  // namespace

void bindProducts(py::module_&, py::class_<PyHeightField>& cls) {
    const auto commonDoc =
        "max_distance: metres beyond which terrain does not count (default 0: the whole DEM).\n"
        "curvature_coeff: earth curvature less refraction (0.85714 for standard refraction; default 0: flat).\n"
        "method: a direct cell method: bilinear (default), bilinear-double, triangles, nearest, reference.\n"
        "threads: worker threads, 0 = all cores (default).\n"
        "progress: None or a function called with (share done, rays so far) while it runs.\n"
        "The GIL is released while it runs; Ctrl-C stops it between tiles and raises KeyboardInterrupt.";
    cls.def("sun_at", &sunAt, py::arg("when"),
            "Where the sun stands at an instant over the DEM's centre, as sun_time places it: (azimuth,\n"
            "elevation) in degrees, the azimuth clockwise from the grid's north, the apparent elevation with\n"
            "refraction (NOAA's equations).\n\n"
            "when: an ISO 8601 time such as '2026-06-21T15:00Z' or an aware datetime. The DEM needs a CRS.");
    cls.def("shadow", &shadow, py::arg("sun") = py::make_tuple(315.0, 35.0), py::kw_only(), py::arg("sun_size") = 0.0,
            py::arg("sun_time") = py::none(), py::arg("max_distance") = 0.0, py::arg("curvature_coeff") = 0.0,
            py::arg("method") = "bilinear", py::arg("threads") = 0, py::arg("progress") = py::none(),
            (std::string("Sun shadow mask per DEM vertex, as `terracast shadow` writes it: an array of the DEM's\n"
                         "shape, row 0 north.\n\n"
                         "A point sun gives uint8: 1 shadowed, 0 lit, 255 on nodata. With sun_size > 0 the sun is a\n"
                         "disc and the values are the share of it hidden (float32, NaN on nodata).\n\n"
                         "sun: (azimuth, elevation) in degrees, azimuth clockwise from north (default (315, 35)).\n"
                         "sun_size: the sun's angular diameter in degrees (default 0: a point).\n"
                         "sun_time: instead of sun, where the sun stands over the DEM's centre (the DEM needs a CRS):\n"
                         "  an ISO 8601 time such as '2026-06-21T15:00Z' or an aware datetime (a 2-D mask), or\n"
                         "  'START/END/STEP' (such as '2026-06-21T04:00Z/2026-06-21T20:00Z/1h') or a list of times\n"
                         "  (one band per time: shape (rows, columns, times)).\n") +
             commonDoc)
                .c_str())
        .def("horizon", &horizon, py::arg("azimuth") = py::none(), py::kw_only(), py::arg("azimuths") = py::none(),
             py::arg("max_distance") = 0.0, py::arg("curvature_coeff") = 0.0, py::arg("method") = "bilinear",
             py::arg("threads") = 0, py::arg("progress") = py::none(),
             (std::string("Horizon elevation angle in degrees per DEM vertex, as `terracast horizon` writes it\n"
                          "(float32, NaN on nodata, -90 where no surface lies that way), row 0 north.\n\n"
                          "azimuth: degrees clockwise from north: one 2-D array.\n"
                          "azimuths: 'START:END:STEP' (END excluded, such as '0:360:15') or a list of degrees:\n"
                          "  shape (rows, columns, azimuths), in one pass.\n") +
              commonDoc)
                 .c_str())
        .def("viewshed", &viewshed, py::arg("observer") = py::none(), py::kw_only(), py::arg("observers") = py::none(),
             py::arg("lonlat") = false, py::arg("observer_height") = 1.7, py::arg("target_height") = 0.0,
             py::arg("values") = "visible", py::arg("curvature_coeff") = 0.85714, py::arg("max_distance") = 0.0,
             py::arg("method") = "bilinear", py::arg("threads") = 0, py::arg("progress") = py::none(),
             "Visibility from an observer per DEM vertex, as `terracast viewshed` writes it, row 0 north.\n\n"
             "observer: (x, y) in the DEM's CRS (longitude, latitude with lonlat=True).\n"
             "observers: instead, a CSV of X,Y[,HEIGHT] or a vector file of points: how many see each vertex.\n"
             "observer_height, target_height: metres above the terrain (defaults 1.7 and 0).\n"
             "values: 'visible' (uint8: 1 visible, 0 hidden, 255 on nodata; counts with observers), 'angle'\n"
             "  (float32 degrees from the eye, NaN where hidden) or 'height' (float32 metres a target needs).\n"
             "curvature_coeff: as gdal_viewshed -cc (default 0.85714; 0 = flat earth).\n"
             "max_distance: targets farther (metres) are not seen (default 0: no limit).\n"
             "method, threads, progress: as shadow's.")
        .def("svf", &skyView, py::kw_only(), py::arg("directions") = 16, py::arg("max_distance") = 0.0,
             py::arg("curvature_coeff") = 0.0, py::arg("method") = "bilinear", py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             "Sky-view factor, positive and negative openness per DEM vertex, as `terracast svf` writes them:\n"
             "float32 (rows, columns, 3), NaN on nodata.\n\n"
             "directions: azimuths, evenly spaced from north (default 16).\n"
             "max_distance: search radius in metres (default 0: 10 cells).\n"
             "curvature_coeff, method, threads, progress: as shadow's.")
        .def("insolation", &insolation, py::arg("date"), py::kw_only(), py::arg("step") = "30m",
             py::arg("day_step") = 1, py::arg("linke") = 3.0, py::arg("albedo") = 0.2, py::arg("max_distance") = 0.0,
             py::arg("curvature_coeff") = 0.0, py::arg("method") = "bilinear", py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             "Clear-sky beam, diffuse, reflected and global irradiation (Wh/m2) and hours of direct sun per DEM\n"
             "vertex, as `terracast insolation` writes them: float32 (rows, columns, 5), NaN on nodata.\n\n"
             "date: 'YYYY-MM-DD' or 'START/END' (END included), local solar days; the DEM needs a CRS.\n"
             "step: time step within a day, such as '30m' or '1h' (default '30m').\n"
             "day_step: compute every n-th day, each standing for n days (default 1).\n"
             "linke: Linke turbidity (default 3.0). albedo: ground reflectance (default 0.2).\n"
             "max_distance, curvature_coeff, method, threads, progress: as shadow's.")
        .def("map_view", &mapView, py::arg("sun") = py::make_tuple(315.0, 35.0), py::kw_only(),
             py::arg("sun_time") = py::none(), py::arg("scale") = 1.0, py::arg("no_shadows") = false,
             py::arg("sky_samples") = -1, py::arg("colour") = "grey", py::arg("hillshade_blend") = 0.0,
             py::arg("exaggeration") = 1.0, py::arg("method") = "bilinear", py::arg("threads") = 0,
             py::arg("progress") = py::none(),
             "The top-down shaded relief on the DEM's own grid, as `terracast render --view map` writes it:\n"
             "uint8 (rows, columns, 4): sRGB and alpha (255 over the terrain, 0 over nodata), row 0 north.\n\n"
             "sun, sun_time: as shadow's (one instant). scale: output pixels per cell (default 1).\n"
             "no_shadows: no cast shadows (default False). sky_samples: sky-visibility rays per pixel\n"
             "(default -1: 16). colour: 'grey' (default) or 'ramp' (by elevation). hillshade_blend: weight of a\n"
             "plain hillshade, 0..1 (default 0). exaggeration: vertical scale factor (default 1).\n"
             "method, threads, progress: as shadow's.")
        .def("render", &render, py::kw_only(), py::arg("size") = py::make_tuple(1280, 720),
             py::arg("sun") = py::make_tuple(315.0, 35.0), py::arg("sun_time") = py::none(),
             py::arg("exaggeration") = 1.0, py::arg("camera") = py::none(), py::arg("view") = "perspective",
             py::arg("method") = "bilinear", py::arg("threads") = 0, py::arg("spp") = 1,
             py::arg("sampler") = "stratified", py::arg("filter") = "box", py::arg("adaptive") = py::none(),
             py::arg("sky") = "physical", py::arg("haze") = 1.0, py::arg("sky_samples") = -1, py::arg("seed") = 0,
             py::arg("normals") = "smooth", py::arg("colour") = py::none(), py::arg("drape") = py::none(),
             py::arg("no_base") = false, py::arg("background") = "neutral", py::arg("linear") = false,
             py::arg("progress") = py::none(),
             "A shaded 3D view of the DEM, as `terracast render -o VIEW.png` makes it: uint8 sRGB (height,\n"
             "width, 3), or float32 linear RGB with linear=True (what a .exr holds), row 0 at the top.\n\n"
             "size: (width, height) or 'WxH' in pixels (default (1280, 720)).\n"
             "sun, sun_time: as shadow's (one instant). exaggeration: vertical scale factor (default 1).\n"
             "camera: 'eye=x,y,z look=x,y,z fov=deg' in local metres (default: the automatic view).\n"
             "view: perspective (default), orthographic, panorama or fisheye.\n"
             "method: bilinear (default), bilinear-double, triangles, nearest, reference, embree, embree-grid.\n"
             "spp: camera samples per pixel (default 1); sampler: regular, random, stratified (default), poisson,\n"
             "best-candidate; filter: box (default), tent, gaussian; adaptive: None or the standard error of a\n"
             "pixel's luminance to reach, up to spp samples.\n"
             "sky: physical (default), gradient, flat or none; haze: multiplies aerosol scattering (default 1);\n"
             "sky_samples: sky-visibility rays per hit (default -1: 4); seed: their random seed (default 0).\n"
             "normals: smooth (default) or facet. colour: 'ramp' (default), 'grey' or '#rrggbb'.\n"
             "drape: an image file GDAL reads, warped onto the DEM. no_base: no solid base (default False).\n"
             "background: neutral (default), sky or ground.\n"
             "threads, progress: as shadow's.");
}

}  // namespace terracast::python
