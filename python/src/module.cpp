// The Python module `terracast._core`: height fields from files or NumPy arrays, and batch ray queries against
// them, threaded and with the GIL released. The package `terracast` (python/terracast/__init__.py) re-exports it.
#include "loaders/dem_loader.h"
#include "tracer/core/errors.h"
#include "tracer/core/surface_method.h"
#include "tracer/terrain/surface.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <variant>

namespace py = pybind11;
using namespace terracast;

namespace {

// A height field as Python sees it: the grid, where it came from, and the surfaces built on it so far (one per
// method, built on first use).
class PyHeightField {
public:
    PyHeightField(HeightGrid grid, std::string source, std::string crs)
        : grid_(std::make_shared<HeightGrid>(std::move(grid))), source_(std::move(source)), crs_(std::move(crs)) {}

    const HeightGrid& grid() const { return *grid_; }
    const std::string& source() const { return source_; }
    const std::string& crs() const { return crs_; }

    const TerrainSurface& surface(SurfaceMethod method) {
        auto& s = surfaces_[method];
        if (!s) s = std::make_unique<TerrainSurface>(*grid_, method);
        return *s;
    }

private:
    std::shared_ptr<HeightGrid> grid_;
    std::string source_, crs_;
    std::map<SurfaceMethod, std::unique_ptr<TerrainSurface>> surfaces_;
};

SurfaceMethod methodOf(const std::string& name) {
    const auto m = parseSurfaceMethod(name);
    if (!m) throw py::value_error("method: expected one of " + std::string(surfaceMethodList()) + ", found '" + name + "'");
    return *m;
}

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

Ray rayAt(const double* o, const double* d, size_t k) {
    return Ray{{o[3 * k], o[3 * k + 1], o[3 * k + 2]}, {d[3 * k], d[3 * k + 1], d[3 * k + 2]}};
}

py::dict traceFirstHits(PyHeightField& hf, const Rays& origins, const Rays& directions, const std::string& method) {
    const size_t n = rayCount(origins, directions);
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
    {
        py::gil_scoped_release release;
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t k = r.begin(); k < r.end(); ++k) {
                const auto h = surface.intersect(rayAt(o, d, k), {0.0, kInfinity});
                hp[k] = h.has_value();
                tp[k] = h ? h->t : std::numeric_limits<double>::infinity();
                for (int c = 0; c < 3; ++c) {
                    pp[3 * k + c] = h ? h->pointM[c] : std::numeric_limits<double>::quiet_NaN();
                    np[3 * k + c] = h ? h->normal[c] : std::numeric_limits<double>::quiet_NaN();
                }
            }
        });
    }
    py::dict out;
    out["t"] = t;
    out["point"] = point;
    out["normal"] = normal;
    out["hit"] = hit;
    return out;
}

py::array_t<bool> traceOcclusion(PyHeightField& hf, const Rays& origins, const Rays& directions, const std::string& method) {
    const size_t n = rayCount(origins, directions);
    const TerrainSurface& surface = hf.surface(methodOf(method));
    py::array_t<bool> out{py::ssize_t(n)};
    const double* o = origins.data();
    const double* d = directions.data();
    bool* p = out.mutable_data();
    {
        py::gil_scoped_release release;
        tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 1024), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t k = r.begin(); k < r.end(); ++k) p[k] = surface.occluded(rayAt(o, d, k), {0.0, kInfinity});
        });
    }
    return out;
}

// A 2-D array of heights, row 0 at the north edge as rasters are stored, into a grid (row 0 at the south).
template <class T>
HeightGrid gridFromArray(const py::array& a, double cellX, double cellY, std::optional<double> nodata) {
    const auto typed = py::array_t<T, py::array::forcecast>::ensure(a);
    const py::ssize_t rows = a.shape(0), cols = a.shape(1);
    std::vector<float> heights(size_t(rows * cols));
    std::vector<uint8_t> valid;
    bool anyNodata = false;
    const auto view = typed.template unchecked<2>();
    for (py::ssize_t r = 0; r < rows; ++r)
        for (py::ssize_t c = 0; c < cols; ++c) {
            const double v = double(view(r, c));
            const size_t k = size_t((rows - 1 - r) * cols + c);
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
    return HeightGrid(cols, rows, cellX, cellY, std::move(heights), std::move(valid));
}

std::unique_ptr<PyHeightField> fromArray(const py::array& heights, const py::object& cellSize, std::optional<double> nodata,
                                         std::optional<std::vector<double>> transform, const std::string& crs) {
    if (heights.ndim() != 2)
        throw py::value_error("heights: expected a 2-D array, found " + std::to_string(heights.ndim()) + " dimensions");
    if (heights.shape(0) < 2 || heights.shape(1) < 2)
        throw py::value_error("heights: expected at least 2 x 2 samples, found " + std::to_string(heights.shape(0)) +
                              " x " + std::to_string(heights.shape(1)));
    double cx = 1.0, cy = 1.0;
    if (transform) {
        if (transform->size() != 6) throw py::value_error("transform: expected 6 numbers (a GDAL geotransform)");
        cx = std::abs((*transform)[1]);
        cy = std::abs((*transform)[5]);
        if ((*transform)[2] != 0.0 || (*transform)[4] != 0.0)
            throw py::value_error("transform: expected a north-up raster (no rotation terms)");
    }
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
    const py::dtype dt = heights.dtype();
    HeightGrid grid;
    try {
        if (dt.is(py::dtype::of<int16_t>())) grid = gridFromArray<int16_t>(heights, cx, cy, nodata);
        else if (dt.is(py::dtype::of<uint16_t>())) grid = gridFromArray<uint16_t>(heights, cx, cy, nodata);
        else if (dt.is(py::dtype::of<float>())) grid = gridFromArray<float>(heights, cx, cy, nodata);
        else if (dt.is(py::dtype::of<double>())) grid = gridFromArray<double>(heights, cx, cy, nodata);
        else
            throw py::type_error("heights: expected int16, uint16, float32 or float64, found " +
                                 dt.attr("name").cast<std::string>());
    } catch (const GridError& e) {
        throw py::value_error(std::string("heights: ") + e.what());
    }
    return std::make_unique<PyHeightField>(std::move(grid), "array", crs);
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
    return std::make_unique<PyHeightField>(std::move(dem.grid), path, dem.geo.crsName);
}

std::string describe(const PyHeightField& hf) {
    const HeightGrid& g = hf.grid();
    std::ostringstream s;
    s.precision(6);
    s << "HeightField(" << hf.source() << ": " << g.width() << " x " << g.height() << " vertices, cells "
      << g.cellSizeXM() << " x " << g.cellSizeYM() << " m, heights " << g.minHeightM() << " .. " << g.maxHeightM()
      << " m, " << g.nodataVertexCount() << " nodata vertices";
    if (!hf.crs().empty()) s << ", " << hf.crs();
    s << ")";
    return s.str();
}

}  // namespace

