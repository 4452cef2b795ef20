#include "py_interrupt.h"

#include <pybind11/pybind11.h>

namespace obscura::python {

CancelCheck pythonSignalPending() {
    return [] {
        pybind11::gil_scoped_acquire gil;
        return PyErr_CheckSignals() != 0;
    };
}

} // namespace obscura::python
