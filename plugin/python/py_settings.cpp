#include "python/py_settings.h"

#include "core/devices.h"
#include "core/methods.h"
#include "core/settings_schema.h"
#include "python/py_args.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

namespace obscura::python {

namespace {

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
            s.*(p->boolField) = boolArg(value, p->key);
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

// lights=: up to 4 ((x, y, z), (r, g, b)), a world direction towards the light and its
// irradiance, as --light.
std::vector<Settings::DirectionalLight> lightsArg(const py::object& lights) {
    if (!py::isinstance<py::sequence>(lights) || py::isinstance<py::str>(lights))
        valueError("lights must be a list of ((x, y, z), (r, g, b)), got " + typeName(lights));
    py::sequence seq = py::reinterpret_borrow<py::sequence>(lights);
    if (py::len(seq) > 4) valueError("lights: at most 4 directional lights, got " + std::to_string(py::len(seq)));
    std::vector<Settings::DirectionalLight> out;
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
        out.push_back(l);
    }
    return out;
}

} // namespace

void refuseIgnored(const std::string& method, const std::string& key, const py::handle& value) {
    if (value.is_none() || (py::isinstance<py::bool_>(value) && !value.cast<bool>())) return;
    const std::string problem = settingRefusal(method, key, Spelling::Key);
    if (!problem.empty()) valueError(problem);
}

Settings settingsFrom(const SettingArgs& a, const char* method) {
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
    if (!a.lights.is_none()) s.lights = lightsArg(a.lights);
}

} // namespace obscura::python
