// compute_ao, compute_gi, compute_ssdo and ao_from_passes: the operator (core/operator.h) over numpy
// arrays, viewed in place; the GIL is released while it runs.
#include "base/error.h"
#include "core/methods.h"
#include "core/operator.h"
#include "python/call_args.h"
#include "python/py_args.h"
#include "python/py_spelling.h"
#include "python/py_bind.h"
#include "python/py_interrupt.h"
#include "python/py_settings.h"

#include <algorithm>
#include <string>
#include <utility>

namespace obscura::python {

namespace {

// The operator on in-memory passes, called with the GIL held: released while it runs (the
// arrays `in` views stay referenced by the caller's frame), stopped by Ctrl-C, and what it noted
// (a device that fell back, a source's NaN pixels) raised as RuntimeWarnings, since the arrays'
// functions return arrays, not a report.
OperatorOutputs runOnArrays(const OperatorInputs& in, const Settings& settings) {
    OperatorOutputs out;
    const CtrlCStops interrupt;
    {
        py::gil_scoped_release release;
        out = runOperator(in, settings);
    }
    for (const std::string& note : out.stats.notes)
        if (PyErr_WarnEx(PyExc_RuntimeWarning, keywordSpelling(note).c_str(), 1) != 0) throw py::error_already_set();
    return out;
}

const char* kComputeAoDoc = R"doc(Ambient occlusion of in-memory passes: a float32 array (H, W), 1 = unoccluded.

depth: float32 (H, W), planar camera depth (or distance to the eye with depth_kind='radial').
normal: float32 (H, W, 3), world space (normals='world', needs camera.camera_to_world) or
OpenGL camera space (normals='camera'); with normals='depth' it is not needed (nor read): the
normals are reconstructed from the depth and the camera.
Both are read in place, without a copy, whatever their strides (slices, transposes, broadcasts),
as long as strides are whole float32 elements and a normal's 3 components are adjacent.
Anything else raises ValueError (no silent conversion: use .astype(numpy.float32) or
numpy.ascontiguousarray). Pixels with depth 0, inf, >= sky_depth, NaN or negative are
background (AO = 1).
deep (hbao): float32 (H, W, 2K), the surfaces along each pixel's ray as (front, back) depths,
nearest first, the visible one first; front inf past a ray's last; back == front where the
span is unknown (docs/deep.md). deep_layers=K caps how many are used.

camera: obscura.Camera, required. data_window: (x0, y0, x1, y1) the arrays cover in display-window
pixels (default: W x H from display_window's corner; larger than the display window for overscan). display_window:
the frame's (x0, y0, x1, y1), default (0, 0, W, H). Both may be an EXR header's absolute windows:
the camera's pixels count from display_window's corner.
Settings (defaults as the CLI): radius=1.0 world units, directions=8, steps=8,
weighting='uniform'|'cosine', falloff='linear'|'none', blur=1 px (the 'medium' preset's), quality=None ('low',
'medium', 'high', 'ultra'; explicit directions/steps/blur override it), method='hbao'
(or 'ssao', 'rtao', with their own keywords: ssao_samples=16, ssao_hemisphere=False,
rtao_rays=16, rtao_grid=1), thickness='auto' (hbao and rtao: world units, 'auto' or 'inf'),
device='cpu', threads=0 (all cores). The GIL is released while computing.)doc";

const char* kComputeSsdoDoc = R"doc(Screen-space directional occlusion (method 'ssdo') of in-memory passes, as a dict:
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
(up to 4 ((x, y, z), (r, g, b))), device, threads. The GIL is released while computing.)doc";

const char* kComputeGiDoc = R"doc(One bounce of indirect light from HBAO's march (as --method hbao --bounce) of in-memory
passes, as a dict: 'gi' float32 (H, W, 3) irradiance E from the surfaces within radius, 'ao' float32
(H, W) the AO of the same run.

depth, normal, camera and the settings: as compute_ao (method='hbao', its default, is the one
method whose bounce has no DO; for SSDO's use compute_ssdo(bounce=True)). radiance: float32
(H, W, 3), the light leaving each pixel's surface (the bounce source), required; albedo: float32
(H, W, 3), optional, multiplies radiance (give both for the CLI's default bounce source,
direct-diffuse x albedo). Both viewed in place, in the working colour space. deep: float32
(H, W, 2K), hbao's hidden surfaces as compute_ao takes them; deep_colour: float32 (H, W, 3K), the
un-premultiplied RGB each of those surfaces radiates (read_deep(path, colour=True)['colour']; the
visible surface's, the first, is radiance's); without it the hidden surfaces hide but send
nothing (docs/deep.md). The GIL is released while computing.)doc";

const char* kAoFromPassesDoc = R"doc(compute_ao over a read_passes() dict, with its camera, conventions (normals, depth_kind,
sky_depth) and windows: the same AO that process() writes for that file and these settings.
Raises obscura.Error when the passes have no camera (see passes['camera_error']).)doc";

