// Settings: the CLI's flags as keyword arguments, turned into core's Settings. `quality` is
// applied first; explicit directions/steps/blur then override it, as later flags do on the
// command line. Every range, device name and method rule comes from plugin/core
// (settings_schema.h, devices.h, methods.h).
#pragma once
#include "core/settings.h"

#include <pybind11/pybind11.h>

#include <string>

namespace obscura::python {

namespace py = pybind11;

struct SettingArgs {
    py::object quality, method, radius, directions, steps, weighting, falloff, blur, device, threads;
    py::dict own;  // the remaining keywords: the methods' own parameters (core/methods.h), by key
};

// A keyword the method would ignore is refused from the method table (core/methods.h), as the
// CLI refuses the flag. False and None are the defaults: passing them asks for nothing.
void refuseIgnored(const std::string& method, const std::string& key, const py::handle& value);

// `method`, when given, is the method the call runs whatever sa.method says (compute_ssdo).
Settings settingsFrom(const SettingArgs& a, const char* method = nullptr);

// SSDO's operator settings (method 'ssdo'): --samples, --interleave, --sky, --env-rotate,
// --env-intensity, --light. Checked here so a bad value is a ValueError, not obscura.Error.
struct SsdoArgs {
    py::object samples, interleave, sky, envRotate, envIntensity, lights;
};

void applySsdo(const SsdoArgs& a, Settings& s);

} // namespace obscura::python

// The keywords of SettingArgs and SsdoArgs, in that order, each defaulting to None.
#define OBSCURA_SSDO_ARGS                                                                                            \
    py::arg("samples") = py::none(), py::arg("interleave") = py::none(), py::arg("sky") = py::none(),               \
        py::arg("env_rotate") = py::none(), py::arg("env_intensity") = py::none(), py::arg("lights") = py::none()

#define OBSCURA_SETTING_ARGS                                                                                         \
    py::arg("quality") = py::none(), py::arg("method") = py::none(), py::arg("radius") = py::none(),                \
        py::arg("directions") = py::none(), py::arg("steps") = py::none(), py::arg("weighting") = py::none(),       \
        py::arg("falloff") = py::none(), py::arg("blur") = py::none(), py::arg("device") = py::none(),              \
        py::arg("threads") = py::none()
