// One-line errors for calls that pybind11 would answer with its overload listing
// ("incompatible function arguments", then the repr of every argument: a numpy array's runs
// to dozens of lines). The module's entry points take every argument as an object that
// defaults to None, extra positional arguments as *args and unknown keywords as **kwargs, so
// every call reaches these checks, which name the argument in one line.
#pragma once
#include <pybind11/pybind11.h>

#include <initializer_list>

namespace obscura::python {

namespace py = pybind11;

// Positional arguments beyond `positional` (their names, in order): a TypeError saying what the
// function takes by position and that the rest (`hint`, e.g. "camera=...") go by keyword.
void checkPositional(const char* function, const py::args& extra, std::initializer_list<const char*> positional,
                     const char* hint);

// A keyword the function does not take: a TypeError naming it, as Python's own.
void checkNoKeywords(const char* function, const py::kwargs& unknown);

// A required argument left out (or None): a TypeError naming it and what it should be.
void required(const char* function, const py::object& value, const char* name, const char* what);

// compute_ao, compute_ssdo: depth and normal (by position or keyword) and camera= are required;
// normal not with normals='depth'.
void checkArrayCall(const char* function, const py::args& extra, const py::object& depth, const py::object& normal,
                    const py::object& camera, const py::object& normals);

// read_passes, inspect: a path, then the file keywords.
void checkFileCall(const char* function, const py::args& extra, const py::kwargs& unknown, const py::object& path);

// ao_from_passes's `passes`: the dict read_passes returns.
py::dict passesArg(const py::args& extra, const py::object& passes);

} // namespace obscura::python
