// terracast.accuracy, terracast.compare (the JSON reports of `terracast accuracy` and `compare` as dictionaries)
// and terracast.render_scene (a scene file's picture as an array).
#include "python/src/core.h"

#include "tracer/core/errors.h"
#include "tracer/measure/accuracy.h"
#include "tracer/measure/compare.h"
#include "tracer/measure/reports.h"
#include "tracer/scene/scene_pipeline.h"
#include "tracer/terrain/dem_pipeline.h"

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace terracast::python {

namespace {

// A HeightField, or a path opened as HeightField.open opens it (kept alive by `opened`).
PyHeightField& heightFieldOf(const py::object& dem, py::object& opened) {
    if (py::isinstance<PyHeightField>(dem)) return dem.cast<PyHeightField&>();
    opened = py::module_::import("terracast._core").attr("HeightField").attr("open")(py::str(dem));
    return opened.cast<PyHeightField&>();
}

py::object parsedJson(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

py::object accuracy(const py::object& demArg, int64_t rays, uint64_t seed, const py::object& progress) {
    if (rays < 3 || rays > 100000000)
        throw py::value_error("rays: expected 3 .. 100000000, found " + std::to_string(rays));
    py::object opened;
    PyHeightField& hf = heightFieldOf(demArg, opened);
    AccuracyOptions options;
    options.rays = rays;
    options.seed = seed;
    const AccuracyReport r =
        runWatched<AccuracyReport>(progress, [&](WorkProgress&) { return measureAccuracy(hf.grid(), options); });
    return parsedJson(accuracyJson({hf.dem().path, hf.grid().width(), hf.grid().height()}, seed, r));
}

py::object compare(const py::object& demArg, const std::vector<int>& size, const std::vector<double>& sun,
                   double exaggeration, const py::object& camera, const std::vector<std::string>& methods,
                   int threads, const py::object& progress) {
    if (size.size() != 2 || size[0] < 1 || size[1] < 1 || size[0] > 65536 || size[1] > 65536)
        throw py::value_error("size: expected (width, height) from 1 to 65536 pixels");
    if (sun.size() != 2) throw py::value_error("sun: expected (azimuth, elevation) in degrees");
    if (threads < 0) throw py::value_error("threads: expected 0 (all cores) or more");
    checkViewValues(exaggeration, sun[1]);
    py::object opened;
    PyHeightField& hf = heightFieldOf(demArg, opened);
    const std::shared_ptr<const LoadedDem> dem = exaggerated(hf, exaggeration);
    std::optional<PinholeCamera> cam;
    if (!camera.is_none()) {
        PinholeCamera c;
        if (auto err = parseCamera(camera.cast<std::string>(), c)) throw py::value_error("camera: " + *err);
        cam = c;
    }
    CompareSettings cs;
    if (!methods.empty()) {
        cs.methods.clear();
        for (const std::string& m : methods) cs.methods.push_back(methodOf(m));
    }
    cs.render = makeView(dem->grid, size[0], size[1], sun[0], sun[1], cam, threads);
    const CompareReport r = runWatched<CompareReport>(progress, [&](WorkProgress& state) {
        cs.onMethod = [&](SurfaceMethod, size_t k, size_t n) { state(double(k) / double(n), 0); };
        return compareSurfaces(dem->grid, cs);
    });
    return parsedJson(compareJson({dem->path, dem->grid.width(), dem->grid.height()}, r));
}

py::array renderScene(const std::string& path, const py::object& size, int spp, int threads, int64_t seed,
                      const py::object& method, bool allowPaths, bool linear, const py::object& progress) {
    SceneRunOptions o;
    o.path = path;
    o.write = false;
    o.anyPath = allowPaths;
    if (!size.is_none()) {
        const auto wh = size.cast<std::vector<int>>();
        if (wh.size() != 2 || wh[0] < 1 || wh[1] < 1 || wh[0] > 65536 || wh[1] > 65536)
            throw py::value_error("size: expected (width, height) from 1 to 65536 pixels");
        o.width = wh[0];
        o.height = wh[1];
    }
    if (spp < 0 || spp > 65536) throw py::value_error("spp: expected 1 .. 65536 samples per pixel (0: the file's)");
    o.samples = spp;
    o.threads = threads;
    o.seed = seed;
    if (!method.is_none()) o.method = methodOf(method.cast<std::string>());
    const Film film = runWatched<Film>(progress, [&](WorkProgress& state) {
        RunListener listener;
        listener.progress = [&](double f, int64_t r) { state(f, r); };
        return renderSceneFile(o, listener);
    });
    return pictureArray(film, linear);
}

}  // namespace

void bindMeasures(py::module_& m, py::class_<PyHeightField>&) {
    m.def("accuracy", &accuracy, py::arg("dem"), py::kw_only(), py::arg("rays") = 100000, py::arg("seed") = 1,
          py::arg("progress") = py::none(),
          "Every cell method against the exact reference on seeded rays (camera-like, grazing and shadow-like in\n"
          "equal parts), as `terracast accuracy --json` reports it: a dict with the JSON report's keys.\n\n"
          "dem: a HeightField or a path. rays: how many (default 100000). seed: random seed (default 1).");
    m.def("compare", &compare, py::arg("dem"), py::kw_only(), py::arg("size") = std::vector<int>{640, 480},
          py::arg("sun") = std::vector<double>{315.0, 35.0}, py::arg("exaggeration") = 1.0,
          py::arg("camera") = py::none(), py::arg("methods") = std::vector<std::string>{}, py::arg("threads") = 0,
          py::arg("progress") = py::none(),
          "Every method's speed and error on the same camera and shadow rays, side by side, as `terracast compare\n"
          "--json` reports it: a dict with the JSON report's keys.\n\n"
          "dem: a HeightField or a path. size: (width, height) in pixels (default (640, 480)).\n"
          "sun: (azimuth, elevation) in degrees (default (315, 35)). exaggeration: vertical scale (default 1).\n"
          "camera: 'eye=x,y,z look=x,y,z fov=deg' (default: the automatic view).\n"
          "methods: names to measure (default: every method); the reference is always added.\n"
          "threads: worker threads, 0 = all cores (default).");
    m.def("render_scene", &renderScene, py::arg("path"), py::kw_only(), py::arg("size") = py::none(),
          py::arg("spp") = 0, py::arg("threads") = -1, py::arg("seed") = -1, py::arg("method") = py::none(),
          py::arg("allow_paths") = false, py::arg("linear") = false, py::arg("progress") = py::none(),
          "A scene file's picture, as `terracast scene SCENE.toml` renders it: uint8 sRGB (height, width, 3), or\n"
          "float32 linear RGB with linear=True, row 0 at the top. Nothing is written.\n\n"
          "size: (width, height) overriding [render]'s. spp: samples per pixel (default 0: the file's).\n"
          "threads: worker threads (default -1: the file's; 0 = all cores). seed: random seed (-1: the file's).\n"
          "method: every height field's method (default: each one's own).\n"
          "allow_paths: the file may name files outside its folder (as --allow-paths).\n"
          "progress: None or a function called with (share done, rays so far). Ctrl-C raises KeyboardInterrupt.");
}

}  // namespace terracast::python
