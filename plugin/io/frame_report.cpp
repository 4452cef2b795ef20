// The JSON a frame's --report holds (settings, camera, timings, statistics), and a failed
// frame's instead; declared in io/frame_job.h.
#include "io/frame_job.h"

#include "core/methods.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>

namespace obscura {

std::string frameFailureJson(const FrameJob& job, int frame, const std::string& error) {
    const nlohmann::json j = {{"obscura", OBSCURA_VERSION_STRING}, {"frame", frame}, {"input", job.input},
                              {"output", job.output}, {"error", error}};
    return j.dump(2);
}

namespace {
template <class T> nlohmann::json optionalJson(const std::optional<T>& v) { return v ? nlohmann::json(*v) : nlohmann::json(); }

// A path as given, less what names nothing (./, a/../): two spellings of one file compare equal.
std::string normalPath(const std::string& p) {
    return p.empty() ? p : std::filesystem::path(p).lexically_normal().string();
}

// What else of the job changes the output's pixels or channels beyond the settings: how the
// passes are read (the camera, the layers, the depth's encoding), which layers are written and
// where the light comes from. With the settings, what --resume compares (io/frame_job.h); paths
// of the files written, the threads and the device are not part of it.
nlohmann::json recipeJson(const FrameJob& job) {
    using nlohmann::json;
    json layers = json::object();
    for (const auto& [role, name] : job.layerOverrides) layers[roleName(role)] = name;
    const CameraRequest& c = job.camera;
    std::vector<std::string> elements;
    for (const std::string& e : job.deepElements) elements.push_back(normalPath(e));
    return {{"preset", job.preset},
            {"layers", layers},
            {"depth", job.depthEncoding ? json(toString(*job.depthEncoding)) : json()},
            {"depth_range", optionalJson(job.depthRange)},
            {"normals", job.normalSpace ? json(toString(*job.normalSpace)) : json()},
            {"sky_depth", optionalJson(job.skyDepth)},
            {"bad_pixels", job.badPixels == BadPixelPolicy::Skip ? "skip" : "error"},
            {"camera", {{"sidecar", normalPath(c.sidecarPath)}, {"fov_deg", optionalJson(c.fovDeg)},
                        {"focal_mm", optionalJson(c.focalMm)}, {"aperture_mm", optionalJson(c.apertureMm)},
                        {"ortho_width", optionalJson(c.orthoWidth)}, {"camera_to_world", optionalJson(c.cameraToWorld)}}},
            {"views", job.views},
            {"deep", {{"input", normalPath(job.deepInput)}, {"elements", elements}, {"per_element_ao", job.perElementAo}}},
            {"write", toString(job.write)},
            {"out_type", job.aoFloat ? "float" : "half"},
            {"out_layers", {{"ao", job.aoLayer},
                            {"do", job.writeDirectional ? json(job.doLayer) : json()},
                            {"gi", job.writeIndirect ? json(job.giLayer) : json()},
                            {"relit", job.writeRelit ? json(job.relitLayer) : json()}}},
            {"light", {{"bounce_source", job.bounceSource}, {"times_albedo", job.timesAlbedo},
                       {"relit_direct", job.relitWithDirect}, {"env", normalPath(job.envPath)}, {"up", optionalJson(job.zUp)},
                       {"colorspace", job.colourSpace}, {"env_colorspace", job.envColourSpace}}}};
}
} // namespace

// One statement per field of the report (docs/cli.md's schema): a table, so longer than a function
// should be.
std::string frameReportJson(const FrameJob& job, const FrameReport& r) {
    using nlohmann::json;
    const Settings& s = job.settings;
    json j;
    j["obscura"] = OBSCURA_VERSION_STRING;
    j["input"] = job.input;
    j["output"] = job.output;
    // The output wherever the run was started from: --resume run from another directory, with
    // paths spelled from there, finds this record by it.
    j["output_absolute"] = recordedPath(job.output);
    j["recipe"] = recipeJson(job);
    if (!r.sources.empty()) {
        j["sources"] = json::array();
        for (const FileStamp& f : r.sources)
            j["sources"].push_back({{"file", f.path}, {"size", f.size}, {"mtime_ns", f.mtimeNs}});
    }
    // What the method reads: its own parameters follow, from the method table.
    j["settings"] = {{"method", s.method}, {"radius", s.radius}, {"blur", resolvedBlur(s)},
                     {"threads", s.threads}, {"device", s.device}};
    if (settingRefusal(s.method, "weighting", Spelling::Key).empty()) j["settings"]["weighting"] = toString(s.weighting);
    if (settingRefusal(s.method, "falloff", Spelling::Key).empty()) j["settings"]["falloff"] = toString(s.falloff);
    if (methodOutputs(s.method, "gi") && !methodOutputs(s.method, "do")) {  // hbao --bounce; ssdo's below
        j["settings"]["bounce"] = job.writeIndirect || job.writeRelit;
        if (job.writeIndirect || job.writeRelit) {
            j["settings"]["bounce_source"] = job.bounceSource;
            j["settings"]["times_albedo"] = job.timesAlbedo;
        }
    }
    for (const MethodParam* p : paramsOf(s.method)) {
        json v = p->intField ? json(s.*(p->intField)) : p->floatField ? json(s.*(p->floatField)) : json(s.*(p->boolField));
        for (const NamedValue& n : p->named)  // "auto", "inf" (JSON has no infinity)
            if (p->floatField ? s.*(p->floatField) == (float)n.value : p->intField && s.*(p->intField) == (int)n.value)
                v = n.word;
        j["settings"][p->key] = v;
    }
    if (methodOutputs(s.method, "do")) {
        json lights = json::array();
        for (const auto& l : s.lights)
            lights.push_back({{"direction", {l.direction[0], l.direction[1], l.direction[2]}},
                              {"irradiance", {l.irradiance[0], l.irradiance[1], l.irradiance[2]}}});
        j["settings"]["ssdo"] = {{"samples", s.ssdoSamples},
                                 {"interleave", s.interleave},
                                 {"bounce", job.writeIndirect || job.writeRelit},
                                 {"bounce_source", job.bounceSource},
                                 {"env", normalPath(job.envPath)},
                                 {"env_rotate_deg", s.envRotationDeg},
                                 {"env_intensity", s.envIntensity},
                                 {"sky", {s.skyRadiance[0], s.skyRadiance[1], s.skyRadiance[2]}},
                                 {"lights", lights},
                                 {"times_albedo", job.timesAlbedo}};
    }
    if (!r.aoChannel.empty()) {
        j["output_channels"] = {{"ao", r.aoChannel}};
        if (readsColour(job)) {
            if (job.writeDirectional && methodOutputs(s.method, "do")) j["output_channels"]["do"] = job.doLayer;
            if (job.writeIndirect) j["output_channels"]["gi"] = job.giLayer;
            if (job.writeRelit) j["output_channels"]["relit"] = job.relitLayer;
        }
        j["conventions"] = {{"depth", toString(r.depthEncoding)}, {"normals", toString(r.normalSpace)},
                            {"sky_depth", r.skyDepth}};
        if (job.depthRange) j["conventions"]["depth_range"] = {(*job.depthRange)[0], (*job.depthRange)[1]};
        json cam = {{"projection", r.camera.projection == Projection::Perspective ? "perspective" : "orthographic"},
                    {"fx", r.camera.fx}, {"fy", r.camera.fy}, {"cx", r.camera.cx}, {"cy", r.camera.cy},
                    {"source", r.camera.source}};
        if (r.camera.fitResidualPx >= 0) cam["fit_residual_px"] = r.camera.fitResidualPx;
        j["camera"] = cam;
        json stages = json::object();
        double total = 0;
        for (const StageTiming& t : r.stages) {
            stages[t.name] = t.seconds;
            total += t.seconds;
        }
        j["timings_s"] = stages;
        j["total_s"] = total;
        j["stats"] = {{"pixels", r.stats.pixels}, {"sky_pixels", r.stats.skyPixels},
                      {"invalid_depth_pixels", r.stats.invalidDepthPixels},
                      {"zero_normal_pixels", r.stats.zeroNormalPixels},
                      {"non_unit_normal_pixels", r.nonUnitNormalPixels}, {"device", r.stats.device}};
        if (!job.deepInput.empty() || r.deepElements > 0) {  // --flat, or deep elements (their merge)
            j["deep"] = {{"layers", r.deepLayers}, {"empty_pixels", r.deepEmptyPixels},
                         {"dropped_samples", r.deepDroppedSamples}, {"unsorted_pixels", r.deepUnsortedPixels},
                         {"truncated_pixels", r.deepTruncatedPixels}};
            if (!job.deepInput.empty()) j["deep"]["file"] = job.deepInput;
            else j["deep"]["elements"] = job.deepElements.empty() ? std::vector<std::string>{job.input} : job.deepElements;
        }
        if (r.reference) {
            const ErrorMetrics& m = *r.reference;
            j["reference"] = {{"layer", job.referenceLayer}, {"pixels", m.pixels}, {"mae", m.mae}, {"rmse", m.rmse},
                              {"psnr_db", std::isfinite(m.psnr) ? json(m.psnr) : json("inf")}, {"p99_abs", m.p99},
                              {"max_abs", m.maxAbs}};
        }
        j["write"] = {{"mode", toString(job.write)}, {"description", r.writeDescription}};
        j["warnings"] = r.warnings;
        j["plan"] = r.plan;
        j["written"] = r.written;
        if (std::any_of(r.writtenViews.begin(), r.writtenViews.end(), [](const std::string& v) { return !v.empty(); }))
            j["written_views"] = r.writtenViews;
        if (!r.views.empty()) j["views"] = r.views;
    }
    return j.dump(r.aoChannel.empty() ? -1 : 2);
}

} // namespace obscura
