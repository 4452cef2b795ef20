#include "python/py_job.h"

#include "core/methods.h"
#include "core/settings_schema.h"
#include "io/deep_job.h"
#include "python/py_args.h"

#include <string>
#include <utility>

namespace obscura::python {

namespace {

// out_layer=: a name for the AO, or {output: name} for any of ao, do, gi, relit.
void applyOutLayer(const py::object& outLayer, FrameJob& job) {
    auto needSsdo = [&](const std::string& output) {
        const std::string problem = outputRefusal(job.settings.method, output, Spelling::Key);
        if (!problem.empty()) valueError(problem);
    };
    if (py::isinstance<py::dict>(outLayer)) {
        for (auto item : py::reinterpret_borrow<py::dict>(outLayer)) {
            const std::string role = strArg(item.first, "out_layer role");
            const std::string name = strArg(item.second, "out_layer name");
            const std::string problem = outLayerProblem(name);
            if (!problem.empty()) valueError("out_layer['" + role + "']: the name " + problem);
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
        job.aoLayer = strArg(outLayer, "out_layer");
        const std::string problem = outLayerProblem(job.aoLayer);
        if (!problem.empty()) valueError("out_layer: the name " + problem);
    }
}

void applyJobSsdo(const JobSsdoArgs& js, FrameJob& job) {
    if (!js.bounce.is_none() && boolArg(js.bounce, "bounce")) requestBounce(job);
    if (!js.bounceSource.is_none()) {
        job.bounceSource = strArg(js.bounceSource, "bounce_source");
        if (job.bounceSource.empty())
            valueError("bounce_source must be 'direct-diffuse', 'beauty' or an RGB layer name, got ''");
    }
    if (!js.env.is_none()) job.envPath = pathArg(js.env, "env");
    if (!js.envColorspace.is_none()) job.envColourSpace = strArg(js.envColorspace, "env_colorspace");
    if (!js.colorspace.is_none()) job.colourSpace = strArg(js.colorspace, "colorspace");
    if (!js.up.is_none()) job.zUp = upArg(js.up);
    if (!js.timesAlbedo.is_none() && boolArg(js.timesAlbedo, "times_albedo")) job.timesAlbedo = true;
    if (!js.relitDirect.is_none() && boolArg(js.relitDirect, "relit_direct")) job.relitWithDirect = true;
}

void applyOutputs(const OutputArgs& o, FrameJob& job) {
    if (!o.outType.is_none()) job.aoFloat = choiceArg(o.outType, "out_type", kOutTypeWords) == "float";
    if (!o.badPixels.is_none())
        job.badPixels = choiceArg(o.badPixels, "bad_pixels", kBadPixelsWords) == "skip" ? BadPixelPolicy::Skip
                                                                                       : BadPixelPolicy::Error;
    if (!o.reference.is_none()) job.referenceLayer = strArg(o.reference, "reference");
    if (!o.preview.is_none()) job.previewPath = pathArg(o.preview, "preview");
    if (!o.previewExposure.is_none()) {
        if (job.previewPath.empty()) valueError("preview_exposure needs preview=PATH");
        job.previewExposure = (float)numberArg(o.previewExposure, "preview_exposure");
    }
    if (!o.inPlace.is_none()) job.inPlace = boolArg(o.inPlace, "in_place");
    if (!o.write.is_none()) parse(choiceArg(o.write, "write", {"copy", "new", "append"}), job.write);
    if (job.write == WriteMode::New && job.inPlace)
        valueError("write='new' and in_place=True do not go together: the output holds only the new layers");
    if (!o.perElementAo.is_none()) job.perElementAo = boolArg(o.perElementAo, "per_element_ao");
    const std::string problem = perElementAoProblem(job, Spelling::Key);
    if (!problem.empty()) valueError(problem);
}

} // namespace

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
    if (!f.focalMm.is_none()) job.camera.focalMm = numberArg(f.focalMm, "focal_mm");
    if (!f.apertureMm.is_none()) job.camera.apertureMm = numberArg(f.apertureMm, "aperture_mm");
    if (const std::string lens = lensProblem(job.camera, Spelling::Key); !lens.empty()) valueError(lens);
    if (!f.cameraToWorld.is_none()) job.camera.cameraToWorld = matrixRowsArg(f.cameraToWorld, "camera_to_world");
    if (!f.depth.is_none())
        job.depthEncoding = enumArg<DepthEncoding>(f.depth, "depth", "'planar', 'radial', 'inverse' or 'normalized'");
    if (!f.depthRange.is_none()) {
        const std::vector<double> ends = numbersArg(f.depthRange, "depth_range", 2);
        const std::string problem = depthRangeProblem(ends[0], ends[1], Spelling::Key);
        if (!problem.empty()) valueError(problem);
        job.depthRange = std::array<double, 2>{ends[0], ends[1]};
    }
    if (!f.normals.is_none()) job.normalSpace = enumArg<NormalSpace>(f.normals, "normals", "'world', 'camera' or 'depth'");
    if (!f.skyDepth.is_none()) job.skyDepth = (float)numberArg(f.skyDepth, "sky_depth");
    if (!f.view.is_none()) {
        // One name, or a list or tuple of names, as --view NAME[,NAME].
        const bool one = py::isinstance<py::str>(f.view);
        if (!one && !py::isinstance<py::list>(f.view) && !py::isinstance<py::tuple>(f.view))
            throw py::type_error("view must be a view name or a list of them, got " + typeName(f.view));
        if (one) job.views = {strArg(f.view, "view")};
        else
            for (const py::handle item : f.view) job.views.push_back(strArg(py::reinterpret_borrow<py::object>(item), "view"));
        const std::string problem = nameListProblem(nameListSetting("view"), job.views, Spelling::Key);
        if (!problem.empty()) valueError(problem);
    }
    return job;
}

FrameJob processJob(const py::object& path, const py::object& out, const FileArgs& f, const SettingArgs& sa,
                    const OutputArgs& o, const SsdoArgs& ssdoArgs, const JobSsdoArgs& js) {
    // A list or tuple of paths: deep elements, merged; the first is the input the errors name.
    const bool several = py::isinstance<py::list>(path) || py::isinstance<py::tuple>(path);
    std::vector<std::string> elements;
    if (several)
        for (const py::handle item : path) elements.push_back(pathArg(py::reinterpret_borrow<py::object>(item), "path"));
    if (several && elements.empty()) valueError("path: an empty list of deep elements");
    FrameJob job = jobFrom(several ? py::object(py::str(elements[0])) : path, f);
    if (elements.size() > 1) job.deepElements = elements;
    job.output = pathArg(out, "out");
    job.settings = settingsFrom(sa);
    applySsdo(ssdoArgs, job.settings);
    // Keywords and outputs the method would ignore: asking for them would silently write nothing.
    for (const auto& [key, value] :
         {std::pair<const char*, const py::object*>{"bounce", &js.bounce}, {"bounce_source", &js.bounceSource},
          {"env", &js.env}, {"env_colorspace", &js.envColorspace}, {"colorspace", &js.colorspace}, {"up", &js.up},
          {"times_albedo", &js.timesAlbedo}, {"relit_direct", &js.relitDirect}})
        refuseIgnored(job.settings.method, key, *value);
    if (!o.outLayer.is_none()) applyOutLayer(o.outLayer, job);
    applyJobSsdo(js, job);
    applyOutputs(o, job);
    return job;
}

} // namespace obscura::python
