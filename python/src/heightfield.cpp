// terracast.HeightField: height fields from files or NumPy arrays, and batch ray queries against them, threaded
// and with the GIL released.
#include "python/src/core.h"

#include "tracer/core/errors.h"

#include <pybind11/stl.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>
#include <vector>

namespace terracast::python {

SurfaceMethod methodOf(const std::string& name) {
    const auto m = parseSurfaceMethod(name);
    if (!m) throw py::value_error("method: expected one of " + std::string(surfaceMethodList()) + ", found '" + name + "'");
    return *m;
}

namespace {

// (N, 3) float64 arrays of origins and directions, checked.
using Rays = py::array_t<double, py::array::c_style | py::array::forcecast>;
size_t rayCount(const Rays& origins, const Rays& directions) {
    if (origins.ndim() != 2 || origins.shape(1) != 3)
        throw py::value_error("origins: expected an (N, 3) array, found " + std::to_string(origins.ndim()) +
                              " dimensions" + (origins.ndim() == 2 ? " of width " + std::to_string(origins.shape(1)) : ""));
    if (directions.ndim() != 2 || directions.shape(1) != 3 || directions.shape(0) != origins.shape(0))
        throw py::value_error("directions: expected an (N, 3) array matching origins (N = " +
                              std::to_string(origins.shape(0)) + ")");
    return size_t(origins.shape(0));
}

void checkThreads(int threads) {
    if (threads < 0 || threads > 4096) throw py::value_error("threads: expected 0 (all cores) to 4096, found " + std::to_string(threads));
}

Ray rayAt(const double* o, const double* d, size_t k) {
    return Ray{{o[3 * k], o[3 * k + 1], o[3 * k + 2]}, {d[3 * k], d[3 * k + 1], d[3 * k + 2]}};
}

// Where each ray's search ends, in units of its direction's length: None (no end), one number, or one per ray.
class RayEnds {
public:
    RayEnds(const py::object& tMax, size_t n) {
        if (tMax.is_none()) return;
        if (py::isinstance<py::float_>(tMax) || py::isinstance<py::int_>(tMax)) {
            one_ = tMax.cast<double>();
        } else {
            array_ = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(tMax);
            if (!array_ || array_.ndim() != 1 || size_t(array_.shape(0)) != n)
                throw py::value_error("t_max: expected a number or an (N,) array matching the rays (N = " +
                                      std::to_string(n) + ")");
            each_ = array_.data();
        }
        for (size_t k = 0; k < (each_ ? n : 1); ++k) {
            const double t = each_ ? each_[k] : one_;
            if (!(t > 0.0)) throw py::value_error("t_max: expected distances > 0, found " + std::to_string(t));
        }
    }
    Interval at(size_t k) const { return {0.0, each_ ? each_[k] : one_}; }

private:
    double one_ = kInfinity;
    py::array_t<double, py::array::c_style | py::array::forcecast> array_;
    const double* each_ = nullptr;
};

// Calls body(k) for every ray on `threads` threads (0: all cores), watched (core.h): progress counts rays, and a
// cancellation skips the remaining chunks.
// The seconds the last forEachRay spent in its loop over the rays, for the bench: what a Python call takes
// beyond it is the binding's overhead.
std::atomic<double> lastLoopSeconds{0.0};

void forEachRay(size_t n, int threads, const py::object& progress, const std::function<void(size_t)>& body) {
    runWatched<int>(progress, [&](WorkProgress& state) {
        const auto start = std::chrono::steady_clock::now();
        std::atomic<int64_t> done{0};
        tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
        arena.execute([&] {
            tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
                if (cancelFlag().load(std::memory_order_relaxed)) return;
                for (size_t k = r.begin(); k < r.end(); ++k) body(k);
                const int64_t total = done.fetch_add(int64_t(r.size())) + int64_t(r.size());
                state(n > 0 ? double(total) / double(n) : 1.0, total);
            });
        });
        lastLoopSeconds.store(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        throwIfCancelled();
        return 0;
    });
}

py::dict traceFirstHits(PyHeightField& hf, const Rays& origins, const Rays& directions, const std::string& method,
                        const py::object& tMax, int threads, const py::object& progress) {
    const size_t n = rayCount(origins, directions);
    const RayEnds ends(tMax, n);
    checkThreads(threads);
    const TerrainSurface& surface = hf.surface(methodOf(method));
    py::array_t<double> t{py::ssize_t(n)};
    py::array_t<double> point({py::ssize_t(n), py::ssize_t(3)}), normal({py::ssize_t(n), py::ssize_t(3)});
    py::array_t<bool> hit{py::ssize_t(n)};
    const double* o = origins.data();
    const double* d = directions.data();
    double* tp = t.mutable_data();
    double* pp = point.mutable_data();
    double* np = normal.mutable_data();
    bool* hp = hit.mutable_data();
    forEachRay(n, threads, progress, [&](size_t k) {
        const auto h = surface.intersect(rayAt(o, d, k), ends.at(k));
        hp[k] = h.has_value();
        tp[k] = h ? h->t : std::numeric_limits<double>::infinity();
        for (int c = 0; c < 3; ++c) {
            pp[3 * k + c] = h ? h->pointM[c] : std::numeric_limits<double>::quiet_NaN();
            np[3 * k + c] = h ? h->normal[c] : std::numeric_limits<double>::quiet_NaN();
        }
    });
    py::dict out;
    out["t"] = t;
    out["point"] = point;
    out["normal"] = normal;
    out["hit"] = hit;
    return out;
}

py::array_t<bool> traceOcclusion(PyHeightField& hf, const Rays& origins, const Rays& directions,
                                 const std::string& method, const py::object& tMax, int threads,
                                 const py::object& progress) {
    const size_t n = rayCount(origins, directions);
    const RayEnds ends(tMax, n);
    checkThreads(threads);
    const TerrainSurface& surface = hf.surface(methodOf(method));
    py::array_t<bool> out{py::ssize_t(n)};
    const double* o = origins.data();
    const double* d = directions.data();
    bool* p = out.mutable_data();
    forEachRay(n, threads, progress, [&](size_t k) { p[k] = surface.occluded(rayAt(o, d, k), ends.at(k)); });
    return out;
}

// A 2-D array of heights into a grid (row 0 at the south): array row 0 is the north edge unless `flipRows` is
// false, column 0 the west edge unless `flipColumns`.
template <class T>
HeightGrid gridFromArray(const py::array& a, const ArrayPlacement& place, std::optional<double> nodata) {
    const auto typed = py::array_t<T, py::array::forcecast>::ensure(a);
    const py::ssize_t rows = a.shape(0), cols = a.shape(1);
    std::vector<float> heights(size_t(rows * cols));
    std::vector<uint8_t> valid;
    bool anyNodata = false;
    const auto view = typed.template unchecked<2>();
    for (py::ssize_t r = 0; r < rows; ++r)
        for (py::ssize_t c = 0; c < cols; ++c) {
            const double v = double(view(r, c));
            const size_t k = size_t((place.flipRows ? rows - 1 - r : r) * cols + (place.flipColumns ? cols - 1 - c : c));
            const bool hole = (nodata && (v == *nodata || (std::isnan(*nodata) && std::isnan(v))));
            if (!hole && !std::isfinite(v))
                throw py::value_error("heights: expected finite numbers (or give nodata=), found " + std::to_string(v) +
                                      " at row " + std::to_string(r) + ", column " + std::to_string(c));
            if (hole && !anyNodata) {
                valid.assign(heights.size(), 1);
                anyNodata = true;
            }
            if (hole) valid[k] = 0;
            heights[k] = hole ? 0.0f : float(v);
        }
    return HeightGrid(cols, rows, place.cellSizeXM, place.cellSizeYM, std::move(heights), std::move(valid));
}

// A geotransform from a GDAL-style 6-tuple, an affine 6-tuple (a, b, c, d, e, f: x = a col + b row + c, y = d col
// + e row + f, as rasterio writes it), a 9-term affine matrix, or an object with to_gdal() (rasterio's Affine).
std::vector<double> geoTransformOf(const py::object& t) {
    if (py::hasattr(t, "to_gdal")) {
        const auto gt = t.attr("to_gdal")().cast<std::vector<double>>();
        if (gt.size() != 6) throw py::value_error("transform: to_gdal() gave " + std::to_string(gt.size()) + " numbers, expected 6");
        return gt;
    }
    std::vector<double> v;
    try {
        v = t.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
        throw py::value_error("transform: expected 6 numbers (a GDAL geotransform or an affine), found " +
                              py::repr(t).cast<std::string>());
    }
    if (v.size() == 9) {
        if (v[6] != 0.0 || v[7] != 0.0 || v[8] != 1.0)
            throw py::value_error("transform: a 9-term affine must end 0, 0, 1");
        v.resize(6);
    } else if (v.size() != 6) {
        throw py::value_error("transform: expected 6 numbers (a GDAL geotransform or an affine), found " +
                              std::to_string(v.size()));
    }
    // North-up rasters tell the two orders apart: GDAL's has its rotation terms at 2 and 4 and a pixel width at
    // 1; an affine has them at 1 and 3 and its pixel width at 0.
    const bool gdal = v[1] != 0.0 && v[2] == 0.0 && v[4] == 0.0;
    const bool affine = v[0] != 0.0 && v[1] == 0.0 && v[3] == 0.0;
    if (affine && !gdal) return {v[2], v[0], v[1], v[5], v[3], v[4]};
    return v;
}

std::string crsText(const py::object& crs) {
    if (crs.is_none()) return "";
    if (py::isinstance<py::int_>(crs)) return "EPSG:" + std::to_string(crs.cast<int64_t>());
    if (py::isinstance<py::str>(crs)) return crs.cast<std::string>();
    if (py::hasattr(crs, "to_wkt")) return crs.attr("to_wkt")().cast<std::string>();
    throw py::value_error("crs: expected WKT, a PROJ string, 'EPSG:n' or an EPSG code, found " +
                          py::repr(crs).cast<std::string>());
}

std::unique_ptr<PyHeightField> fromArray(const py::array& heights, const py::object& cellSize, std::optional<double> nodata,
                                         const py::object& transform, const py::object& crs) {
    if (heights.ndim() != 2)
        throw py::value_error("heights: expected a 2-D array, found " + std::to_string(heights.ndim()) + " dimensions");
    if (heights.shape(0) < 2 || heights.shape(1) < 2)
        throw py::value_error("heights: expected at least 2 x 2 samples, found " + std::to_string(heights.shape(0)) +
                              " x " + std::to_string(heights.shape(1)));
    if (!transform.is_none() && !cellSize.is_none())
        throw py::value_error("cell_size and transform both set the spacing: give one");
    const int64_t rows = heights.shape(0), cols = heights.shape(1);
    ArrayPlacement place;
    if (!transform.is_none()) {
        const std::vector<double> gt = geoTransformOf(transform);
        place = placeArray("heights", gt.data(), crsText(crs), cols, rows);
    } else {
        double cx = 1.0, cy = 1.0;
        if (!cellSize.is_none()) {
            if (py::isinstance<py::tuple>(cellSize) || py::isinstance<py::list>(cellSize)) {
                const auto pair = cellSize.cast<std::vector<double>>();
                if (pair.size() != 2) throw py::value_error("cell_size: expected a number or an (x, y) pair");
                cx = pair[0];
                cy = pair[1];
            } else {
                cx = cy = cellSize.cast<double>();
            }
        }
        if (!(cx > 0.0 && cy > 0.0 && std::isfinite(cx) && std::isfinite(cy)))
            throw py::value_error("cell_size: expected positive finite metres, found (" + std::to_string(cx) + ", " +
                                  std::to_string(cy) + ")");
        if (!crs.is_none()) throw py::value_error("crs: give it with a transform, which places the array in it");
        place.cellSizeXM = cx;
        place.cellSizeYM = cy;
    }
    const py::dtype dt = heights.dtype();
    LoadedDem dem;
    dem.path = "array";
    dem.driver = "NumPy";
    dem.sourceWidth = cols;
    dem.sourceHeight = rows;
    dem.geo = place.geo;
    dem.warnings = place.warnings;
    try {
        if (dt.is(py::dtype::of<int16_t>())) dem.grid = gridFromArray<int16_t>(heights, place, nodata);
        else if (dt.is(py::dtype::of<uint16_t>())) dem.grid = gridFromArray<uint16_t>(heights, place, nodata);
        else if (dt.is(py::dtype::of<float>())) dem.grid = gridFromArray<float>(heights, place, nodata);
        else if (dt.is(py::dtype::of<double>())) dem.grid = gridFromArray<double>(heights, place, nodata);
        else
            throw py::type_error("heights: expected int16, uint16, float32 or float64, found " +
                                 dt.attr("name").cast<std::string>());
    } catch (const GridError& e) {
        throw py::value_error(std::string("heights: ") + e.what());
    }
    for (const std::string& w : dem.warnings) PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1);
    return std::make_unique<PyHeightField>(std::move(dem), DemLoadOptions{}, false);
}

