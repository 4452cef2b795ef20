// read_passes, process, inspect and read_layer: the CLI's frame job (io/frame_job.h) and EXR
// reader (io/exr_file.h) from Python, with keywords named like the CLI's flags (py_job.h).
// The GIL is released while files are read or written.
#include "base/error.h"
#include "io/atomic_files.h"
#include "io/frame_job.h"
#include "io/inspect.h"
#include "io/layers.h"
#include "io/write_guard.h"
#include "python/call_args.h"
#include "python/py_args.h"
#include "python/py_bind.h"
#include "python/py_interrupt.h"
#include "python/py_job.h"
#include "python/py_spelling.h"

#include <pybind11/stl.h>

#include <algorithm>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace obscura::python {

namespace {

const char* kReadPassesDoc = R"doc(The passes of a multilayer EXR, found as the CLI finds them, as a dict:

'depth' float32 (H, W), decoded to planar (or radial) depth, sky +inf (from the position pass and
the camera when the file has no depth layer); 'normal' float32 (H, W, 3) (RenderMan's left-handed camera normals
already flipped to OpenGL's), None when the normals are to be reconstructed from the depth
(normals='depth', or the file has no normal layer); 'position' float32 (H, W, 3) when the file
has one; 'camera' obscura.Camera or None ('camera_error' then says why); 'normals'
'world'|'camera'|'depth';
'depth_kind' 'planar'|'radial' (of 'depth'); 'depth_encoding' 'planar'|'radial'|'inverse'|'normalized'
(how the file stores it); 'sky_depth'; 'data_window' and 'display_window'
(x0, y0, x1, y1), half-open, display min = (0, 0); 'pixel_aspect'; 'up' ('z' for Blender's
files, else 'y': the world's up axis process() lights them with; give it to compute_ssdo's up=);
'preset'; 'layers'
{role: [channel names]}; 'part'; 'view' (of a multi-view file, else None); 'path'. Arrays cover the
data window.

Keywords as process(): preset ('auto', 'blender', 'arnold', 'renderman', 'vray', 'karma',
'generic'), layer={role: name}, camera (sidecar path; default NAME.json next to the file),
fov_deg (or focal_mm with aperture_mm: the horizontal film back), ortho_width, camera_to_world (4x4
row-major), depth ('planar', 'radial', 'inverse',
'normalized'), depth_range ((A, B): normalized's 0 and 1, A > B for white near), normals,
sky_depth, max_pixels, view (a multi-view file's view to read; default the first with a depth).
Raises obscura.Error for a missing/unreadable file or missing passes.)doc";

const char* kProcessDoc = R"doc(obscura PATH -o OUT [flags]: writes OUT, a copy of PATH with the new layers added, and returns
the --report JSON as a dict (settings, recipe, camera, conventions, timings_s, stats, reference, warnings,
plan, written: the channels added, and written_views: each one's view where a part per view repeats the names).

The layers written, by argument (the CLI's flags write the same):
- always: the AO, obscura.AO.Y (out_layer='NAME' or {'ao': 'NAME'}: NAME.Y).
- method='ssdo': also the directional occlusion obscura.DO.R/G/B ({'do': NAME} renames it).
- bounce=True (method 'ssdo', or 'hbao': the horizon's bounce): also the one bounce
  obscura.GI.R/G/B and the relit image obscura.relit.R/G/B = albedo x (DO + GI) / pi (hbao: albedo
  x GI / pi; + albedo x direct diffuse with relit_direct=True). Needs the albedo pass and the
  bounce source's (bounce_source, default 'direct-diffuse', itself times the albedo); a file
  without them raises obscura.Error.
- out_layer={'gi': NAME} or {'relit': NAME} (ssdo, hbao): names that layer and asks for it alone,
  so out_layer={'gi': 'obscura.GI'} without bounce writes GI but no relit.

Keywords are the CLI's flags with underscores: quality, method (a key of obscura.METHODS), radius,
directions, steps, weighting, falloff, blur, device, threads; each method's own parameters
(obscura.METHODS[m]['params']: thickness, border and deep_layers for hbao, ssao_samples,
rtao_rays, disc_window, ...); preset, layer={role: name}, camera
(sidecar path), fov_deg (or focal_mm with aperture_mm: the horizontal film back), ortho_width,
camera_to_world (4x4 or 16 numbers, row-major), depth
('planar' | 'radial' | 'inverse' | 'normalized'), depth_range ((near, far): what a normalized
depth's 0 and 1 stand for), normals ('world' | 'camera' | 'depth': reconstructed from the depth),
sky_depth, max_pixels (refuse a data or
display window above it before allocating, as --max-pixels; default 16384^2), view (a multi-view
file's views to process: a name or a list, as --view; default every view with a depth); out_layer (above),
out_type ('half' | 'float'), bad_pixels ('error' | 'skip'), reference (layer name), report
(also write the JSON there), preview (PNG path: 8-bit sRGB of the AO, or in a lit run, ssdo or
hbao with bounce, of the relit layer when written, else ssdo's DO or hbao's GI),
preview_exposure (stops before the preview's encoding; default AO 0, a lit run automatic: the
99th percentile at 0.8), in_place (bool), write ('copy': PATH plus the
new layers, the default; 'new': only the new layers, with PATH's windows, camera and colour
attributes; PATH's other channels are not decoded; 'append': PATH's parts copied as compressed
chunks, untouched, plus a part holding the new layers).
Deep input (docs/deep.md): PATH a deep EXR with no flat file, or a list of deep elements rendered
apart, merged; OUT is then the flattened image plus the new layers. per_element_ao=True (hbao,
falloff='none') also writes an AO per element, of its own visible surface: <ao layer>.<element>.Y,
the file's stem less its frame number.
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
Outputs are written atomically; on obscura.Error nothing is left behind.)doc";

const char* kInspectDoc = R"doc(obscura PATH --inspect --json, as a dict: what obscura finds in the file, writing nothing.

'file'; 'parts' and 'multipart'; 'display_window', 'data_window' (x0, y0, x1, y1) half-open;
'layers' [{'name', 'part', 'part_name', 'channels', 'type'}]; 'preset'; 'roles' {role: [channel
names] or None}; 'role_parts' {role: part name or index} in a multipart file; 'conventions' {'depth', 'normals', 'normals_left_handed', 'sky_depth'}; 'deep'
(None without deep input); 'camera' {'projection', 'fx', 'fy', 'cx', 'cy', 'source',
'horizontal_fov_deg' or 'ortho_width', 'camera_to_world' (4 rows or None), 'fit_residual_px'
when fitted} or None, then 'camera_error' says why; 'write' (how process() would write);
'device' (or None and 'device_error'); 'views', 'view' (the one described), 'views_processed';
'fills' {role: how obscura finds or fills it}; 'problems' (what stops a run as asked);
'command' and 'command_args' (a CLI line that would run, or None and 'command_problem'),
'command_notes' (what it assumed). Only an unreadable file raises. Keywords as read_passes(),
and device.)doc";

const char* kReadLayerDoc = R"doc(One channel ('obscura.AO.Y') as float32 (H, W), or a layer ('ViewLayer.Normal') as float32
(H, W, C) with its channels in R, G, B, A / X, Y, Z order, over its part's data window.
max_pixels as process(). Raises obscura.Error when the file or the name is missing.)doc";

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
        p = loadFramePasses(job, {}, nullptr, true);
        try {
            camera = resolveFrameCamera(job, p);
        } catch (const Error& e) {
            cameraError = keywordSpelling(e.what());
        }
        depthKind = decodedKind(p.depthEncoding);
        normalSpace = p.normalsFromDepth ? NormalSpace::Depth : job.normalSpace.value_or(p.plan.normalSpace);
        sky = job.skyDepth.value_or(p.plan.skyDepth);
        // Left-handed camera-space normals (+z forward) become OpenGL's, as runFrameJob does.
        if (p.plan.normalsLeftHanded && normalSpace == NormalSpace::Camera && !job.normalSpace)
            for (size_t i = 2; i < p.normal.pixels.size(); i += 3) p.normal.pixels[i] = -p.normal.pixels[i];
    }
    py::dict layers;
    for (const LayerBinding& b : p.plan.bindings) layers[py::str(roleName(b.role))] = py::cast(b.channels);
    py::dict d;
    d["depth"] = imageToArray(std::move(p.depth), true);
    d["normal"] = p.normalsFromDepth ? py::object(py::none()) : py::object(imageToArray(std::move(p.normal), false));
    if (!p.position.empty()) d["position"] = imageToArray(std::move(p.position), false);
    d["camera"] = camera ? py::cast(*camera) : py::none();
    d["camera_error"] = camera ? py::none() : py::cast(cameraError);
    d["normals"] = toString(normalSpace);
    d["depth_kind"] = toString(depthKind);
    d["depth_encoding"] = toString(p.depthEncoding);
    d["sky_depth"] = (double)sky;
    d["data_window"] = boxToTuple(p.data);
    d["display_window"] = boxToTuple(p.display);
    d["pixel_aspect"] = p.pixelAspect;
    d["up"] = job.zUp.value_or(p.plan.preset == "blender") ? "z" : "y";  // the world's, as process() takes it
    d["preset"] = p.plan.preset;
    d["layers"] = layers;
    d["part"] = p.part;
    d["view"] = p.view.empty() ? py::object(py::none()) : py::object(py::str(p.view));
    d["path"] = job.input;
    return d;
}

// process(): the job's files checked against one another, then run; the report as a dict.
py::object processPy(const FrameJob& job, const std::string& reportPath) {
    std::string json;
    const CtrlCStops interrupt;  // with the GIL held
    {
        py::gil_scoped_release release;
        checkFrameFiles({{&job, reportPath}}, Spelling::Key);
        if (!reportPath.empty()) requireWritableDestination(reportPath);
        WriteBatch files;  // the output, preview and report land together or not at all
        const FrameReport report = runFrameJob(job);
        json = frameReportJson(job, report);
        if (!reportPath.empty()) writeTextFileAtomically(reportPath, json);
        files.commit();
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

// read_layer's name in the first part that has it: the channel itself, or LAYER.c channels in a
// conventional order (io/layers.h channelOrder): R G B A, X Y Z, then the rest by name. Empty when no part has it.
std::vector<ChannelRef> channelsNamed(const ExrInfo& info, const std::string& name) {
    std::vector<ChannelRef> wanted;
    for (size_t p = 0; p < info.parts.size() && wanted.empty(); ++p) {
        const ExrPart& part = info.parts[p];
        if (part.findChannel(name) >= 0) {
            wanted.push_back({(int)p, name});
            break;
        }
        std::vector<std::string> found;
        for (const ExrChannel& c : part.channels)
            if (c.name.size() > name.size() + 1 && c.name.compare(0, name.size() + 1, name + ".") == 0 &&
                c.name.find('.', name.size() + 1) == std::string::npos)
                found.push_back(c.name);
        auto rank = [&](const std::string& n) { return channelOrder(n.substr(name.size() + 1)); };
        std::stable_sort(found.begin(), found.end(),
                         [&](const std::string& a, const std::string& b) { return rank(a) < rank(b); });
        for (const std::string& n : found) wanted.push_back({(int)p, n});
    }
    return wanted;
}

py::array readLayerPy(const py::object& path, const py::object& nameObj, const py::object& maxPixels) {
    const std::string file = pathArg(path, "path");
    const std::string name = strArg(nameObj, "name");
    const long long limit = maxPixelsArg(maxPixels);
    Image image;
    {
        py::gil_scoped_release release;
        const ExrInfo info = readExrInfo(file, limit);
        const std::vector<ChannelRef> wanted = channelsNamed(info, name);
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

void bindReadPasses(py::module_& m) {
    m.def(
        "read_passes",
        [](const py::object& path, const py::args& extra, OBSCURA_FILE_PARAMS, const py::kwargs& unknown) {
            checkFileCall("read_passes", extra, unknown, path);
            return readPassesPy(path, OBSCURA_FILE_ARGS_MADE);
        },
        py::arg("path") = py::none(), OBSCURA_FILE_ARGS, kReadPassesDoc);
}

// The lambda takes every keyword of process() (docs in kProcessDoc) and only groups them.
void bindProcess(py::module_& m) {
    m.def(
        "process",
        [](const py::object& path, const py::object& out, const py::args& extra, py::object quality,
           py::object method, py::object radius, py::object directions, py::object steps, py::object weighting, py::object falloff, py::object blur,
           py::object device, py::object threads, OBSCURA_FILE_PARAMS, py::object outLayer, py::object outType, py::object badPixels, py::object reference,
           py::object report, py::object preview, py::object inPlace, py::object samples, py::object interleave,
           py::object sky, py::object envRotate, py::object envIntensity, py::object lights, py::object bounce,
           py::object bounceSource, py::object env, py::object envColorspace, py::object colorspace, py::object up,
           py::object timesAlbedo, py::object relitDirect, py::object write, py::object previewExposure,
           py::object perElementAo, const py::kwargs& own) {
            checkPositional("process", extra, {"path", "out"}, "method=..., radius=...");
            required("process", path, "path", "the input EXR's path");
            required("process", out, "out", "the output EXR's path");
            const FrameJob job = processJob(
                path, out,
                OBSCURA_FILE_ARGS_MADE,
                SettingArgs{quality, method, radius, directions, steps, weighting, falloff, blur, device, threads, own},
                OutputArgs{outLayer, outType, badPixels, reference, report, preview, inPlace, write, previewExposure,
                           perElementAo},
                SsdoArgs{samples, interleave, sky, envRotate, envIntensity, lights},
                JobSsdoArgs{bounce, bounceSource, env, envColorspace, colorspace, up, timesAlbedo, relitDirect});
            return processPy(job, report.is_none() ? std::string() : pathArg(report, "report"));
        },
        py::arg("path") = py::none(), py::arg("out") = py::none(), OBSCURA_SETTING_ARGS, OBSCURA_FILE_ARGS,
        py::arg("out_layer") = py::none(), py::arg("out_type") = py::none(), py::arg("bad_pixels") = py::none(),
        py::arg("reference") = py::none(), py::arg("report") = py::none(), py::arg("preview") = py::none(),
        py::arg("in_place") = py::none(), OBSCURA_SSDO_ARGS, py::arg("bounce") = py::none(),
        py::arg("bounce_source") = py::none(), py::arg("env") = py::none(), py::arg("env_colorspace") = py::none(),
        py::arg("colorspace") = py::none(), py::arg("up") = py::none(), py::arg("times_albedo") = py::none(),
        py::arg("relit_direct") = py::none(), py::arg("write") = py::none(), py::arg("preview_exposure") = py::none(),
        py::arg("per_element_ao") = py::none(), kProcessDoc);
}

void bindInspect(py::module_& m) {
    m.def(
        "inspect",
        [](const py::object& path, const py::args& extra, OBSCURA_FILE_PARAMS, py::object device, const py::kwargs& unknown) {
            checkFileCall("inspect", extra, unknown, path);
            return inspectPy(path, OBSCURA_FILE_ARGS_MADE,
                             device);
        },
        py::arg("path") = py::none(), OBSCURA_FILE_ARGS, py::arg("device") = py::none(), kInspectDoc);
}

void bindReadLayer(py::module_& m) {
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
        py::arg("path") = py::none(), py::arg("name") = py::none(), py::arg("max_pixels") = py::none(), kReadLayerDoc);
}

} // namespace

void bindFiles(py::module_& m) {
    bindReadPasses(m);
    bindProcess(m);
    bindInspect(m);
    bindReadLayer(m);
}

} // namespace obscura::python