struct ViewArgs {
    py::object camera, normals, depthKind, skyDepth, dataWindow, displayWindow;
};

// A plane given beside depth must cover the same pixels.
void sameSizeAsDepth(const ConstPlane& p, const char* what, const ConstPlane& depth) {
    if (p.width != depth.width || p.height != depth.height)
        valueError(std::string(what) + " covers " + std::to_string(p.height) + "x" + std::to_string(p.width) +
                   " pixels (H x W) but depth covers " + std::to_string(depth.height) + "x" +
                   std::to_string(depth.width) + "; they must be the same size");
}

// The inputs and settings compute_ao, compute_gi and compute_ssdo share: planes viewed in place, checked.
OperatorInputs viewInputs(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v,
                          Settings& settings) {
    OperatorInputs in;
    in.depth = planeArg(depthObj, "depth", 1);
    if (!v.normals.is_none()) in.normalSpace = enumArg<NormalSpace>(v.normals, "normals", "'world', 'camera' or 'depth'");
    // normals='depth': reconstructed from the depth; a normal array, if given, is not read.
    if (in.normalSpace != NormalSpace::Depth) in.normal = planeArg(normalObj, "normal", 3);
    if (in.normal.valid()) sameSizeAsDepth(in.normal, "normal", in.depth);
    const Box2i full{0, 0, in.depth.width, in.depth.height};
    in.displayWindow = v.displayWindow.is_none() ? full : boxArg(v.displayWindow, "display_window");
    // Windows as an EXR header gives them: the camera's pixels count from the display window's
    // corner, so both move by its origin (data inside display at (10, 10) is data at (0, 0)).
    const int ox = in.displayWindow.x0, oy = in.displayWindow.y0;
    in.dataWindow = v.dataWindow.is_none() ? Box2i{ox, oy, ox + in.depth.width, oy + in.depth.height}
                                           : boxArg(v.dataWindow, "data_window");
    if (in.dataWindow.width() != in.depth.width || in.dataWindow.height() != in.depth.height)
        valueError("data_window is " + std::to_string(in.dataWindow.width()) + "x" +
                   std::to_string(in.dataWindow.height()) + " (W x H) but the arrays are " +
                   std::to_string(in.depth.width) + "x" + std::to_string(in.depth.height));
    in.dataWindow = Box2i{in.dataWindow.x0 - ox, in.dataWindow.y0 - oy, in.dataWindow.x1 - ox, in.dataWindow.y1 - oy};
    in.displayWindow = Box2i{0, 0, in.displayWindow.width(), in.displayWindow.height()};
    if (!v.depthKind.is_none()) in.depthKind = enumArg<DepthKind>(v.depthKind, "depth_kind", "'planar' or 'radial'");
    if (!v.skyDepth.is_none()) settings.skyDepth = (float)numberArg(v.skyDepth, "sky_depth");
    in.camera = cameraArg(v.camera);
    if (!in.camera.valid()) valueError("the camera has no valid projection (focal length or orthographic width)");
    const int w = in.displayWindow.width(), h = in.displayWindow.height();
    if (in.camera.displayWidth > 0 && (in.camera.displayWidth != w || in.camera.displayHeight != h))
        valueError("the camera was made for a " + std::to_string(in.camera.displayWidth) + "x" +
                   std::to_string(in.camera.displayHeight) + " display window but the display window is " +
                   std::to_string(w) + "x" + std::to_string(h) +
                   " (W x H): make the Camera with the frame's size, or pass display_window=");
    if (in.normalSpace == NormalSpace::World && !in.camera.hasPose)
        valueError("normals='world' needs the camera's pose: give the Camera a camera_to_world matrix, "
                   "or pass camera-space normals with normals='camera'");
    return in;
}

