// File-level jobs: a FrameJob (io/frame_job.h) built from keyword arguments named like the
// CLI's flags, for read_passes, process and inspect (py_files.cpp).
#pragma once
#include "io/frame_job.h"
#include "python/py_settings.h"

#include <pybind11/pybind11.h>

namespace obscura::python {

namespace py = pybind11;

// The keywords that find and read the passes (OBSCURA_FILE_ARGS, in this order).
struct FileArgs {
    py::object preset, layer, camera, fovDeg, focalMm, apertureMm, orthoWidth, cameraToWorld,
        depth, depthRange, normals, skyDepth, maxPixels, view;
};

// max_pixels=, as --max-pixels: a window above it is refused before anything is allocated.
long long maxPixelsArg(const py::object& obj);

FrameJob jobFrom(const py::object& path, const FileArgs& f);

// process()'s keywords for what it writes and where.
struct OutputArgs {
    py::object outLayer, outType, badPixels, reference, report, preview, inPlace, write, previewExposure;
    py::object perElementAo;  // deep elements (docs/deep.md)
};

// process()'s SSDO keywords beyond the operator's: what to write and where the light comes from.
struct JobSsdoArgs {
    py::object bounce, bounceSource, env, envColorspace, colorspace, up, timesAlbedo, relitDirect;
};

// The job process(path, out, ...) runs; a list of paths is deep elements, merged (docs/deep.md): every keyword checked, as the CLI checks its flags
// (o.report is left to the caller).
FrameJob processJob(const py::object& path, const py::object& out, const FileArgs& f, const SettingArgs& sa,
                    const OutputArgs& o, const SsdoArgs& ssdoArgs, const JobSsdoArgs& js);

} // namespace obscura::python

// The lambda parameters OBSCURA_FILE_ARGS binds, in its order, and the FileArgs made of them: a
// keyword that finds or reads the passes is added here, in FileArgs and in OBSCURA_FILE_ARGS.
#define OBSCURA_FILE_PARAMS                                                                                       \
    py::object preset, py::object layer, py::object camera, py::object fovDeg, py::object focalMm,              \
        py::object apertureMm, py::object orthoWidth, py::object c2w, py::object depth, py::object depthRange,  \
        py::object normals, py::object skyDepth, py::object maxPixels, py::object view
#define OBSCURA_FILE_ARGS_MADE                                                                                    \
    FileArgs { preset, layer, camera, fovDeg, focalMm, apertureMm, orthoWidth, c2w, depth, depthRange, normals, \
               skyDepth, maxPixels, view }

#define OBSCURA_FILE_ARGS                                                                                           \
    py::arg("preset") = py::none(), py::arg("layer") = py::none(), py::arg("camera") = py::none(),                 \
        py::arg("fov_deg") = py::none(), py::arg("focal_mm") = py::none(), py::arg("aperture_mm") = py::none(),   \
        py::arg("ortho_width") = py::none(),                                                                       \
        py::arg("camera_to_world") = py::none(), py::arg("depth") = py::none(), py::arg("depth_range") = py::none(), \
        py::arg("normals") = py::none(),                                                                           \
        py::arg("sky_depth") = py::none(), py::arg("max_pixels") = py::none(), py::arg("view") = py::none()
