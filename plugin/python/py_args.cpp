#include "python/py_args.h"
#include "python/py_spelling.h"

#include "base/error.h"
#include "core/methods.h"
#include "core/settings.h"
#include "core/settings_schema.h"
#include "io/camera_sources.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace obscura::python {

[[noreturn]] void valueError(const std::string& message) { throw py::value_error(message); }

std::string typeName(const py::handle& obj) { return py::str(py::type::handle_of(obj).attr("__name__")); }

std::string pathArg(const py::handle& obj, const char* what) {
    if (obj.is_none()) valueError(std::string(what) + " must be a path, got None");
    // The file system's bytes (os.fsencode): a str, bytes or os.PathLike, whatever its encoding.
    const py::module_ os = py::module_::import("os");
    const py::bytes raw = os.attr("fsencode")(os.attr("fspath")(obj));
    // Reports, notes and errors carry paths as str: a name that is not UTF-8 could not be said.
    const py::object text = py::reinterpret_steal<py::object>(
        PyUnicode_DecodeUTF8(PyBytes_AsString(raw.ptr()), PyBytes_Size(raw.ptr()), "strict"));
    if (!text) {
        PyErr_Clear();
        valueError(std::string(what) + " " + std::string(py::repr(raw)) +
                   " is not UTF-8; obscura's reports name files as text: rename it");
    }
    std::string s = raw.cast<std::string>();
    if (s.empty()) valueError(std::string(what) + " must not be empty");
    return s;
}

std::string strArg(const py::handle& obj, const char* what) {
    if (!py::isinstance<py::str>(obj))
        throw py::type_error(std::string(what) + " must be a str, got " + typeName(obj));
    return obj.cast<std::string>();
}

double floatArg(const py::handle& obj, const char* what) {
    if (py::isinstance<py::str>(obj) || py::isinstance<py::bool_>(obj) || obj.is_none())
        throw py::type_error(std::string(what) + " must be a number, got " + typeName(obj));
    const double v = py::float_(py::reinterpret_borrow<py::object>(obj)).cast<double>();
    if (!std::isfinite(v)) valueError(std::string(what) + " must be finite, got " + std::to_string(v));
    return v;
}

long long intArg(const py::handle& obj, const char* what) {
    if (py::isinstance<py::bool_>(obj) || py::isinstance<py::float_>(obj) || py::isinstance<py::str>(obj) ||
        obj.is_none())
        throw py::type_error(std::string(what) + " must be an int, got " + typeName(obj));
    PyObject* index = PyNumber_Index(obj.ptr());
    if (!index) throw py::error_already_set();
    py::int_ i = py::reinterpret_steal<py::int_>(index);
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow) valueError(std::string(what) + " is out of range, got " + std::string(py::str(i)));
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    return v;
}

bool boolArg(const py::handle& obj, const char* what) {
    // numpy's bool is not Python's: both are taken, and nothing else ('no' is truthy).
    if (py::isinstance<py::bool_>(obj)) return obj.cast<bool>();
    if (py::isinstance(obj, py::module_::import("numpy").attr("bool_"))) return PyObject_IsTrue(obj.ptr()) == 1;
    throw py::type_error(std::string(what) + " must be True or False, got " + typeName(obj));
}

int intInRange(const py::handle& obj, const char* what, long long lo, long long hi) {
    const long long v = intArg(obj, what);
    if (v < lo || v > hi)
        valueError(std::string(what) + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) +
                   ", got " + std::to_string(v));
    return (int)v;
}

// A shared numeric setting (core/settings_schema.h), checked against core's range.
double numberArg(const py::handle& obj, const char* key) {
    const NumberSetting& setting = numberSetting(key);
    const double v = setting.integer ? (double)intArg(obj, key) : floatArg(obj, key);
    const std::string problem = numberProblem(setting, v, Spelling::Key);
    if (!problem.empty()) valueError(problem);
    return v;
}

// A method's own integer parameter (core/methods.h), checked against the table's range.
int methodIntArg(const py::handle& obj, const char* key) {
    for (const MethodParam* p : allMethodParams())
        if (std::string(p->key) == key) return intInRange(obj, key, (long long)p->min, (long long)p->max);
    throw std::logic_error(std::string("no method parameter ") + key);
}

std::string choiceArg(const py::handle& obj, const char* what, const std::vector<std::string>& choices) {
    const std::string s = strArg(obj, what);
    if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
    std::string all;
    for (const std::string& c : choices) all += (all.empty() ? "'" : ", '") + c + "'";
    valueError(std::string(what) + " must be one of " + all + ", got '" + s + "'");
}

bool upArg(const py::handle& obj) { return choiceArg(obj, "up", kUpWords) == "z"; }

std::vector<double> numbersArg(const py::handle& obj, const char* what, size_t count) {
    if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj) || py::len(obj) != count)
        valueError(std::string(what) + " must be " + std::to_string(count) + " numbers, got " + typeName(obj));
    py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
    std::vector<double> v;
    for (size_t i = 0; i < count; ++i) v.push_back(floatArg(seq[i], what));
    return v;
}

std::array<float, 3> tripleArg(const py::handle& obj, const char* what, bool light) {
    if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj) || py::len(obj) != 3)
        valueError(std::string(what) + " must be 3 numbers, got " + typeName(obj));
    py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
    std::array<float, 3> v{};
    for (int i = 0; i < 3; ++i) {
        const double d = floatArg(seq[i], what);
        if (light && !withinLight(d))
            valueError(std::string(what) + " must be between 0 and 1e9, got " + std::to_string(d));
        v[i] = (float)d;
    }
    return v;
}