// A per-layer plane, float32 (H, W, perLayer K), over depth's pixels: deep= (perLayer 2, (front, back)
// depth pairs, docs/deep.md) and deep_colour= (3, RGB); `most` caps K (0: no cap).
ConstPlane layeredArg(const py::object& obj, const char* what, int perLayer, const char* unit, int most,
                      const OperatorInputs& in) {
    const std::string name = what;
    if (!py::isinstance<py::array>(obj)) throw py::type_error(name + " must be a numpy.ndarray of float32, got " + typeName(obj));
    const py::array a = py::reinterpret_borrow<py::array>(obj);
    const int channels = a.ndim() == 3 ? (int)a.shape(2) : 0;
    const std::string k = std::to_string(perLayer) + "K";
    if (channels < perLayer || channels % perLayer != 0 || (most > 0 && channels > perLayer * most))
        valueError(name + " must have shape (H, W, " + k + "): K " + unit + " per pixel" +
                   (most > 0 ? ", K at most deep's " + std::to_string(most) : std::string()) + ", got " +
                   std::to_string(a.ndim()) + " dimension(s)" +
                   (a.ndim() == 3 ? " of " + std::to_string(channels) + " channels" : ""));
    const ConstPlane p = planeArg(obj, what, channels);
    if (p.width != in.depth.width || p.height != in.depth.height) valueError(name + " must cover the same pixels as depth");
    return p;
}

ConstPlane deepArg(const py::object& obj, const OperatorInputs& in) {
    return layeredArg(obj, "deep", 2, "(front, back) depth pairs", 0, in);
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
    return imageToArray(runOnArrays(in, settings).ao, true);
}

// compute_ssdo: DO (and GI) irradiance and AO of in-memory passes, lit by a lat-long array or
// a constant sky, plus directional lights.
struct SsdoArrayArgs {
    py::object radiance, albedo, environment, bounce, up;
};

// An RGB plane copied into an owned image.
Image ownedRgb(const ConstPlane& p) {
    Image image(p.width, p.height, 3);
    for (int y = 0; y < p.height; ++y)
        for (int x = 0; x < p.width; ++x) {
            const float* src = p.data + y * p.yStride + x * p.xStride;
            std::copy(src, src + 3, image.at(x, y));
        }
    return image;
}

// radiance= and albedo=, the bounce source, viewed in place.
void bounceSource(const py::object& radiance, const py::object& albedo, OperatorInputs& in) {
    if (!radiance.is_none()) {
        in.radiance = planeArg(radiance, "radiance", 3);
        sameSizeAsDepth(in.radiance, "radiance", in.depth);
    }
    if (!albedo.is_none()) {
        in.albedo = planeArg(albedo, "albedo", 3);
        sameSizeAsDepth(in.albedo, "albedo", in.depth);
    }
}

