// The module's parts, each bound by the file named beside it; obscura_module.cpp calls them
// in this order.
#pragma once
#include <pybind11/pybind11.h>

namespace obscura::python {

namespace py = pybind11;

void bindCamera(py::module_& m);  // py_camera.cpp: obscura.Camera
void bindArrays(py::module_& m);  // py_arrays.cpp: compute_ao, compute_gi, compute_ssdo, ao_from_passes
void bindFiles(py::module_& m);   // py_files.cpp: read_passes, process, inspect, read_layer
void bindDeep(py::module_& m);    // py_deep.cpp: read_deep
void bindTables(py::module_& m);  // py_tables.cpp: QUALITY_PRESETS, METHODS, NUMBER_SETTINGS, PRESETS

} // namespace obscura::python