PYBIND11_MODULE(_core, m) {
    m.doc() = "terracast: exact ray casting of elevation grids (the compiled core of the terracast package)";
    m.attr("__version__") = TERRACAST_VERSION;

    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const InputError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        } catch (const GridError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });

    py::class_<PyHeightField>(m, "HeightField",
                              "A height grid in local metres: x east, y north, z up, origin at the south-west sample.")
        .def_static("open", &openFile, py::arg("path"), py::arg("cell_size") = 1.0, py::arg("height_scale") = 1.0,
                    "Reads a DEM (GeoTIFF, .hgt, anything GDAL reads, or an 8/16-bit PNG height map).\n\n"
                    "cell_size: metres between samples of a raster without georeference (default 1).\n"
                    "height_scale: metres per stored unit of a PNG height map (default 1).\n"
                    "Raises FileNotFoundError (an OSError) for a missing file, ValueError naming the file and the\n"
                    "problem for one that is not a readable DEM.")
        .def_static("from_array", &fromArray, py::arg("heights"), py::arg("cell_size") = py::none(),
                    py::arg("nodata") = py::none(), py::arg("transform") = py::none(), py::arg("crs") = "",
                    "A height field from a 2-D NumPy array (int16, uint16, float32 or float64; C or Fortran "
                    "order), row 0 at the north edge as rasters are stored.\n\n"
                    "cell_size: metres, a number or an (x, y) pair (default: from transform, else 1).\n"
                    "nodata: the value of missing samples (NaN allowed); other non-finite values are refused.\n"
                    "transform: a GDAL geotransform (6 numbers), north up.\n"
                    "crs: the coordinate reference system, as text (kept for reference).")
        .def_property_readonly("width", [](const PyHeightField& h) { return h.grid().width(); },
                               "Vertices along x (columns).")
        .def_property_readonly("height", [](const PyHeightField& h) { return h.grid().height(); },
                               "Vertices along y (rows).")
        .def_property_readonly("cell_size",
                               [](const PyHeightField& h) { return py::make_tuple(h.grid().cellSizeXM(), h.grid().cellSizeYM()); },
                               "(x, y) metres between vertices.")
        .def_property_readonly("min_height", [](const PyHeightField& h) { return h.grid().minHeightM(); },
                               "Lowest valid height, metres.")
        .def_property_readonly("max_height", [](const PyHeightField& h) { return h.grid().maxHeightM(); },
                               "Highest valid height, metres.")
        .def_property_readonly("nodata_count", [](const PyHeightField& h) { return h.grid().nodataVertexCount(); },
                               "Vertices without a height.")
        .def("intersect", &traceFirstHits, py::arg("origins"), py::arg("directions"), py::arg("method") = "bilinear",
             "Where each ray first meets the surface: a dict of arrays 't' (N; distance in units of the direction's "
             "length, inf where the ray misses), 'point' (N, 3; NaN on a miss), 'normal' (N, 3; unit, pointing up) "
             "and 'hit' (N; bool).\n\norigins, directions: (N, 3) arrays in local metres.\n"
             "method: bilinear (default), bilinear-double, triangles, nearest, reference, embree, embree-grid.\n"
             "Threaded; the GIL is released while the rays are traced.")
        .def("occluded", &traceOcclusion, py::arg("origins"), py::arg("directions"), py::arg("method") = "bilinear",
             "Whether each ray meets the surface at all (an (N,) bool array): line of sight, shadow tests.")
        .def("__repr__", &describe);
}