py::dict computeSsdo(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v,
                     const SettingArgs& sa, const SsdoArgs& ssdoArgs, const SsdoArrayArgs& x) {
    Settings settings = settingsFrom(sa, "ssdo");
    applySsdo(ssdoArgs, settings);
    settings.bounce = !x.bounce.is_none() && boolArg(x.bounce, "bounce");
    if (!x.up.is_none()) settings.zUp = upArg(x.up);
    OperatorInputs in = viewInputs(depthObj, normalObj, v, settings);
    bounceSource(x.radiance, x.albedo, in);
    if (settings.bounce && !in.radiance.valid())
        valueError("bounce=True needs radiance: the light leaving the bouncing surfaces, float32 (H, W, 3) "
                   "(e.g. the direct-diffuse pass, with albedo=the albedo pass)");
    ConstPlane env;
    if (!x.environment.is_none()) env = planeArg(x.environment, "environment", 3);

    Image environment;
    if (env.valid()) {  // the prefilter wants an owned image: one copy of the (small) map
        environment = ownedRgb(env);
        in.environment = &environment;
    }
    OperatorOutputs out = runOnArrays(in, settings);
    py::dict d;
    d["do"] = imageToArray(std::move(out.directional), false);
    d["gi"] = out.indirect.empty() ? py::object(py::none()) : py::object(imageToArray(std::move(out.indirect), false));
    d["ao"] = imageToArray(std::move(out.ao), true);
    return d;
}

// compute_gi's deep= and deep_colour=: hbao's hidden layers and the colour each radiates.
struct DeepArrayArgs {
    py::object deep, colour;
};

// compute_gi: a method whose bounce has no DO (hbao's horizon light), its GI and AO.
py::dict computeGi(const py::object& depthObj, const py::object& normalObj, const ViewArgs& v, const SettingArgs& sa,
                   const py::object& radiance, const py::object& albedo, const DeepArrayArgs& deep) {
    Settings settings = settingsFrom(sa);
    if (!methodOutputs(settings.method, "gi") || methodOutputs(settings.method, "do"))
        valueError("compute_gi computes the bounce of a method without DO (method='hbao'); method='" +
                   settings.method + "' " +
                   (methodOutputs(settings.method, "do") ? "is SSDO's: use compute_ssdo(bounce=True)" : "has no bounce"));
    settings.bounce = true;
    OperatorInputs in = viewInputs(depthObj, normalObj, v, settings);
    bounceSource(radiance, albedo, in);
    if (!in.radiance.valid())
        valueError("compute_gi needs radiance: the light leaving the bouncing surfaces, float32 (H, W, 3) "
                   "(e.g. the direct-diffuse pass, with albedo=the albedo pass)");
    if (!deep.deep.is_none()) in.deepLayers = deepArg(deep.deep, in);
    if (!deep.colour.is_none()) {
        if (deep.deep.is_none()) valueError("deep_colour needs deep=: the surfaces it colours");
        in.deepColour = layeredArg(deep.colour, "deep_colour", 3, "RGB colours", in.deepLayers.channels / 2, in);
    }
    OperatorOutputs out = runOnArrays(in, settings);
    py::dict d;
    d["gi"] = imageToArray(std::move(out.indirect), false);
    d["ao"] = imageToArray(std::move(out.ao), true);
    return d;
}

// ao_from_passes: compute_ao over a read_passes() dict, its camera and conventions included.
py::array aoFromPasses(const py::dict& passes, const SettingArgs& sa) {
    for (const char* key : {"depth", "normal", "camera"})
        if (!passes.contains(key)) valueError(std::string("passes has no '") + key + "' (use read_passes())");
    py::object camera = passes["camera"];
    if (camera.is_none()) {
        const py::object why =
            passes.contains("camera_error") ? py::object(passes["camera_error"]) : py::object(py::none());
        throw Error(why.is_none() ? std::string("the passes have no camera") : why.cast<std::string>());
    }
    auto get = [&](const char* key) -> py::object {
        return passes.contains(key) ? py::object(passes[key]) : py::object(py::none());
    };
    return computeAo(passes["depth"], passes["normal"],
                     ViewArgs{camera, get("normals"), get("depth_kind"), get("sky_depth"), get("data_window"),
                              get("display_window")},
                     sa, py::none());
}

