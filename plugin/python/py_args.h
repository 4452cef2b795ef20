// One Python argument to one C++ value. Wrong types raise TypeError (Python's own
// conversions); wrong values, shapes, dtypes and layouts raise ValueError; failures of the
// core raise obscura.Error. Ranges, names and choices come from plugin/core and plugin/io,
// never from here. (call_args.h checks the call as a whole: missing, extra or unknown
// arguments.)
#pragma once
#include "base/image.h"
#include "core/camera.h"
#include "core/settings.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <string>
#include <vector>

namespace obscura::python {

namespace py = pybind11;

[[noreturn]] void valueError(const std::string& message);

// The name of obj's type, for messages ("got list").
std::string typeName(const py::handle& obj);

// A str or os.PathLike, not empty.
std::string pathArg(const py::handle& obj, const char* what);
std::string strArg(const py::handle& obj, const char* what);
// A finite number (not a str, bool or None).
double floatArg(const py::handle& obj, const char* what);
// An int (or an object with __index__), not a bool, float or str; ValueError past long long.
long long intArg(const py::handle& obj, const char* what);
int intInRange(const py::handle& obj, const char* what, long long lo, long long hi);
// True or False (Python's or numpy's bool), not any truthy object.
bool boolArg(const py::handle& obj, const char* what);

// A shared numeric setting (core/settings_schema.h), checked against core's range.
double numberArg(const py::handle& obj, const char* key);
// A method's own integer parameter (core/methods.h), checked against the table's range.
int methodIntArg(const py::handle& obj, const char* key);

// An enum by core's name for it (parse() of core/settings.h or io/frame_job.h).
template <class E>
E enumArg(const py::handle& obj, const char* what, const char* choices) {
    const std::string s = strArg(obj, what);
    E e{};
    if (!parse(s, e)) valueError(std::string(what) + " must be " + choices + ", got '" + s + "'");
    return e;
}

std::string choiceArg(const py::handle& obj, const char* what, const std::vector<std::string>& choices);
// The words of the keywords that take words the core tables do not list (read here and in py_job;
// py_spelling recognises them in messages).
inline const std::vector<std::string> kBadPixelsWords = {"error", "skip"};
inline const std::vector<std::string> kOutTypeWords = {"half", "float"};
inline const std::vector<std::string> kUpWords = {"y", "z"};
// 'y' or 'z': true for z up.
bool upArg(const py::handle& obj);
// `count` numbers (a tuple or list), unchecked: the caller checks them against core's table.
std::vector<double> numbersArg(const py::handle& obj, const char* what, size_t count);
// 3 numbers (`light`: a radiance or irradiance, each withinLight).
std::array<float, 3> tripleArg(const py::handle& obj, const char* what, bool light);

// 16 numbers row-major (4x4 nested or flat), OpenGL convention; checked to be an affine,
// invertible transform.
std::array<double, 16> matrixRowsArg(const py::handle& obj, const char* what);
py::array_t<double> matrixToRows(const glm::dmat4& m);

py::tuple boxToTuple(const Box2i& b);
// (x0, y0, x1, y1), half-open pixel bounds, not empty.
Box2i boxArg(const py::handle& obj, const char* what);

// A numpy array as a strided plane, without copying. `channels` 1: shape (H, W); 3: (H, W, 3).
ConstPlane planeArg(const py::handle& obj, const char* what, int channels);
// An owned image handed to numpy without a copy: the array keeps it alive. `squeeze`: one
// channel as (H, W).
py::array imageToArray(Image&& image, bool squeeze);

Camera cameraArg(const py::handle& obj);

} // namespace obscura::python
