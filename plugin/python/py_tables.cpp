// The module's tables, read from plugin/core and plugin/io, never kept here: QUALITY_PRESETS
// (core/settings.h), METHODS (core/methods.h), NUMBER_SETTINGS (core/settings_schema.h) and
// PRESETS (io/layers.h).
#include "core/methods.h"
#include "core/settings.h"
#include "core/settings_schema.h"
#include "io/layers.h"
#include "python/py_bind.h"

#include <pybind11/stl.h>

#include <string>
#include <vector>

namespace obscura::python {

using namespace py::literals;

namespace {

py::dict qualityTable() {
    py::dict quality;
    for (const QualityPreset& q : qualityPresets())
        quality[py::str(q.name)] = py::dict("directions"_a = q.directions, "steps"_a = q.steps, "blur"_a = q.blur);
    return quality;
}

// The method table (core/methods.h): what each method reads and writes, where it runs, its
// own keywords with their ranges, and the other keywords only some methods read.
py::dict methodTable() {
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
    return table;
}

// The shared numeric settings (core/settings_schema.h): every host's one range.
py::dict numberTable() {
    py::dict numbers;
    for (const NumberSetting& n : numberSettings())
        numbers[py::str(n.key)] = py::dict("min"_a = n.min, "max"_a = n.max, "min_excluded"_a = n.minExcluded,
                                           "integer"_a = n.integer, "flag"_a = n.flag, "count"_a = n.count);
    return numbers;
}

} // namespace

void bindTables(py::module_& m) {
    m.attr("QUALITY_PRESETS") = qualityTable();
    m.attr("METHODS") = methodTable();
    m.attr("NUMBER_SETTINGS") = numberTable();
    m.attr("PRESETS") = py::tuple(py::cast(presetNames()));
}

} // namespace obscura::python
