// The Python module `terracast._core`; the package `terracast` (python/terracast/__init__.py) re-exports it.
// Its parts: height fields and ray queries (heightfield.cpp), map products and renders as arrays (products.cpp),
// the accuracy and compare reports and scene files (measures.cpp).
#include "python/src/core.h"

#include "tracer/core/errors.h"

namespace py = pybind11;
using namespace terracast;
using terracast::python::PyHeightField;

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
        } catch (const Cancelled&) {
            PyErr_SetNone(PyExc_KeyboardInterrupt);
        }
    });

    py::class_<PyHeightField> cls(m, "HeightField",
                                  "A height grid in local metres: x east, y north, z up, origin at the south-west "
                                  "vertex. Map products are arrays of its shape, row 0 north, as rasters are "
                                  "stored.");
    python::bindHeightField(m, cls);
    python::bindProducts(m, cls);
    python::bindMeasures(m, cls);
}