// compute_ao's and compute_gi's shared parameters: the lambda's, the keywords declaring them (in the
// same order) and the argument structs made of them.
#define OBSCURA_ARRAY_PARAMS                                                                                       \
    const py::object &depth, const py::object &normal, const py::args &extra, py::object camera, py::object normals, \
        py::object depthKind, py::object skyDepth, py::object dataWindow, py::object displayWindow,                 \
        py::object quality, py::object method, py::object radius, py::object directions, py::object steps,          \
        py::object weighting, py::object falloff, py::object blur, py::object device, py::object threads
#define OBSCURA_ARRAY_ARGS                                                                                         \
    py::arg("depth") = py::none(), py::arg("normal") = py::none(), py::arg("camera") = py::none(),                \
        py::arg("normals") = "world", py::arg("depth_kind") = "planar", py::arg("sky_depth") = 1e9,                 \
        py::arg("data_window") = py::none(), py::arg("display_window") = py::none(), OBSCURA_SETTING_ARGS
#define OBSCURA_ARRAY_VIEW ViewArgs{camera, normals, depthKind, skyDepth, dataWindow, displayWindow}
#define OBSCURA_ARRAY_SETTINGS                                                                                     \
    SettingArgs { quality, method, radius, directions, steps, weighting, falloff, blur, device, threads, own }

void bindComputeAo(py::module_& m) {
    m.def(
        "compute_ao",
        [](OBSCURA_ARRAY_PARAMS, py::object deep, const py::kwargs& own) {
            checkArrayCall("compute_ao", extra, depth, normal, camera, normals);
            return computeAo(depth, normal, OBSCURA_ARRAY_VIEW, OBSCURA_ARRAY_SETTINGS, deep);
        },
        OBSCURA_ARRAY_ARGS, py::arg("deep") = py::none(), kComputeAoDoc);
}

void bindComputeGi(py::module_& m) {
    m.def(
        "compute_gi",
        [](OBSCURA_ARRAY_PARAMS, py::object radiance, py::object albedo, py::object deep, py::object deepColour,
           const py::kwargs& own) {
            checkArrayCall("compute_gi", extra, depth, normal, camera, normals);
            return computeGi(depth, normal, OBSCURA_ARRAY_VIEW, OBSCURA_ARRAY_SETTINGS, radiance, albedo,
                             DeepArrayArgs{deep, deepColour});
        },
        OBSCURA_ARRAY_ARGS, py::arg("radiance") = py::none(), py::arg("albedo") = py::none(),
        py::arg("deep") = py::none(), py::arg("deep_colour") = py::none(), kComputeGiDoc);
}

void bindComputeSsdo(py::module_& m) {
    m.def(
        "compute_ssdo",
        [](const py::object& depth, const py::object& normal, const py::args& extra, py::object camera,
           py::object radiance, py::object albedo, py::object environment, py::object bounce, py::object up,
           py::object normals, py::object depthKind, py::object skyDepth, py::object dataWindow,
           py::object displayWindow, py::object radius, py::object blur, py::object device, py::object threads,
           py::object samples, py::object interleave, py::object sky, py::object envRotate, py::object envIntensity,
           py::object lights, const py::kwargs& unknown) {
            checkArrayCall("compute_ssdo", extra, depth, normal, camera, normals);
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
        py::arg("threads") = py::none(), OBSCURA_SSDO_ARGS, kComputeSsdoDoc);
}

void bindAoFromPasses(py::module_& m) {
    m.def(
        "ao_from_passes",
        [](const py::object& passes, const py::args& extra, py::object quality, py::object method,
           py::object radius, py::object directions, py::object steps, py::object weighting, py::object falloff,
           py::object blur, py::object device, py::object threads, const py::kwargs& own) {
            return aoFromPasses(passesArg(extra, passes), SettingArgs{quality, method, radius, directions, steps,
                                                                      weighting, falloff, blur, device, threads, own});
        },
        py::arg("passes") = py::none(), OBSCURA_SETTING_ARGS, kAoFromPassesDoc);
}

} // namespace

void bindArrays(py::module_& m) {
    bindComputeAo(m);
    bindComputeGi(m);
    bindComputeSsdo(m);
    bindAoFromPasses(m);
}

} // namespace obscura::python
