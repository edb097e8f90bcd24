// What the parts of the Python module share: the height field object, and long work run with its progress
// handed to a Python callback and Ctrl-C honoured.
#pragma once

#include "loaders/dem_loader.h"
#include "tracer/core/cancel.h"
#include "tracer/core/surface_method.h"
#include "tracer/sampling/film.h"
#include "tracer/terrain/surface.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <utility>

namespace terracast::python {

namespace py = pybind11;

// A height field as Python sees it: the loaded DEM (grid and georeference), how it was opened (to open it again
// exaggerated), and the surfaces built on it so far (one per method, built on first use).
class PyHeightField {
public:
    PyHeightField(LoadedDem dem, DemLoadOptions options, bool fromFile)
        : dem_(std::make_shared<LoadedDem>(std::move(dem))), options_(options), fromFile_(fromFile) {}

    const LoadedDem& dem() const { return *dem_; }
    const HeightGrid& grid() const { return dem_->grid; }
    const DemLoadOptions& loadOptions() const { return options_; }
    bool fromFile() const { return fromFile_; }

    const TerrainSurface& surface(SurfaceMethod method) {
        auto& s = surfaces_[method];
        if (!s) s = std::make_unique<TerrainSurface>(dem_->grid, method);
        return *s;
    }

private:
    std::shared_ptr<LoadedDem> dem_;
    DemLoadOptions options_;
    bool fromFile_ = false;
    std::map<SurfaceMethod, std::unique_ptr<TerrainSurface>> surfaces_;
};

// The progress of work running on another thread, as the library's progress functions report it.
struct WorkProgress {
    std::atomic<double> fraction{0.0};
    std::atomic<int64_t> rays{0};
    void operator()(double f, int64_t r) {
        fraction.store(f, std::memory_order_relaxed);
        rays.store(r, std::memory_order_relaxed);
    }
};

// Runs `work` on a worker thread while the calling thread, without the GIL, wakes every 50 ms to hand the progress
// to `progress` (a callable taking the share done and the rays so far, or None) and to let Python handle signals.
// Ctrl-C (KeyboardInterrupt) or an exception raised by `progress` asks the work to stop (tracer/core/cancel.h:
// loops stop between tiles) and is raised once it has; an error of the work itself is raised as the module
// translates it. Returns what `work` returns.
//
// The cancellation flag is the process's: while calls run from several Python threads, a Ctrl-C (or a raising
// progress function) stops them all. It is cleared when the first call starts and when the last one ends.
inline std::atomic<int>& watchedCalls() {
    static std::atomic<int> calls{0};
    return calls;
}

template <class Result>
Result runWatched(const py::object& progress, const std::function<Result(WorkProgress&)>& work) {
    WorkProgress state;
    std::optional<Result> result;
    std::exception_ptr failure, watching;
    std::optional<py::error_already_set> raised;
    std::mutex mutex;
    std::condition_variable finished;
    bool done = false;
    if (watchedCalls().fetch_add(1) == 0) cancelFlag().store(false);
    struct LastOut {
        ~LastOut() {
            if (watchedCalls().fetch_sub(1) == 1) cancelFlag().store(false);
        }
    } lastOut;
    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                result.emplace(work(state));
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mutex);
            done = true;
            finished.notify_one();
        });
        double shown = -1.0;
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mutex);
                if (finished.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) break;
            }
            py::gil_scoped_acquire acquire;
            if (raised || watching) continue;  // stopping already
            try {
                if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                const double f = state.fraction.load(std::memory_order_relaxed);
                if (!progress.is_none() && f != shown) {
                    shown = f;
                    progress(f, state.rays.load(std::memory_order_relaxed));
                }
            } catch (py::error_already_set& e) {
                raised.emplace(std::move(e));
                cancelFlag().store(true);
            } catch (...) {
                // Whatever else goes wrong here stops the work too, and is raised once the worker has joined.
                watching = std::current_exception();
                cancelFlag().store(true);
            }
        }
        worker.join();
    }
    if (raised) throw std::move(*raised);
    if (watching) std::rethrow_exception(watching);
    if (failure) std::rethrow_exception(failure);
    if (!progress.is_none()) progress(1.0, state.rays.load());
    return std::move(*result);
}

// Registration of the module's parts (module.cpp calls them in order).
void bindHeightField(py::module_& m, py::class_<PyHeightField>& cls);
void bindProducts(py::module_& m, py::class_<PyHeightField>& cls);
void bindMeasures(py::module_& m, py::class_<PyHeightField>& cls);

// The method named `name`, or ValueError listing the methods.
SurfaceMethod methodOf(const std::string& name);

// The DEM a view is made of: the height field's own (k = 1), or exaggerated by k: a file opened again as
// `--exaggeration` opens it, an array's heights multiplied in a copy. ValueError for a factor it refuses.
std::shared_ptr<const LoadedDem> exaggerated(PyHeightField& hf, double k);

// A picture as an array (height, width, 3), row 0 at the top: 8-bit sRGB as PNG files hold it, or with `linear`
// the linear float values an EXR holds.
py::array pictureArray(const Film& film, bool linear);

}  // namespace terracast::python
