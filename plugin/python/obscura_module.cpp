// The Python host: a pybind11 module over the same operator (plugin/core) and frame
// job (plugin/io) as the CLI. numpy arrays are viewed in place (strided planes), never
// converted; the GIL is released while pixels are read, computed or written.
#include "core/devices.h"
#include "base/error.h"
#include "core/operator.h"
#include "core/methods.h"
#include "core/settings_schema.h"
#include "io/camera_sources.h"
#include "io/frame_job.h"
#include "io/inspect.h"
#include "io/preview.h"
#include "io/write_guard.h"
#include "python/call_args.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace py = pybind11;
using namespace py::literals;

namespace obscura::python {

namespace {

// ---------------------------------------------------------------------------------------------
// Argument helpers. Wrong types raise TypeError (Python's own conversions); wrong values,
// shapes, dtypes and layouts raise ValueError; failures of the core raise obscura.Error.

[[noreturn]] void valueError(const std::string& message) { throw py::value_error(message); }

std::string typeName(const py::handle& obj) { return py::str(py::type::handle_of(obj).attr("__name__")); }

std::string pathArg(const py::handle& obj, const char* what) {
    if (obj.is_none()) valueError(std::string(what) + " must be a path, got None");
    py::object p = py::module_::import("os").attr("fsdecode")(py::module_::import("os").attr("fspath")(obj));
    std::string s = p.cast<std::string>();
    if (s.empty()) valueError(std::string(what) + " must not be empty");
    return s;
}

std::string strArg(const py::handle& obj, const char* what) {
    if (!py::isinstance<py::str>(obj))
        throw py::type_error(std::string(what) + " must be a str, got " + typeName(obj));
    return obj.cast<std::string>();
}

double floatArg(const py::handle& obj, const char* what) {
    if (py::isinstance<py::str>(obj) || obj.is_none())
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
    const long long v = PyLong_AsLongLong(i.ptr());
    if (v == -1 && PyErr_Occurred()) throw py::error_already_set();
    return v;
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

template <class E>
E enumArg(const py::handle& obj, const char* what, const char* choices) {
    const std::string s = strArg(obj, what);
    E e{};
    if (!parse(s, e)) valueError(std::string(what) + " must be " + choices + ", got '" + s + "'");
    return e;
}

std::string choiceArg(const py::handle& obj, const char* what, const std::vector<std::string>& choices) {
    const std::string s = strArg(obj, what);
    if (std::find(choices.begin(), choices.end(), s) != choices.end()) return s;
    std::string all;
    for (const std::string& c : choices) all += (all.empty() ? "'" : ", '") + c + "'";
    valueError(std::string(what) + " must be one of " + all + ", got '" + s + "'");
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
        valueError(e.what());
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
        valueError(std::string(what) + " is not aligned to whole float32 elements; pass numpy.ascontiguousarray(" +
                   what + ")");
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

// ---------------------------------------------------------------------------------------------
// Settings: the CLI's flags as keyword arguments. `quality` is applied first; explicit
// directions/steps/blur then override it, as later flags do on the command line.

struct SettingArgs {
    py::object quality, method, radius, directions, steps, weighting, falloff, blur, device, threads;
    py::dict own;  // the remaining keywords: the methods' own parameters (core/methods.h), by key
};

// A method's own parameter from the method table (ssao_samples, thickness, rtao_grid, ...),
// checked against the table's range; an unknown keyword is a TypeError, as Python's own.
void applyMethodParam(const std::string& key, const py::handle& value, Settings& s) {
    for (const MethodParam* p : allMethodParams()) {
        if (key != p->key) continue;
        // A word the parameter knows ("auto", "inf", "clamp", ...) stands for its value.
        const NamedValue* named = py::isinstance<py::str>(value) ? findNamed(*p, value.cast<std::string>()) : nullptr;
        if (!named && !p->named.empty() && py::isinstance<py::str>(value))  // a word it does not know
            valueError(key + checkParam(*p, std::nan("")).substr(std::string(p->flag).size()) + ", got '" +
                       value.cast<std::string>() + "'");
        if (p->boolField) {
            if (!py::isinstance<py::bool_>(value)) throw py::type_error(key + " must be a bool, got " + typeName(value));
            s.*(p->boolField) = value.cast<bool>();
        } else if (p->intField) {
            s.*(p->intField) = named ? (int)named->value : intInRange(value, p->key, (long long)p->min, (long long)p->max);
        } else {
            const double v = named ? named->value : floatArg(value, p->key);
            const std::string problem = checkParam(*p, v, named != nullptr);  // "--thickness must be ..."
            if (!problem.empty()) valueError(key + problem.substr(std::string(p->flag).size()) + ", got " + std::to_string(v));
            s.*(p->floatField) = (float)v;
        }
        return;
    }
    throw py::type_error("unexpected keyword argument '" + key + "'");
}

// A keyword the method would ignore is refused from the method table (core/methods.h), as the
// CLI refuses the flag. False and None are the defaults: passing them asks for nothing.
void refuseIgnored(const std::string& method, const std::string& key, const py::handle& value) {
    if (value.is_none() || (py::isinstance<py::bool_>(value) && !value.cast<bool>())) return;
    const std::string problem = settingRefusal(method, key, Spelling::Key);
    if (!problem.empty()) valueError(problem);
}

// `method`, when given, is the method the call runs whatever sa.method says (compute_ssdo).
Settings settingsFrom(const SettingArgs& a, const char* method = nullptr) {
    Settings s;
    if (!a.quality.is_none()) {
        const std::string q = strArg(a.quality, "quality");
        if (!applyQualityPreset(q, s)) valueError("quality must be 'low', 'medium', 'high' or 'ultra', got '" + q + "'");
    }
    if (!a.method.is_none()) {
        std::vector<std::string> names;
        for (const MethodInfo& m : methods()) names.push_back(m.name);
        s.method = choiceArg(a.method, "method", names);
    }
    if (!a.radius.is_none()) s.radius = (float)numberArg(a.radius, "radius");
    if (!a.directions.is_none()) s.directions = methodIntArg(a.directions, "directions");
    if (!a.steps.is_none()) s.steps = methodIntArg(a.steps, "steps");
    if (!a.weighting.is_none()) s.weighting = enumArg<Weighting>(a.weighting, "weighting", "'uniform' or 'cosine'");
    if (!a.falloff.is_none()) s.falloff = enumArg<Falloff>(a.falloff, "falloff", "'linear' or 'none'");
    if (!a.blur.is_none()) s.blur = (int)numberArg(a.blur, "blur");
    if (!a.device.is_none()) {
        s.device = strArg(a.device, "device");
        if (!isDeviceName(s.device))
            valueError("device must be one of " + deviceNameList(", ", " or ") + ", got '" + s.device + "'");
    }
    if (!a.threads.is_none()) s.threads = (int)numberArg(a.threads, "threads");
    for (const auto& item : a.own) applyMethodParam(py::str(item.first), item.second, s);
    if (method) s.method = method;
    refuseIgnored(s.method, "directions", a.directions);
    refuseIgnored(s.method, "steps", a.steps);
    refuseIgnored(s.method, "weighting", a.weighting);
    refuseIgnored(s.method, "falloff", a.falloff);
    for (const auto& item : a.own) refuseIgnored(s.method, py::str(item.first), item.second);
    return s;
}

// SSDO's operator settings (method 'ssdo'): --samples, --interleave, --sky, --env-rotate,
// --env-intensity, --light. Checked here so a bad value is a ValueError, not obscura.Error.
struct SsdoArgs {
    py::object samples, interleave, sky, envRotate, envIntensity, lights;
};

std::array<float, 3> tripleArg(const py::handle& obj, const char* what, bool nonNegative) {
    if (!py::isinstance<py::sequence>(obj) || py::isinstance<py::str>(obj) || py::len(obj) != 3)
        valueError(std::string(what) + " must be 3 numbers, got " + typeName(obj));
    py::sequence seq = py::reinterpret_borrow<py::sequence>(obj);
    std::array<float, 3> v{};
    for (int i = 0; i < 3; ++i) {
        const double d = floatArg(seq[i], what);
        if (nonNegative && d < 0) valueError(std::string(what) + " must not be negative, got " + std::to_string(d));
        v[i] = (float)d;
    }
    return v;
}

void applySsdo(const SsdoArgs& a, Settings& s) {
    for (const auto& [key, value] : {std::pair<const char*, const py::object*>{"samples", &a.samples},
                                     {"interleave", &a.interleave}, {"sky", &a.sky}, {"env_rotate", &a.envRotate},
                                     {"env_intensity", &a.envIntensity}, {"lights", &a.lights}})
        refuseIgnored(s.method, key, *value);
    if (!a.samples.is_none()) s.ssdoSamples = methodIntArg(a.samples, "samples");
    if (!a.interleave.is_none()) s.interleave = methodIntArg(a.interleave, "interleave");
    if (s.interleave * s.interleave > s.ssdoSamples)
        valueError("interleave " + std::to_string(s.interleave) + " splits " + std::to_string(s.ssdoSamples) +
                   " samples over " + std::to_string(s.interleave * s.interleave) +
                   " pixels: give at least interleave**2 samples");
    if (!a.sky.is_none()) {
        const std::array<float, 3> c = tripleArg(a.sky, "sky", true);
        std::copy(c.begin(), c.end(), s.skyRadiance);
    }
    if (!a.envRotate.is_none()) s.envRotationDeg = (float)numberArg(a.envRotate, "env_rotate");
    if (!a.envIntensity.is_none()) s.envIntensity = (float)numberArg(a.envIntensity, "env_intensity");
    if (!a.lights.is_none()) {
        if (!py::isinstance<py::sequence>(a.lights) || py::isinstance<py::str>(a.lights))
            valueError("lights must be a list of ((x, y, z), (r, g, b)), got " + typeName(a.lights));
        py::sequence seq = py::reinterpret_borrow<py::sequence>(a.lights);
        if (py::len(seq) > 4) valueError("lights: at most 4 directional lights, got " + std::to_string(py::len(seq)));
        s.lights.clear();
        for (py::handle item : seq) {
            if (!py::isinstance<py::sequence>(item) || py::isinstance<py::str>(item) || py::len(item) != 2)
                valueError("each light must be ((x, y, z), (r, g, b)): a world direction towards the light and "
                           "its irradiance, got " + typeName(item));
            py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
            const std::array<float, 3> d = tripleArg(pair[0], "light direction", false);
            const std::array<float, 3> e = tripleArg(pair[1], "light irradiance", true);
            if (d[0] == 0 && d[1] == 0 && d[2] == 0) valueError("light direction must not be (0, 0, 0)");
            Settings::DirectionalLight l{};
            std::copy(d.begin(), d.end(), l.direction);
            std::copy(e.begin(), e.end(), l.irradiance);
            s.lights.push_back(l);
        }
    }
}

bool upArg(const py::handle& obj) { return choiceArg(obj, "up", {"y", "z"}) == "z"; }

#define OBSCURA_SSDO_ARGS                                                                                            \
    py::arg("samples") = py::none(), py::arg("interleave") = py::none(), py::arg("sky") = py::none(),               \
        py::arg("env_rotate") = py::none(), py::arg("env_intensity") = py::none(), py::arg("lights") = py::none()

#define OBSCURA_SETTING_ARGS                                                                                         \
    py::arg("quality") = py::none(), py::arg("method") = py::none(), py::arg("radius") = py::none(),                \
        py::arg("directions") = py::none(), py::arg("steps") = py::none(), py::arg("weighting") = py::none(),       \
        py::arg("falloff") = py::none(), py::arg("blur") = py::none(), py::arg("device") = py::none(),              \
        py::arg("threads") = py::none()

// ---------------------------------------------------------------------------------------------
// compute_ao

struct ViewArgs {
    py::object camera, normals, depthKind, skyDepth, dataWindow, displayWindow;
};

// The inputs and settings compute_ao and compute_ssdo share: planes viewed in place, checked.
OperatorInputs viewInputs(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v,
                          Settings& settings) {
    OperatorInputs in;
    in.depth = planeArg(depthObj, "depth", 1);
    in.normal = planeArg(normalObj, "normal", 3);
    if (in.normal.width != in.depth.width || in.normal.height != in.depth.height)
        valueError("normal covers " + std::to_string(in.normal.height) + "x" + std::to_string(in.normal.width) +
                   " pixels (H x W) but depth covers " + std::to_string(in.depth.height) + "x" +
                   std::to_string(in.depth.width) + "; they must be the same size");
    const Box2i full{0, 0, in.depth.width, in.depth.height};
    in.dataWindow = v.dataWindow.is_none() ? full : boxArg(v.dataWindow, "data_window");
    if (in.dataWindow.width() != in.depth.width || in.dataWindow.height() != in.depth.height)
        valueError("data_window is " + std::to_string(in.dataWindow.width()) + "x" +
                   std::to_string(in.dataWindow.height()) + " (W x H) but the arrays are " +
                   std::to_string(in.depth.width) + "x" + std::to_string(in.depth.height));
    in.displayWindow = v.displayWindow.is_none() ? full : boxArg(v.displayWindow, "display_window");
    if (!v.normals.is_none()) in.normalSpace = enumArg<NormalSpace>(v.normals, "normals", "'world' or 'camera'");
    if (!v.depthKind.is_none()) in.depthKind = enumArg<DepthKind>(v.depthKind, "depth_kind", "'planar' or 'radial'");
    if (!v.skyDepth.is_none()) settings.skyDepth = (float)numberArg(v.skyDepth, "sky_depth");
    in.camera = cameraArg(v.camera);
    if (!in.camera.valid()) valueError("the camera has no valid projection (focal length or orthographic width)");
    if (in.normalSpace == NormalSpace::World && !in.camera.hasPose)
        valueError("normals='world' needs the camera's pose: give the Camera a camera_to_world matrix, "
                   "or pass camera-space normals with normals='camera'");
    return in;
}

// deep=: hbao's hidden layers (docs/deep.md), (H, W, 2K) float32 (front, back) depth pairs.
ConstPlane deepArg(const py::object& obj, const OperatorInputs& in) {
    if (!py::isinstance<py::array>(obj)) throw py::type_error("deep must be a numpy.ndarray of float32, got " + typeName(obj));
    const py::array a = py::reinterpret_borrow<py::array>(obj);
    const int channels = a.ndim() == 3 ? (int)a.shape(2) : 0;
    if (channels < 2 || channels % 2 != 0)
        valueError("deep must have shape (H, W, 2K): K (front, back) depth pairs per pixel, got " +
                   std::to_string(a.ndim()) + " dimension(s)" + (a.ndim() == 3 ? " of " + std::to_string(channels) + " channels" : ""));
    const ConstPlane p = planeArg(obj, "deep", channels);
    if (p.width != in.depth.width || p.height != in.depth.height) valueError("deep must cover the same pixels as depth");
    return p;
}

py::array computeAo(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v, const SettingArgs& sa,
                    const py::object& deep) {
    Settings settings = settingsFrom(sa);
    if (methodOutputs(settings.method, "do")) valueError("compute_ao computes AO methods; use compute_ssdo for SSDO");
    OperatorInputs in = viewInputs(depthObj, normalObj, v, settings);
    if (!deep.is_none()) {
        if (!methodReads(settings.method, "deep")) valueError("deep layers are used by method='" + methodNames("', '", "deep") + "' only");
        in.deepLayers = deepArg(deep, in);
    }
    OperatorOutputs out;
    {
        // depthObj / normalObj stay referenced by the caller's frame for the whole call.
        py::gil_scoped_release release;
        out = runOperator(in, settings);
    }
    return imageToArray(std::move(out.ao), true);
}

// compute_ssdo: DO (and GI) irradiance and AO of in-memory passes, lit by a lat-long array or
// a constant sky, plus directional lights.
struct SsdoArrayArgs {
    py::object radiance, albedo, environment, bounce, up;
};

py::dict computeSsdo(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v,
                     const SettingArgs& sa, const SsdoArgs& ssdoArgs, const SsdoArrayArgs& x) {
    Settings settings = settingsFrom(sa, "ssdo");
    applySsdo(ssdoArgs, settings);
    settings.bounce = !x.bounce.is_none() && py::bool_(x.bounce);
    if (!x.up.is_none()) settings.zUp = upArg(x.up);
    OperatorInputs in = viewInputs(depthObj, normalObj, v, settings);
    auto sameSize = [&](const ConstPlane& p, const char* what) {
        if (p.width != in.depth.width || p.height != in.depth.height)
            valueError(std::string(what) + " covers " + std::to_string(p.height) + "x" + std::to_string(p.width) +
                       " pixels (H x W) but depth covers " + std::to_string(in.depth.height) + "x" +
                       std::to_string(in.depth.width) + "; they must be the same size");
    };
    if (!x.radiance.is_none()) {
        in.radiance = planeArg(x.radiance, "radiance", 3);
        sameSize(in.radiance, "radiance");
    }
    if (!x.albedo.is_none()) {
        in.albedo = planeArg(x.albedo, "albedo", 3);
        sameSize(in.albedo, "albedo");
    }
    if (settings.bounce && !in.radiance.valid())
        valueError("bounce=True needs radiance: the light leaving the bouncing surfaces, float32 (H, W, 3) "
                   "(e.g. the direct-diffuse pass, with albedo=the albedo pass)");
    ConstPlane env;
    if (!x.environment.is_none()) env = planeArg(x.environment, "environment", 3);

    OperatorOutputs out;
    {
        py::gil_scoped_release release;
        Image environment;
        if (env.valid()) {  // the prefilter wants an owned image: one copy of the (small) map
            environment = Image(env.width, env.height, 3);
            for (int y = 0; y < env.height; ++y)
                for (int xx = 0; xx < env.width; ++xx) {
                    const float* src = env.data + y * env.yStride + xx * env.xStride;
                    std::copy(src, src + 3, environment.at(xx, y));
                }
            in.environment = &environment;
        }
        out = runOperator(in, settings);
    }
    py::dict d;
    d["do"] = imageToArray(std::move(out.directional), false);
    d["gi"] = out.indirect.empty() ? py::object(py::none()) : py::object(imageToArray(std::move(out.indirect), false));
    d["ao"] = imageToArray(std::move(out.ao), true);
    return d;
}

// ---------------------------------------------------------------------------------------------
// File-level jobs: a FrameJob built from keyword arguments named like the CLI's flags.

struct FileArgs {
    py::object preset, layer, camera, fovDeg, orthoWidth, cameraToWorld, depth, normals, skyDepth, maxPixels;
};

// max_pixels=, as --max-pixels: a window above it is refused before anything is allocated.
long long maxPixelsArg(const py::object& obj) {
    if (obj.is_none()) return kDefaultMaxPixels;
    return (long long)numberArg(obj, "max_pixels");
}

FrameJob jobFrom(const py::object& path, const FileArgs& f) {
    FrameJob job;
    job.input = pathArg(path, "path");
    job.maxPixels = maxPixelsArg(f.maxPixels);
    if (!f.preset.is_none()) job.preset = choiceArg(f.preset, "preset", presetNames());
    if (!f.layer.is_none()) {
        if (!py::isinstance<py::dict>(f.layer))
            throw py::type_error("layer must be a dict {role: layer name}, e.g. {'normal': 'ViewLayer.Normal'}, got " +
                                 typeName(f.layer));
        for (auto item : py::reinterpret_borrow<py::dict>(f.layer)) {
            const std::string role = strArg(item.first, "layer role");
            Role r;
            if (!parseRole(role, r))
                valueError("layer: unknown role '" + role + "' (depth, normal, position, beauty, albedo, direct-diffuse)");
            job.layerOverrides[r] = strArg(item.second, "layer name");
        }
    }
    if (!f.camera.is_none()) job.camera.sidecarPath = pathArg(f.camera, "camera");
    if (!f.fovDeg.is_none()) job.camera.fovDeg = numberArg(f.fovDeg, "fov_deg");
    if (!f.orthoWidth.is_none()) job.camera.orthoWidth = numberArg(f.orthoWidth, "ortho_width");
    if (job.camera.fovDeg && job.camera.orthoWidth) valueError("give either fov_deg or ortho_width, not both");
    if (!f.cameraToWorld.is_none()) job.camera.cameraToWorld = matrixRowsArg(f.cameraToWorld, "camera_to_world");
    if (!f.depth.is_none()) job.depthKind = enumArg<DepthKind>(f.depth, "depth", "'planar' or 'radial'");
    if (!f.normals.is_none()) job.normalSpace = enumArg<NormalSpace>(f.normals, "normals", "'world' or 'camera'");
    if (!f.skyDepth.is_none()) job.skyDepth = (float)numberArg(f.skyDepth, "sky_depth");
    return job;
}

#define OBSCURA_FILE_ARGS                                                                                           \
    py::arg("preset") = py::none(), py::arg("layer") = py::none(), py::arg("camera") = py::none(),                 \
        py::arg("fov_deg") = py::none(), py::arg("ortho_width") = py::none(),                                      \
        py::arg("camera_to_world") = py::none(), py::arg("depth") = py::none(), py::arg("normals") = py::none(),  \
        py::arg("sky_depth") = py::none(), py::arg("max_pixels") = py::none()

py::dict readPassesPy(const py::object& path, const FileArgs& f) {
    const FrameJob job = jobFrom(path, f);
    FramePasses p;
    std::optional<Camera> camera;
    std::string cameraError;
    DepthKind depthKind = DepthKind::Planar;
    NormalSpace normalSpace = NormalSpace::World;
    float sky = 1e9f;
    {
        py::gil_scoped_release release;
        p = loadFramePasses(job, false, nullptr, true);
        try {
            camera = resolveFrameCamera(job, p);
        } catch (const Error& e) {
            cameraError = e.what();
        }
        depthKind = job.depthKind.value_or(p.plan.depthKind);
        normalSpace = job.normalSpace.value_or(p.plan.normalSpace);
        sky = job.skyDepth.value_or(p.plan.skyDepth);
        // Left-handed camera-space normals (+z forward) become OpenGL's, as runFrameJob does.
        if (p.plan.normalsLeftHanded && normalSpace == NormalSpace::Camera && !job.normalSpace)
            for (size_t i = 2; i < p.normal.pixels.size(); i += 3) p.normal.pixels[i] = -p.normal.pixels[i];
    }
    py::dict layers;
    for (const LayerBinding& b : p.plan.bindings) layers[py::str(roleName(b.role))] = py::cast(b.channels);
    py::dict d;
    d["depth"] = imageToArray(std::move(p.depth), true);
    d["normal"] = imageToArray(std::move(p.normal), false);
    if (!p.position.empty()) d["position"] = imageToArray(std::move(p.position), false);
    d["camera"] = camera ? py::cast(*camera) : py::none();
    d["camera_error"] = camera ? py::none() : py::cast(cameraError);
    d["normals"] = toString(normalSpace);
    d["depth_kind"] = toString(depthKind);
    d["sky_depth"] = (double)sky;
    d["data_window"] = boxToTuple(p.data);
    d["display_window"] = boxToTuple(p.display);
    d["pixel_aspect"] = p.pixelAspect;
    d["preset"] = p.plan.preset;
    d["layers"] = layers;
    d["part"] = p.part;
    d["path"] = job.input;
    return d;
}

struct OutputArgs {
    py::object outLayer, outType, badPixels, reference, report, preview, inPlace, write, previewExposure;
};

// process()'s SSDO keywords beyond the operator's: what to write and where the light comes from.
struct JobSsdoArgs {
    py::object bounce, bounceSource, env, envColorspace, colorspace, up, timesAlbedo, relitDirect;
};

py::object processPy(const py::object& path, const py::object& out, const FileArgs& f, const SettingArgs& sa,
                     const OutputArgs& o, const SsdoArgs& ssdoArgs, const JobSsdoArgs& js) {
    FrameJob job = jobFrom(path, f);
    job.output = pathArg(out, "out");
    job.settings = settingsFrom(sa);
    applySsdo(ssdoArgs, job.settings);
    // Keywords and outputs the method would ignore: asking for them would silently write nothing.
    for (const auto& [key, value] :
         {std::pair<const char*, const py::object*>{"bounce", &js.bounce}, {"bounce_source", &js.bounceSource},
          {"env", &js.env}, {"env_colorspace", &js.envColorspace}, {"colorspace", &js.colorspace}, {"up", &js.up},
          {"times_albedo", &js.timesAlbedo}, {"relit_direct", &js.relitDirect}})
        refuseIgnored(job.settings.method, key, *value);
    auto needSsdo = [&](const std::string& output) {
        const std::string problem = outputRefusal(job.settings.method, output, Spelling::Key);
        if (!problem.empty()) valueError(problem);
    };
    if (!o.outLayer.is_none()) {
        if (py::isinstance<py::dict>(o.outLayer)) {
            for (auto item : py::reinterpret_borrow<py::dict>(o.outLayer)) {
                const std::string role = strArg(item.first, "out_layer role");
                const std::string name = strArg(item.second, "out_layer name");
                if (name.empty()) valueError("out_layer['" + role + "'] must not be empty");
                if (role == "ao") {
                    job.aoLayer = name;
                    continue;
                }
                if (role != "do" && role != "gi" && role != "relit")
                    valueError("out_layer: unknown output '" + role + "' (available: ao, do, gi, relit)");
                needSsdo(role);
                // Naming gi or relit also asks for it, as --out-layer does.
                if (role == "do") job.doLayer = name;
                else if (role == "gi") job.giLayer = name, job.writeIndirect = true;
                else job.relitLayer = name, job.writeRelit = true;
            }
        } else {
            job.aoLayer = strArg(o.outLayer, "out_layer");
        }
        if (job.aoLayer.empty()) valueError("out_layer must not be empty");
    }
    if (!js.bounce.is_none() && py::bool_(js.bounce)) requestBounce(job);
    if (!js.bounceSource.is_none()) {
        job.bounceSource = strArg(js.bounceSource, "bounce_source");
        if (job.bounceSource.empty())
            valueError("bounce_source must be 'direct-diffuse', 'beauty' or an RGB layer name, got ''");
    }
    if (!js.env.is_none()) job.envPath = pathArg(js.env, "env");
    if (!js.envColorspace.is_none()) job.envColourSpace = strArg(js.envColorspace, "env_colorspace");
    if (!js.colorspace.is_none()) job.colourSpace = strArg(js.colorspace, "colorspace");
    if (!js.up.is_none()) job.zUp = upArg(js.up);
    if (!js.timesAlbedo.is_none() && py::bool_(js.timesAlbedo)) job.timesAlbedo = true;
    if (!js.relitDirect.is_none() && py::bool_(js.relitDirect)) job.relitWithDirect = true;
    if (!o.outType.is_none()) job.aoFloat = choiceArg(o.outType, "out_type", {"half", "float"}) == "float";
    if (!o.badPixels.is_none())
        job.badPixels = choiceArg(o.badPixels, "bad_pixels", {"error", "skip"}) == "skip" ? BadPixelPolicy::Skip
                                                                                       : BadPixelPolicy::Error;
    if (!o.reference.is_none()) job.referenceLayer = strArg(o.reference, "reference");
    if (!o.preview.is_none()) job.previewPath = pathArg(o.preview, "preview");
    if (!o.previewExposure.is_none()) {
        if (job.previewPath.empty()) valueError("preview_exposure needs preview=PATH");
        job.previewExposure = (float)numberArg(o.previewExposure, "preview_exposure");
    }
    if (!o.inPlace.is_none()) job.inPlace = py::bool_(o.inPlace);
    if (!o.write.is_none()) parse(choiceArg(o.write, "write", {"copy", "new", "append"}), job.write);
    if (job.write == WriteMode::New && job.inPlace)
        valueError("write='new' and in_place=True do not go together: the output holds only the new layers");
    const std::string reportPath = o.report.is_none() ? std::string() : pathArg(o.report, "report");

    std::string json;
    {
        py::gil_scoped_release release;
        checkFrameFiles({{&job, reportPath}}, Spelling::Key);
        if (!reportPath.empty()) requireOutputDirectory(reportPath);
        const FrameReport report = runFrameJob(job);
        json = frameReportJson(job, report);
        if (!reportPath.empty()) writeTextFileAtomically(reportPath, json);
    }
    return py::module_::import("json").attr("loads")(json);
}

// The structure `--inspect --json` prints, through Python's json so it equals that output.
py::object inspectPy(const py::object& path, const FileArgs& f, const py::object& device) {
    FrameJob job = jobFrom(path, f);
    if (!device.is_none()) {
        SettingArgs sa{py::none(), py::none(), py::none(), py::none(), py::none(),
                       py::none(), py::none(), py::none(), device,      py::none(), py::dict()};
        job.settings = settingsFrom(sa);
    }
    std::string json;
    {
        py::gil_scoped_release release;
        json = inspectFrameJson(job).dump();
    }
    return py::module_::import("json").attr("loads")(json);
}

py::array readLayerPy(const py::object& path, const py::object& nameObj, const py::object& maxPixels) {
    const std::string file = pathArg(path, "path");
    const std::string name = strArg(nameObj, "name");
    const long long limit = maxPixelsArg(maxPixels);
    Image image;
    {
        py::gil_scoped_release release;
        const ExrInfo info = readExrInfo(file, limit);
        std::vector<ChannelRef> wanted;
        for (size_t p = 0; p < info.parts.size() && wanted.empty(); ++p) {
            const ExrPart& part = info.parts[p];
            if (part.findChannel(name) >= 0) {
                wanted.push_back({(int)p, name});
                break;
            }
            // LAYER.c channels, in a conventional order: R G B A, X Y Z, then the rest by name.
            std::vector<std::string> found;
            for (const ExrChannel& c : part.channels)
                if (c.name.size() > name.size() + 1 && c.name.compare(0, name.size() + 1, name + ".") == 0 &&
                    c.name.find('.', name.size() + 1) == std::string::npos)
                    found.push_back(c.name);
            auto rank = [&](const std::string& n) {
                static const std::string order = "RGBAXYZW";
                const std::string suffix = n.substr(name.size() + 1);
                const size_t i = suffix.size() == 1 ? order.find(suffix[0]) : std::string::npos;
                return i == std::string::npos ? order.size() : i;
            };
            std::stable_sort(found.begin(), found.end(),
                             [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
            for (const std::string& n : found) wanted.push_back({(int)p, n});
        }
        if (wanted.empty()) {
            std::string all;
            for (const std::string& l : listLayers(info)) all += (all.empty() ? "" : "; ") + l;
            throw FileError(file, "no channel or layer '" + name + "'; layers found: " + all);
        }
        std::vector<Image> planes = readExrChannels(file, info, wanted, false, nullptr);
        image = planes.size() == 1 ? std::move(planes[0]) : interleavePlanes(planes, 0, (int)planes.size());
    }
    return imageToArray(std::move(image), true);
}

std::string cameraRepr(const Camera& c) {
    std::ostringstream os;
    os.precision(9);
    os << "obscura.Camera(" << (c.projection == Projection::Perspective ? "perspective" : "orthographic")
       << ", fx=" << c.fx << ", fy=" << c.fy << ", cx=" << c.cx << ", cy=" << c.cy
       << (c.hasPose ? ", posed" : ", no pose");
    if (!c.source.empty()) os << ", source='" << c.source << "'";
    os << ")";
    return os.str();
}

Camera withPose(Camera c, const py::object& m) {
    if (!m.is_none()) {
        c.cameraToWorld = cameraToWorldFromRows(matrixRowsArg(m, "camera_to_world"), "camera_to_world");
        c.hasPose = true;
    }
    return c;
}

void checkDisplaySize(int width, int height) {
    if (width < 1 || height < 1)
        valueError("width and height are the display window's size in pixels and must be positive, got " +
                   std::to_string(width) + "x" + std::to_string(height));
}

const char* kModuleDoc = R"doc(obscura: screen-space ambient occlusion (HBAO) and directional occlusion with one
bounce (SSDO) for renders that already exist.

The same operator and file pipeline as the ``obscura`` command, for numpy:

- ``compute_ao(depth, normal, camera=..., **settings)`` -> float32 (H, W) AO from arrays
  (viewed in place, never converted: float32, shape (H, W) and (H, W, 3)).
- ``compute_ssdo(depth, normal, camera=..., radiance=, albedo=, environment=, bounce=, ...)``
  -> dict of 'do' (H, W, 3), 'gi' (H, W, 3) or None, 'ao' (H, W), from arrays.
- ``read_passes(path)`` -> dict of the depth/normal/position planes, camera and conventions
  of a multilayer EXR, found by renderer preset as the CLI does.
- ``ao_from_passes(passes, **settings)`` -> compute_ao over a read_passes() dict.
- ``process(path, out, **settings)`` -> the CLI's ``--report`` JSON as a dict; writes OUT.
- ``inspect(path)`` -> dict, the CLI's ``--inspect --json``; ``read_layer(path, name)`` -> an EXR layer.
- ``Camera.perspective / .orthographic / .from_sidecar``.

Settings are the CLI's flags with underscores: radius, directions, steps, weighting
('uniform' | 'cosine'), falloff ('linear' | 'none'), blur, quality ('low' | 'medium' |
'high' | 'ultra', applied before directions/steps/blur), method (a key of obscura.METHODS:
'hbao', 'ssdo', 'ssao', 'rtao'), device, threads; each method's own keywords as METHODS lists
them (ssao_samples, ssao_hemisphere, rtao_rays, thickness, rtao_grid); for 'ssdo' also
samples, interleave, sky, env_rotate, env_intensity, lights, up.

Relighting from Python: ``process(path, out, method='ssdo', bounce=True, env='studio.exr',
env_rotate=90, out_layer={'relit': 'Relit'})`` writes OUT with the directional occlusion
(obscura.DO), the one bounce (obscura.GI) and Relit.R/G/B = albedo x (DO + GI) / pi (without
out_layer: obscura.relit), i.e. the
frame's diffuse lighting redone under that environment (relit_direct=True adds the render's
own direct diffuse light; times_albedo=True writes DO/GI as outgoing radiance). Without env
the light is a constant sky=(r, g, b); lights=[((x, y, z), (r, g, b))] adds up to four
directional lights. The report's 'plan' lists what ran and 'written' the channels added.
examples/batch_relight.py does this over a frame sequence, one output sequence per lighting
setup (environment maps and/or rotations of one), with progress and --resume.

Errors: bad arguments (shape, dtype, memory layout, unknown names, out-of-range values) raise
ValueError (TypeError for a wrong kind of object, a missing argument or one too many), in one line
naming the argument; a failure of the file pipeline or the
operator (missing or corrupt file, no camera, bad pixels, unwritable output) raises
obscura.Error, a RuntimeError whose message is the CLI's one-line error.
The GIL is released while files are read or written and while the AO is computed.)doc";

} // namespace
} // namespace obscura::python

PYBIND11_MODULE(_obscura, m) {
    using namespace obscura;
    using namespace obscura::python;
    m.doc() = kModuleDoc;
    m.attr("__version__") = OBSCURA_VERSION_STRING;
    py::register_exception<Error>(m, "Error", PyExc_RuntimeError);
    // Registered after Error, so tried first: a request that cannot be carried out as asked
    // (two roles naming one file) is the caller's ValueError, like a bad keyword.
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const UsageError& e) {
            PyErr_SetString(PyExc_ValueError, e.what());
        }
    });
    m.attr("Error").attr("__doc__") =
        "A failure reported by obscura's file pipeline or operator (missing, unreadable or corrupt file, no "
        "camera, bad pixels, unwritable output). Subclass of RuntimeError; str(e) is one line naming the file "
        "and the problem, as the CLI prints it.";

    py::class_<Camera>(m, "Camera", R"doc(A pinhole or orthographic camera (OpenGL convention: camera looks down -Z, +Y up).

Pixel (x, y) has its centre at (x + 0.5, y + 0.5) in display-window coordinates, y down.
Build one with Camera.perspective, Camera.orthographic or Camera.from_sidecar, or take
read_passes(path)['camera']. camera_to_world is a 4x4 row-major matrix (numpy float64),
or None when only the intrinsics are known.)doc")
        .def(py::init([](double fx, py::object fy, py::object cx, py::object cy, py::object c2w, bool ortho) {
                 if (!(fx > 0) || !std::isfinite(fx)) valueError("fx must be positive");
                 Camera c;
                 c.projection = ortho ? Projection::Orthographic : Projection::Perspective;
                 c.fx = fx;
                 c.fy = fy.is_none() ? fx : floatArg(fy, "fy");
                 if (!(c.fy > 0)) valueError("fy must be positive");
                 c.cx = floatArg(cx, "cx");
                 c.cy = floatArg(cy, "cy");
                 c.source = "python";
                 return withPose(c, c2w);
             }),
             py::arg("fx"), py::kw_only(), py::arg("fy") = py::none(), py::arg("cx"), py::arg("cy"),
             py::arg("camera_to_world") = py::none(), py::arg("orthographic") = false,
             R"doc(Camera from intrinsics: fx, fy focal lengths in pixels (orthographic: pixels per world
unit; fy defaults to fx), principal point (cx, cy) in display pixels.)doc")
        .def_static(
            "perspective",
            [](double fovDeg, int width, int height, py::object c2w, double pixelAspect) {
                if (!(fovDeg > 0 && fovDeg < 180)) valueError("fov_deg must be between 0 and 180, got " + std::to_string(fovDeg));
                checkDisplaySize(width, height);
                if (!(pixelAspect > 0) || !std::isfinite(pixelAspect)) valueError("pixel_aspect must be positive");
                Camera c = Camera::perspectiveFromFov(fovDeg * M_PI / 180.0, width, height, pixelAspect);
                c.source = "python (perspective)";
                return withPose(c, c2w);
            },
            py::arg("fov_deg"), py::arg("width"), py::arg("height"), py::arg("camera_to_world") = py::none(),
            py::arg("pixel_aspect") = 1.0,
            R"doc(Perspective camera with horizontal field of view fov_deg across a display window of
width x height pixels (the CLI's --fov-deg); optional 4x4 camera_to_world (--camera-to-world).)doc")
        .def_static(
            "orthographic",
            [](double widthWorld, int width, int height, py::object c2w, double pixelAspect) {
                if (!(widthWorld > 0) || !std::isfinite(widthWorld)) valueError("width_world must be positive");
                checkDisplaySize(width, height);
                if (!(pixelAspect > 0) || !std::isfinite(pixelAspect)) valueError("pixel_aspect must be positive");
                Camera c = Camera::orthographic(widthWorld, width, height, pixelAspect);
                c.source = "python (orthographic)";
                return withPose(c, c2w);
            },
            py::arg("width_world"), py::arg("width"), py::arg("height"), py::arg("camera_to_world") = py::none(),
            py::arg("pixel_aspect") = 1.0,
            R"doc(Orthographic camera width_world world units across a display window of width x height
pixels (the CLI's --ortho-width).)doc")
        .def_static(
            "from_sidecar",
            [](const py::object& path, int width, int height, double pixelAspect) {
                const std::string p = pathArg(path, "path");
                checkDisplaySize(width, height);
                py::gil_scoped_release release;
                return cameraFromSidecar(p, Box2i{0, 0, width, height}, pixelAspect);
            },
            py::arg("path"), py::arg("width"), py::arg("height"), py::arg("pixel_aspect") = 1.0,
            R"doc(Camera from a JSON sidecar (camera_to_world rows, horizontal_fov_rad or ortho_width), as
--camera FILE.json reads it, for a display window of width x height pixels. Raises obscura.Error
when the file is missing or invalid.)doc")
        .def_property_readonly(
            "projection", [](const Camera& c) { return c.projection == Projection::Perspective ? "perspective" : "orthographic"; },
            "'perspective' or 'orthographic'.")
        .def_property_readonly("fx", [](const Camera& c) { return c.fx; }, "Focal length in pixels (orthographic: pixels per unit).")
        .def_property_readonly("fy", [](const Camera& c) { return c.fy; })
        .def_property_readonly("cx", [](const Camera& c) { return c.cx; }, "Principal point, display pixels.")
        .def_property_readonly("cy", [](const Camera& c) { return c.cy; })
        .def_property(
            "camera_to_world",
            [](const Camera& c) -> py::object { return c.hasPose ? py::object(matrixToRows(c.cameraToWorld)) : py::none(); },
            [](Camera& c, py::object m) {
                if (m.is_none()) {
                    c.cameraToWorld = glm::dmat4(1.0);
                    c.hasPose = false;
                } else {
                    c = withPose(c, m);
                }
            },
            "4x4 row-major camera-to-world matrix (OpenGL convention), or None if the pose is unknown.")
        .def_property_readonly("has_pose", [](const Camera& c) { return c.hasPose; })
        .def_property_readonly("source", [](const Camera& c) { return c.source; },
                               "Where the camera came from (flags, sidecar, header, fit, python).")
        .def_property_readonly(
            "fit_residual_px",
            [](const Camera& c) -> py::object { return c.fitResidualPx >= 0 ? py::cast(c.fitResidualPx) : py::none(); },
            "RMS reprojection error of a fit to the position pass, None if not fitted.")
        .def(
            "horizontal_fov_deg", [](const Camera& c, int width) { return c.horizontalFovRad(width) * 180.0 / M_PI; },
            py::arg("width"), "Horizontal FOV across a display `width` pixels wide (0 for orthographic).")
        .def("__repr__", &cameraRepr);

    m.def(
        "compute_ao",
        [](const py::object& depth, const py::object& normal, const py::args& extra, py::object camera,
           py::object normals, py::object depthKind, py::object skyDepth, py::object dataWindow,
           py::object displayWindow, py::object quality, py::object method, py::object radius, py::object directions,
           py::object steps, py::object weighting, py::object falloff, py::object blur, py::object device,
           py::object threads, py::object deep, const py::kwargs& own) {
            checkArrayCall("compute_ao", extra, depth, normal, camera);
            return computeAo(depth, normal, ViewArgs{camera, normals, depthKind, skyDepth, dataWindow, displayWindow},
                             SettingArgs{quality, method, radius, directions, steps, weighting, falloff, blur, device,
                                         threads, own},
                             deep);
        },
        py::arg("depth") = py::none(), py::arg("normal") = py::none(), py::arg("camera") = py::none(),
        py::arg("normals") = "world",
        py::arg("depth_kind") = "planar", py::arg("sky_depth") = 1e9, py::arg("data_window") = py::none(),
        py::arg("display_window") = py::none(), OBSCURA_SETTING_ARGS, py::arg("deep") = py::none(),
        R"doc(Ambient occlusion of in-memory passes: a float32 array (H, W), 1 = unoccluded.

depth: float32 (H, W), planar camera depth (or distance to the eye with depth_kind='radial').
normal: float32 (H, W, 3), world space (normals='world', needs camera.camera_to_world) or
OpenGL camera space (normals='camera').
Both are read in place, without a copy, whatever their strides (slices, transposes, broadcasts),
as long as strides are whole float32 elements and a normal's 3 components are adjacent.
Anything else raises ValueError (no silent conversion: use .astype(numpy.float32) or
numpy.ascontiguousarray). Pixels with depth 0, inf, >= sky_depth, NaN or negative are
background (AO = 1).
deep (hbao): float32 (H, W, 2K), the surfaces along each pixel's ray as (front, back) depths,
nearest first, the visible one first; front inf past a ray's last; back == front where the
span is unknown (docs/deep.md). deep_layers=K caps how many are used.

camera: obscura.Camera, required. data_window: (x0, y0, x1, y1) the arrays cover in display-window
pixels (default (0, 0, W, H); larger than the display window for overscan). display_window:
the frame's (x0, y0, x1, y1), default (0, 0, W, H).
Settings (defaults as the CLI): radius=1.0 world units, directions=8, steps=8,
weighting='uniform'|'cosine', falloff='linear'|'none', blur=1 px (the 'medium' preset's), quality=None ('low',
'medium', 'high', 'ultra'; explicit directions/steps/blur override it), method='hbao'
(or 'ssao', 'rtao', with their own keywords: ssao_samples=16, ssao_hemisphere=False,
rtao_rays=16, rtao_grid=1), thickness='auto' (hbao and rtao: world units, 'auto' or 'inf'),
device='cpu', threads=0 (all cores). The GIL is released while computing.)doc");

    m.def(
        "compute_ssdo",
        [](const py::object& depth, const py::object& normal, const py::args& extra, py::object camera,
           py::object radiance, py::object albedo, py::object environment, py::object bounce, py::object up,
           py::object normals, py::object depthKind, py::object skyDepth, py::object dataWindow,
           py::object displayWindow, py::object radius, py::object blur, py::object device, py::object threads,
           py::object samples, py::object interleave, py::object sky, py::object envRotate, py::object envIntensity,
           py::object lights, const py::kwargs& unknown) {
            checkArrayCall("compute_ssdo", extra, depth, normal, camera);
            checkNoKeywords("compute_ssdo", unknown);
            const py::object none = py::none();
            return computeSsdo(depth, normal, ViewArgs{camera, normals, depthKind, skyDepth, dataWindow, displayWindow},
                               SettingArgs{none, none, radius, none, none, none, none, blur, device, threads, py::dict()},
                               SsdoArgs{samples, interleave, sky, envRotate, envIntensity, lights},
                               SsdoArrayArgs{radiance, albedo, environment, bounce, up});
        },
        py::arg("depth") = py::none(), py::arg("normal") = py::none(), py::arg("camera") = py::none(),
        py::arg("radiance") = py::none(),
        py::arg("albedo") = py::none(), py::arg("environment") = py::none(), py::arg("bounce") = false,
        py::arg("up") = "y", py::arg("normals") = "world", py::arg("depth_kind") = "planar",
        py::arg("sky_depth") = 1e9, py::arg("data_window") = py::none(), py::arg("display_window") = py::none(),
        py::arg("radius") = py::none(), py::arg("blur") = py::none(), py::arg("device") = py::none(),
        py::arg("threads") = py::none(), OBSCURA_SSDO_ARGS,
        R"doc(Screen-space directional occlusion (method 'ssdo') of in-memory passes, as a dict:
'do' float32 (H, W, 3) irradiance from the open directions, 'gi' float32 (H, W, 3) one-bounce
irradiance (None unless bounce=True), 'ao' float32 (H, W).

depth, normal, camera, normals, depth_kind, sky_depth, data_window, display_window: as
compute_ao, viewed in place. radiance: float32 (H, W, 3), the light leaving each pixel's surface
(the bounce source; required with bounce=True); albedo: float32 (H, W, 3), optional, multiplies
radiance (give both for the CLI's default bounce source, direct-diffuse x albedo). Both viewed
in place, in the working colour space. environment: float32 (Hm, Wm, 3) lat-long radiance (one
copy is made); None lights with the constant sky. Settings as the CLI's: radius (r_max, default
1), samples (default 64), interleave (default 2), blur (0 = as wide as the interleave block),
sky (r, g, b) (default white), env_rotate (degrees), env_intensity, up ('y' | 'z'), lights
(up to 4 ((x, y, z), (r, g, b))), device, threads. The GIL is released while computing.)doc");

    m.def(
        "ao_from_passes",
        [](const py::object& passesObj, const py::args& extra, py::object quality, py::object method,
           py::object radius, py::object directions, py::object steps, py::object weighting, py::object falloff,
           py::object blur, py::object device, py::object threads, const py::kwargs& own) {
            const py::dict passes = passesArg(extra, passesObj);
            for (const char* key : {"depth", "normal", "camera"})
                if (!passes.contains(key)) valueError(std::string("passes has no '") + key + "' (use read_passes())");
            py::object camera = passes["camera"];
            if (camera.is_none()) {
                const py::object why =
                    passes.contains("camera_error") ? py::object(passes["camera_error"]) : py::object(py::none());
                throw Error(why.is_none() ? std::string("the passes have no camera")
                                          : why.cast<std::string>());
            }
            auto get = [&](const char* key) -> py::object {
                return passes.contains(key) ? py::object(passes[key]) : py::object(py::none());
            };
            return computeAo(passes["depth"], passes["normal"],
                             ViewArgs{camera, get("normals"), get("depth_kind"), get("sky_depth"), get("data_window"),
                                      get("display_window")},
                             SettingArgs{quality, method, radius, directions, steps, weighting, falloff, blur, device,
                                         threads, own},
                             py::none());
        },
        py::arg("passes") = py::none(), OBSCURA_SETTING_ARGS,
        R"doc(compute_ao over a read_passes() dict, with its camera, conventions (normals, depth_kind,
sky_depth) and windows: the same AO that process() writes for that file and these settings.
Raises obscura.Error when the passes have no camera (see passes['camera_error']).)doc");

    m.def(
        "read_passes",
        [](const py::object& path, const py::args& extra, py::object preset, py::object layer, py::object camera,
           py::object fovDeg, py::object orthoWidth, py::object c2w, py::object depth, py::object normals,
           py::object skyDepth, py::object maxPixels, const py::kwargs& unknown) {
            checkFileCall("read_passes", extra, unknown, path);
            return readPassesPy(path, FileArgs{preset, layer, camera, fovDeg, orthoWidth, c2w, depth, normals, skyDepth,
                                               maxPixels});
        },
        py::arg("path") = py::none(), OBSCURA_FILE_ARGS,
        R"doc(The passes of a multilayer EXR, found as the CLI finds them, as a dict:

'depth' float32 (H, W); 'normal' float32 (H, W, 3) (RenderMan's left-handed camera normals
already flipped to OpenGL's); 'position' float32 (H, W, 3) when the file has one;
'camera' obscura.Camera or None ('camera_error' then says why); 'normals' 'world'|'camera';
'depth_kind' 'planar'|'radial'; 'sky_depth'; 'data_window' and 'display_window'
(x0, y0, x1, y1), half-open, display min = (0, 0); 'pixel_aspect'; 'preset'; 'layers'
{role: [channel names]}; 'part'; 'path'. Arrays cover the data window.

Keywords as process(): preset ('auto', 'blender', 'arnold', 'renderman', 'vray', 'karma',
'generic'), layer={role: name}, camera (sidecar path; default NAME.json next to the file),
fov_deg, ortho_width, camera_to_world (4x4 row-major), depth, normals, sky_depth, max_pixels.
Raises obscura.Error for a missing/unreadable file or missing passes.)doc");

    m.def(
        "process",
        [](const py::object& path, const py::object& out, const py::args& extra, py::object quality,
           py::object method, py::object radius, py::object directions, py::object steps, py::object weighting, py::object falloff, py::object blur,
           py::object device, py::object threads, py::object preset, py::object layer, py::object camera,
           py::object fovDeg, py::object orthoWidth, py::object c2w, py::object depth, py::object normals,
           py::object skyDepth, py::object maxPixels, py::object outLayer, py::object outType, py::object badPixels, py::object reference,
           py::object report, py::object preview, py::object inPlace, py::object samples, py::object interleave,
           py::object sky, py::object envRotate, py::object envIntensity, py::object lights, py::object bounce,
           py::object bounceSource, py::object env, py::object envColorspace, py::object colorspace, py::object up,
           py::object timesAlbedo, py::object relitDirect, py::object write, py::object previewExposure,
           const py::kwargs& own) {
            checkPositional("process", extra, {"path", "out"}, "method=..., radius=...");
            required("process", path, "path", "the input EXR's path");
            required("process", out, "out", "the output EXR's path");
            return processPy(path, out,
                             FileArgs{preset, layer, camera, fovDeg, orthoWidth, c2w, depth, normals, skyDepth, maxPixels},
                             SettingArgs{quality, method, radius, directions, steps, weighting, falloff, blur, device,
                                         threads, own},
                             OutputArgs{outLayer, outType, badPixels, reference, report, preview, inPlace, write,
                                        previewExposure},
                             SsdoArgs{samples, interleave, sky, envRotate, envIntensity, lights},
                             JobSsdoArgs{bounce, bounceSource, env, envColorspace, colorspace, up, timesAlbedo,
                                         relitDirect});
        },
        py::arg("path") = py::none(), py::arg("out") = py::none(), OBSCURA_SETTING_ARGS, OBSCURA_FILE_ARGS,
        py::arg("out_layer") = py::none(), py::arg("out_type") = py::none(), py::arg("bad_pixels") = py::none(),
        py::arg("reference") = py::none(), py::arg("report") = py::none(), py::arg("preview") = py::none(),
        py::arg("in_place") = py::none(), OBSCURA_SSDO_ARGS, py::arg("bounce") = py::none(),
        py::arg("bounce_source") = py::none(), py::arg("env") = py::none(), py::arg("env_colorspace") = py::none(),
        py::arg("colorspace") = py::none(), py::arg("up") = py::none(), py::arg("times_albedo") = py::none(),
        py::arg("relit_direct") = py::none(), py::arg("write") = py::none(), py::arg("preview_exposure") = py::none(),
        R"doc(obscura PATH -o OUT [flags]: writes OUT, a copy of PATH with the new layers added, and returns
the --report JSON as a dict (settings, camera, conventions, timings_s, stats, reference, warnings,
plan, written: the channels added).

The layers written, by argument (the CLI's flags write the same):
- always: the AO, obscura.AO.Y (out_layer='NAME' or {'ao': 'NAME'}: NAME.Y).
- method='ssdo': also the directional occlusion obscura.DO.R/G/B ({'do': NAME} renames it).
- method='ssdo', bounce=True: also the one bounce obscura.GI.R/G/B and the relit image
  obscura.relit.R/G/B = albedo x (DO + GI) / pi (+ albedo x direct diffuse with
  relit_direct=True). Needs the albedo pass and the bounce source's (bounce_source, default
  'direct-diffuse', itself times the albedo); a file without them raises obscura.Error.
- out_layer={'gi': NAME} or {'relit': NAME} (ssdo): names that layer and asks for it alone, so
  out_layer={'gi': 'obscura.GI'} without bounce writes GI but no relit.

Keywords are the CLI's flags with underscores: quality, method (a key of obscura.METHODS), radius,
directions, steps, weighting, falloff, blur, device, threads; preset, layer={role: name}, camera
(sidecar path), fov_deg, ortho_width, camera_to_world (4x4 or 16 numbers, row-major), depth
('planar' | 'radial'), normals ('world' | 'camera'), sky_depth, max_pixels (refuse a data or
display window above it before allocating, as --max-pixels; default 16384^2); out_layer (above),
out_type ('half' | 'float'), bad_pixels ('error' | 'skip'), reference (layer name), report
(also write the JSON there), preview (PNG path: 8-bit sRGB of the AO, or for 'ssdo' of the relit
layer when written, else the DO), preview_exposure (stops before the preview's encoding; default
AO 0, ssdo automatic: the 99th percentile at 0.8), in_place (bool), write ('copy': PATH plus the
new layers, the default; 'new': only the new layers, with PATH's windows, camera and colour
attributes; PATH's other channels are not decoded; 'append': PATH's parts copied as compressed
chunks, untouched, plus a part holding the new layers).
method='ssdo': samples (1-4096), interleave (1-8), bounce (bool, above), bounce_source
('direct-diffuse' | 'beauty' | layer), env (lat-long map path), env_rotate (degrees),
env_intensity, env_colorspace, colorspace (of the input's colour passes), sky ((r, g, b) without
env), lights (up to 4 ((x, y, z), (r, g, b)): world direction towards the light, irradiance), up
('y' | 'z'; default z for Blender renders), times_albedo (bool: DO and GI as albedo x E / pi),
relit_direct (bool).
A keyword the method does not read (obscura.METHODS[m]['params'] and ['options'] list those it
does) or an output it cannot write raises ValueError naming the methods that do. So does out,
report or preview naming a file the call reads (PATH, its sidecar, camera, env, the OpenColorIO
config) or one another, compared by identity through links; only in_place=True lets out be PATH.
Outputs are written atomically; on obscura.Error nothing is left behind.)doc");

    m.def(
        "inspect",
        [](const py::object& path, const py::args& extra, py::object preset, py::object layer, py::object camera,
           py::object fovDeg, py::object orthoWidth, py::object c2w, py::object depth, py::object normals,
           py::object skyDepth, py::object maxPixels, py::object device, const py::kwargs& unknown) {
            checkFileCall("inspect", extra, unknown, path);
            return inspectPy(path, FileArgs{preset, layer, camera, fovDeg, orthoWidth, c2w, depth, normals, skyDepth,
                                            maxPixels},
                             device);
        },
        py::arg("path") = py::none(), OBSCURA_FILE_ARGS, py::arg("device") = py::none(),
        R"doc(obscura PATH --inspect --json, as a dict: what obscura finds in the file, writing nothing.

'file'; 'parts' and 'multipart'; 'display_window', 'data_window' (x0, y0, x1, y1) half-open;
'layers' [{'name', 'part', 'part_name', 'channels', 'type'}]; 'preset'; 'roles' {role: [channel
names] or None}; 'conventions' {'depth', 'normals', 'normals_left_handed', 'sky_depth'}; 'deep'
(None without deep input); 'camera' {'projection', 'fx', 'fy', 'cx', 'cy', 'source',
'horizontal_fov_deg' or 'ortho_width', 'camera_to_world' (4 rows or None), 'fit_residual_px'
when fitted} or None, then 'camera_error' says why; 'write' (how process() would write);
'device' (or None and 'device_error'). Keywords as read_passes(), and device.)doc");

    m.def(
        "read_layer",
        [](const py::object& path, const py::object& name, const py::args& extra, const py::object& maxPixels,
           const py::kwargs& unknown) {
            checkPositional("read_layer", extra, {"path", "name"}, "max_pixels=...");
            checkNoKeywords("read_layer", unknown);
            required("read_layer", path, "path", "the EXR's path");
            required("read_layer", name, "name", "a channel ('obscura.AO.Y') or a layer ('ViewLayer.Normal')");
            return readLayerPy(path, name, maxPixels);
        },
        py::arg("path") = py::none(), py::arg("name") = py::none(), py::arg("max_pixels") = py::none(),
          R"doc(One channel ('obscura.AO.Y') as float32 (H, W), or a layer ('ViewLayer.Normal') as float32
(H, W, C) with its channels in R, G, B, A / X, Y, Z order, over its part's data window.
max_pixels as process(). Raises obscura.Error when the file or the name is missing.)doc");

    py::dict quality;
    for (const QualityPreset& q : qualityPresets())
        quality[py::str(q.name)] = py::dict("directions"_a = q.directions, "steps"_a = q.steps, "blur"_a = q.blur);
    m.attr("QUALITY_PRESETS") = quality;
    // The method table (core/methods.h): what each method reads and writes, where it runs, its
    // own keywords with their ranges, and the other keywords only some methods read.
    py::dict table;
    for (const MethodInfo& mi : methods()) {
        py::dict params;
        for (const MethodParam* mp : paramsOf(mi.name))
            params[py::str(mp->key)] = mp->boolField ? py::object(py::str("bool")) : py::object(py::make_tuple(mp->min, mp->max));
        py::list devices;
        if (mi.cpu) devices.append("cpu");
        if (mi.gl) devices.append("gl");
        py::list options;  // keywords beyond its params that it reads (core/methods.h's MethodOption)
        for (const MethodOption& o : methodOptions())
            if (settingRefusal(mi.name, o.key, Spelling::Key).empty()) options.append(o.key);
        table[py::str(mi.name)] = py::dict("description"_a = mi.description, "devices"_a = devices, "options"_a = options,
                                           "reads"_a = py::cast(std::vector<std::string>(mi.reads.begin(), mi.reads.end())),
                                           "outputs"_a = py::cast(std::vector<std::string>(mi.outputs.begin(), mi.outputs.end())),
                                           "params"_a = params);
    }
    m.attr("METHODS") = table;
    // The shared numeric settings (core/settings_schema.h): every host's one range.
    py::dict numbers;
    for (const NumberSetting& n : numberSettings())
        numbers[py::str(n.key)] = py::dict("min"_a = n.min, "max"_a = n.max, "min_excluded"_a = n.minExcluded,
                                           "integer"_a = n.integer, "flag"_a = n.flag);
    m.attr("NUMBER_SETTINGS") = numbers;
    m.attr("PRESETS") = py::tuple(py::cast(presetNames()));
}
