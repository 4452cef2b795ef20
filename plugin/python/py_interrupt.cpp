#include "py_interrupt.h"

#include <pybind11/pybind11.h>

namespace obscura::python {

namespace py = pybind11;

CtrlCStops::CtrlCStops() {
    const py::object threading = py::module_::import("threading");
    if (!threading.attr("current_thread")().is(threading.attr("main_thread")())) return;
    scope_.emplace(askedAtMostEvery(std::chrono::milliseconds(20), [] {
        py::gil_scoped_acquire gil;
        return PyErr_CheckSignals() != 0;
    }));
}

} // namespace obscura::python
