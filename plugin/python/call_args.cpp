#include "call_args.h"

#include <string>

namespace obscura::python {

void checkPositional(const char* function, const py::args& extra, std::initializer_list<const char*> positional,
                     const char* hint) {
    if (extra.empty()) return;
    std::string names;
    for (const char* n : positional) names += (names.empty() ? "" : ", ") + std::string(n);
    const size_t n = positional.size();
    throw py::type_error(std::string(function) + "() takes " + std::to_string(n) + " positional argument" +
                         (n == 1 ? "" : "s") + " (" + names + ") but " +
                         std::to_string(n + extra.size()) + " were given; pass the rest by keyword (" +
                         hint + ")");
}

void checkNoKeywords(const char* function, const py::kwargs& unknown) {
    for (const auto& item : unknown)
        throw py::type_error(std::string(function) + "() got an unexpected keyword argument '" +
                             std::string(py::str(item.first)) + "'");
}

void required(const char* function, const py::object& value, const char* name, const char* what) {
    if (value.is_none())
        throw py::type_error(std::string(function) + "() needs " + name + ": " + what);
}

void checkArrayCall(const char* function, const py::args& extra, const py::object& depth, const py::object& normal,
                    const py::object& camera, const py::object& normals) {
    checkPositional(function, extra, {"depth", "normal"}, "camera=..., radius=...");
    required(function, depth, "depth", "a float32 numpy array (H, W) of camera depth");
    const bool fromDepth = py::isinstance<py::str>(normals) && normals.cast<std::string>() == "depth";
    if (!fromDepth)
        required(function, normal, "normal", "a float32 numpy array (H, W, 3) of normals, or normals='depth'");
    required(function, camera, "camera=",
             "an obscura.Camera (Camera.perspective(fov_deg, width, height, camera_to_world=m), "
             "Camera.from_sidecar(path, width, height) or read_passes(path)['camera'])");
}

void checkFileCall(const char* function, const py::args& extra, const py::kwargs& unknown, const py::object& path) {
    checkPositional(function, extra, {"path"}, "preset=..., camera=...");
    checkNoKeywords(function, unknown);
    required(function, path, "path", "the EXR's path");
}

py::dict passesArg(const py::args& extra, const py::object& passes) {
    checkPositional("ao_from_passes", extra, {"passes"}, "radius=..., quality=...");
    required("ao_from_passes", passes, "passes", "the dict obscura.read_passes(path) returns");
    if (!py::isinstance<py::dict>(passes))
        throw py::type_error("ao_from_passes() passes must be the dict obscura.read_passes(path) returns, got " +
                             std::string(py::str(py::type::handle_of(passes).attr("__name__"))));
    return py::reinterpret_borrow<py::dict>(passes);
}

} // namespace obscura::python