std::unique_ptr<PyHeightField> openFile(const std::string& path, double cellSize, double heightScale) {
    if (!std::filesystem::exists(path)) {
        PyErr_SetString(PyExc_FileNotFoundError, (path + ": no such file").c_str());
        throw py::error_already_set();
    }
    DemLoadOptions options;
    options.imageCellSizeM = cellSize;
    options.imageHeightScale = heightScale;
    LoadedDem dem = loadDem(path, options);
    for (const std::string& w : dem.warnings) PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1);
    return std::make_unique<PyHeightField>(std::move(dem), options, true);
}

std::string describe(const PyHeightField& hf) {
    const HeightGrid& g = hf.grid();
    std::ostringstream s;
    s.precision(6);
    s << "HeightField(" << hf.dem().path << ": " << g.width() << " x " << g.height() << " vertices, cells "
      << g.cellSizeXM() << " x " << g.cellSizeYM() << " m, heights " << g.minHeightM() << " .. " << g.maxHeightM()
      << " m, " << g.nodataVertexCount() << " nodata vertices";
    if (!hf.dem().geo.crsName.empty()) s << ", " << hf.dem().geo.crsName;
    s << ")";
    return s.str();
}

}  // namespace

void bindHeightField(py::module_& m, py::class_<PyHeightField>& cls) {
    m.def("_last_loop_seconds", [] { return lastLoopSeconds.load(); },
          "Bench support: the seconds the last intersect or occluded call spent tracing its rays, timed in C++.");
    cls.def_static("open", &openFile, py::arg("path"), py::arg("cell_size") = 1.0, py::arg("height_scale") = 1.0,
                   "Reads a DEM (GeoTIFF, .hgt, anything GDAL reads, or an 8/16-bit PNG height map).\n\n"
                   "cell_size: metres between samples of a raster without georeference (default 1).\n"
                   "height_scale: metres per stored unit of a PNG height map (default 1).\n"
                   "What the CLI would warn about (assumed units, a large geographic extent) comes as a\n"
                   "UserWarning. Raises FileNotFoundError (an OSError) for a missing file, ValueError naming the\n"
                   "file and the problem for one that is not a readable DEM.")
        .def_static("from_array", &fromArray, py::arg("heights"), py::arg("cell_size") = py::none(),
                    py::arg("nodata") = py::none(), py::arg("transform") = py::none(), py::arg("crs") = py::none(),
                    "A height field from a 2-D NumPy array of heights in metres (int16, uint16, float32 or float64;\n"
                    "C or Fortran order), row 0 at the north edge as rasters are stored.\n\n"
                    "cell_size: metres between samples, a number or an (x, y) pair (default 1; not with transform).\n"
                    "nodata: the value of missing samples (NaN allowed); other non-finite values are refused.\n"
                    "transform: where the array lies: a GDAL geotransform (x0, dx, 0, y0, 0, -dy), a rasterio\n"
                    "  affine (dx, 0, x0, 0, -dy, y0) or Affine object; north up. Row order follows its sign.\n"
                    "crs: the transform's coordinate reference system: WKT, a PROJ string, 'EPSG:n', an EPSG code\n"
                    "  or an object with to_wkt(). A geographic CRS is converted to local metres as files are.\n"
                    "Raises ValueError (TypeError for another dtype) naming the argument and what was found.")
        .def_property_readonly("width", [](const PyHeightField& h) { return h.grid().width(); },
                               "Vertices along x (columns).")
        .def_property_readonly("height", [](const PyHeightField& h) { return h.grid().height(); },
                               "Vertices along y (rows).")
        .def_property_readonly("shape", [](const PyHeightField& h) { return py::make_tuple(h.grid().height(), h.grid().width()); },
                               "(rows, columns): the shape of every map product's array.")
        .def_property_readonly("cell_size",
                               [](const PyHeightField& h) { return py::make_tuple(h.grid().cellSizeXM(), h.grid().cellSizeYM()); },
                               "(x, y) metres between vertices.")
        .def_property_readonly("min_height", [](const PyHeightField& h) { return h.grid().minHeightM(); },
                               "Lowest valid height, metres.")
        .def_property_readonly("max_height", [](const PyHeightField& h) { return h.grid().maxHeightM(); },
                               "Highest valid height, metres.")
        .def_property_readonly("nodata_count", [](const PyHeightField& h) { return h.grid().nodataVertexCount(); },
                               "Vertices without a height.")
        .def_property_readonly("crs", [](const PyHeightField& h) { return h.dem().geo.crsWkt; },
                               "The coordinate reference system as WKT ('' when there is none).")
        .def_property_readonly(
            "transform",
            [](const PyHeightField& h) -> py::object {
                if (!h.dem().geo.georeferenced) return py::none();
                const double* g = h.dem().geo.geoTransform;
                return py::make_tuple(g[0], g[1], g[2], g[3], g[4], g[5]);
            },
            "The GDAL geotransform of the source raster (None without georeference); every map product's array\n"
            "lies on it.")
        .def("intersect", &traceFirstHits, py::arg("origins"), py::arg("directions"), py::arg("method") = "bilinear",
             py::arg("t_max") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
             "Where each ray first meets the surface: a dict of arrays 't' (N; distance in units of the direction's "
             "length, inf where the ray misses), 'point' (N, 3; NaN on a miss), 'normal' (N, 3; unit, pointing up) "
             "and 'hit' (N; bool).\n\norigins, directions: (N, 3) arrays in local metres (x east, y north, z up, "
             "origin at the south-west vertex).\n"
             "method: bilinear (default), bilinear-double, triangles, nearest, reference, embree, embree-grid.\n"
             "t_max: where the search ends, in units of the direction's length: None (default: no end), a\n"
             "  number or an (N,) array. With directions from an eye to targets and t_max=1 the rays are the\n"
             "  sight lines between them.\n"
             "threads: worker threads, 0 = all cores (default).\n"
             "progress: None or a function called with (share done, rays so far) while it runs.\n"
             "The GIL is released while the rays are traced; Ctrl-C stops the work and raises KeyboardInterrupt.")
        .def("occluded", &traceOcclusion, py::arg("origins"), py::arg("directions"), py::arg("method") = "bilinear",
             py::arg("t_max") = py::none(), py::arg("threads") = 0, py::arg("progress") = py::none(),
             "Whether each ray meets the surface at all (an (N,) bool array): line of sight, shadow tests.\n"
             "Arguments as intersect's.")
        .def("__repr__", &describe);
}

}  // namespace terracast::python
