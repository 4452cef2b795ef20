// The Python host: a pybind11 module over the same operator (plugin/core) and frame
// job (plugin/io) as the CLI. numpy arrays are viewed in place (strided planes), never
// converted; the GIL is released while pixels are read, computed or written.
//
// The parts, one file each (py_bind.h): py_camera.cpp (obscura.Camera), py_arrays.cpp
// (compute_ao, compute_gi, compute_ssdo, ao_from_passes), py_files.cpp (read_passes, process, inspect,
// read_layer), py_deep.cpp (read_deep), py_tables.cpp (METHODS and the other tables); the keywords they take are
// converted by py_args.h (one argument), py_settings.h (Settings), py_job.h (FrameJob) and
// call_args.h (the call as a whole).
#include "base/cancel.h"
#include "base/error.h"
#include "python/py_bind.h"
#include "python/py_spelling.h"

#include <pybind11/pybind11.h>

#include <exception>

namespace py = pybind11;

namespace obscura::python {

namespace {

const char* kModuleDoc = R"doc(obscura: screen-space ambient occlusion (HBAO) and directional occlusion with one
bounce (SSDO) for renders that already exist.

The same operator and file pipeline as the ``obscura`` command, for numpy:

- ``compute_ao(depth, normal, camera=..., **settings)`` -> float32 (H, W) AO from arrays
  (viewed in place, never converted: float32, shape (H, W) and (H, W, 3)).
- ``compute_gi(depth, normal, camera=..., radiance=, albedo=, deep=, deep_colour=, **settings)`` -> dict
  of 'gi' (H, W, 3) and 'ao' (H, W): HBAO's one bounce of radiance, from arrays.
- ``compute_ssdo(depth, normal, camera=..., radiance=, albedo=, environment=, bounce=, ...)``
  -> dict of 'do' (H, W, 3), 'gi' (H, W, 3) or None, 'ao' (H, W), from arrays.
- ``read_passes(path)`` -> dict of the depth/normal/position planes, camera and conventions
  of a multilayer EXR, found by renderer preset as the CLI does.
- ``ao_from_passes(passes, **settings)`` -> compute_ao over a read_passes() dict.
- ``process(path, out, **settings)`` -> the CLI's ``--report`` JSON as a dict; writes OUT.
- ``inspect(path)`` -> dict, the CLI's ``--inspect --json``; ``read_layer(path, name)`` -> an EXR layer.
- ``read_deep(path, colour=)`` -> dict of a deep EXR's surfaces ('deep' (H, W, 2L), 'colour'), for
  compute_ao(deep=) and compute_gi(deep=, deep_colour=).
- ``Camera.perspective / .orthographic / .from_sidecar``.
- ``obscura.farm``: frames x settings variants as farm work on a Dask cluster (``run_dask``),
  skipping the outputs a run with the same settings completed (resume).

Settings are the CLI's flags with underscores: radius, directions, steps, weighting
('uniform' | 'cosine'), falloff ('linear' | 'none'), blur, quality ('low' | 'medium' |
'high' | 'ultra', applied before the keywords, which win over it), method (a key of
obscura.METHODS: 'hbao', 'ssdo', 'ssao', 'rtao', 'discs'), device, threads; each method's own
keywords as METHODS lists them (thickness, border, deep_layers, ssao_samples, ssao_hemisphere,
rtao_rays, rtao_grid, disc_window, ...); for 'ssdo' also samples, interleave, sky, env_rotate,
env_intensity, lights, up. help(obscura.process) lists the file keywords.

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
obscura.Error, a RuntimeError whose message is the CLI's one-line error, the flags it names spelled as
keywords (--depth-range NEAR,FAR as depth_range=(NEAR, FAR)).
The GIL is released while files are read or written and while the AO is computed.)doc";

const char* kErrorDoc =
    "A failure reported by obscura's file pipeline or operator (missing, unreadable or corrupt file, no "
    "camera, bad pixels, unwritable output). Subclass of RuntimeError; str(e) is one line naming the file "
    "and the problem, as the CLI prints it, with the flags it names spelled as keywords.";

} // namespace
} // namespace obscura::python

PYBIND11_MODULE(_obscura, m) {
    using namespace obscura;
    using namespace obscura::python;
    m.doc() = kModuleDoc;
    m.attr("__version__") = OBSCURA_VERSION_STRING;
    // The messages name the CLI's flags; a Python caller reads them as keywords. A request that
    // cannot be carried out as asked (two roles naming one file) is the caller's ValueError,
    // like a bad keyword.
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Cancelled&) {
            if (!PyErr_Occurred()) PyErr_SetNone(PyExc_KeyboardInterrupt);  // else the handler's own error
        } catch (const UsageError& e) {
            PyErr_SetString(PyExc_ValueError, keywordSpelling(e.what()).c_str());
        } catch (const Error& e) {
            error(keywordSpelling(e.what()).c_str());
        }
    });
    m.attr("Error").attr("__doc__") = kErrorDoc;

    bindCamera(m);
    bindArrays(m);
    bindFiles(m);
    bindDeep(m);
    bindTables(m);
}