// 16 numbers row-major (4x4 nested or flat), OpenGL convention; checked to be an affine,
// invertible transform.
std::array<double, 16> matrixRowsArg(const py::handle& obj, const char* what) {
    py::array_t<double, py::array::c_style | py::array::forcecast> a;
    try {
        a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
    } catch (const py::error_already_set&) {
    }
    if (!a || !((a.ndim() == 2 && a.shape(0) == 4 && a.shape(1) == 4) || (a.ndim() == 1 && a.shape(0) == 16))) {
        PyErr_Clear();
        valueError(std::string(what) + " must be a 4x4 matrix (or 16 numbers, row-major), got " + typeName(obj));
    }
    std::array<double, 16> rows{};
    std::copy(a.data(), a.data() + 16, rows.begin());
    try {
        (void)cameraToWorldFromRows(rows, what);
    } catch (const Error& e) {
        valueError(keywordSpelling(e.what()));
    }
    return rows;
}

py::array_t<double> matrixToRows(const glm::dmat4& m) {
    py::array_t<double> out({4, 4});
    auto r = out.mutable_unchecked<2>();
    for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 4; ++col) r(row, col) = m[col][row];  // glm is column-major
    return out;
}

py::tuple boxToTuple(const Box2i& b) { return py::make_tuple(b.x0, b.y0, b.x1, b.y1); }

Box2i boxArg(const py::handle& obj, const char* what) {
    if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj) || py::len(obj) != 4)
        valueError(std::string(what) + " must be (x0, y0, x1, y1), half-open pixel bounds, got " + typeName(obj));
    py::sequence s = py::reinterpret_borrow<py::sequence>(obj);
    const int lim = 1 << 30;
    Box2i b{intInRange(s[0], what, -lim, lim), intInRange(s[1], what, -lim, lim), intInRange(s[2], what, -lim, lim),
            intInRange(s[3], what, -lim, lim)};
    if (b.empty()) valueError(std::string(what) + " is empty: x1 must exceed x0 and y1 must exceed y0");
    return b;
}

// A numpy array as a strided plane, without copying. `channels` 1: shape (H, W); 3: (H, W, 3).
ConstPlane planeArg(const py::handle& obj, const char* what, int channels) {
    if (!py::isinstance<py::array>(obj))
        throw py::type_error(std::string(what) + " must be a numpy.ndarray of float32, got " + typeName(obj));
    py::array a = py::reinterpret_borrow<py::array>(obj);
    if (!py::isinstance<py::array_t<float, 0>>(a))
        valueError(std::string(what) + " must have dtype float32 (native byte order), got " +
                   std::string(py::str(a.dtype())) + "; convert it with " + what + ".astype(numpy.float32)");
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    shape += a.ndim() == 1 ? ",)" : ")";
    const bool shapeOk = channels == 1 ? a.ndim() == 2 : (a.ndim() == 3 && a.shape(2) == channels);
    if (!shapeOk)
        valueError(std::string(what) + " must have shape " + (channels == 1 ? "(H, W)" : "(H, W, 3)") + ", got " +
                   shape);
    if (a.shape(0) < 1 || a.shape(1) < 1) valueError(std::string(what) + " is empty: shape " + shape);
    if (a.shape(0) > (1 << 30) || a.shape(1) > (1 << 30)) valueError(std::string(what) + " is too large: " + shape);
    const auto* data = static_cast<const float*>(a.data());
    const bool aligned = reinterpret_cast<std::uintptr_t>(data) % alignof(float) == 0;
    const py::ssize_t f = (py::ssize_t)sizeof(float);
    if (!aligned || a.strides(0) % f || a.strides(1) % f)
        valueError(std::string(what) + " is not aligned to whole float32 elements; pass " + what +
                   ".copy() (numpy aligns a copy)");
    if (channels > 1 && a.strides(2) != f)
        valueError(std::string(what) + "'s " + std::to_string(channels) +
                   " components must be adjacent in memory (strides[2] == 4 bytes, got " +
                   std::to_string(a.strides(2)) + "); pass numpy.ascontiguousarray(" + what + ")");
    ConstPlane p;
    p.data = data;
    p.height = (int)a.shape(0);
    p.width = (int)a.shape(1);
    p.channels = channels;
    p.yStride = a.strides(0) / f;
    p.xStride = a.strides(1) / f;
    return p;
}

// An owned image handed to numpy without a copy: the array keeps it alive.
py::array imageToArray(Image&& image, bool squeeze) {
    auto* owned = new Image(std::move(image));
    py::capsule keep(owned, [](void* p) { delete static_cast<Image*>(p); });
    const py::ssize_t h = owned->height, w = owned->width, c = owned->channels, f = sizeof(float);
    if (c == 1 && squeeze)
        return py::array_t<float>({h, w}, {w * f, f}, owned->pixels.data(), keep);
    return py::array_t<float>({h, w, c}, {w * c * f, c * f, f}, owned->pixels.data(), keep);
}

Camera cameraArg(const py::handle& obj) {
    if (!py::isinstance<Camera>(obj))
        throw py::type_error("camera must be an obscura.Camera (Camera.perspective, Camera.orthographic, "
                             "Camera.from_sidecar or read_passes()['camera']), got " + typeName(obj));
    return obj.cast<Camera>();
}

} // namespace obscura::python
