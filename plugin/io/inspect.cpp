#include "io/inspect.h"

#include "base/error.h"
#include "core/operator.h"
#include "io/deep_job.h"
#include "io/views.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

namespace obscura {

namespace {

using nlohmann::json;

// Half-open (x0, y0, x1, y1), as Python's read_passes gives windows.
json boxJson(const Box2i& b) { return {b.x0, b.y0, b.x1, b.y1}; }

json layersJson(const ExrInfo& info) {
    json out = json::array();
    for (const LayerSummary& l : summariseLayers(info))
        out.push_back({{"name", l.name}, {"part", l.part}, {"part_name", l.partName}, {"channels", l.channels},
                       {"type", l.type}});
    return out;
}

// Every role, null where the file has none, so a missing pass is visible rather than absent.
json rolesJson(const LayerPlan& plan) {
    json out = json::object();
    for (Role r : allRoles()) {
        const LayerBinding* b = plan.find(r);
        out[roleName(r)] = b ? json(b->channels) : json(nullptr);
    }
    return out;
}

// In a multipart file, the part each role is read from (its name, else its index): parts often
// hold bare R, G, B channels, which alone do not say which pass they are.
json rolePartsJson(const LayerPlan& plan, const ExrInfo& info) {
    json out = json::object();
    if (!info.multipart) return out;
    for (Role r : allRoles())
        if (const LayerBinding* b = plan.find(r); b && b->part >= 0 && b->part < (int)info.parts.size())
            out[roleName(r)] = info.parts[b->part].name.empty() ? std::to_string(b->part) : info.parts[b->part].name;
    return out;
}

json conventionsJson(const FrameJob& job, const FramePasses& p) {
    const NormalSpace normals = p.normalsFromDepth ? NormalSpace::Depth : job.normalSpace.value_or(p.plan.normalSpace);
    return {{"depth", toString(p.depthEncoding)},
            {"depth_source", p.depthFromPosition ? "position pass and camera" : "depth layer"},
            {"normals", toString(normals)},
            {"normals_source", normalsSourceLine(job, p.plan)},
            {"normals_left_handed", p.plan.normalsLeftHanded},
            {"sky_depth", job.skyDepth.value_or(p.plan.skyDepth)}};
}

// The depth as stored (from the position pass: as computed from it).
json depthStatisticsJson(const DepthStatistics& d) {
    return {{"min", d.min}, {"max", d.max}, {"sky_share", d.skyShare}, {"type", d.type},
            {"hint", d.hint.empty() ? json(nullptr) : json(d.hint)}};
}

void writeDepthStatistics(std::ostream& os, const json& conv, const json& d) {
    char line[200];
    std::snprintf(line, sizeof line, "depth values: min %g, max %g, sky %.1f%%, %s", d["min"].get<double>(),
                  d["max"].get<double>(), 100.0 * d["sky_share"].get<double>(), d["type"].get<std::string>().c_str());
    os << line;
    if (conv["depth_source"] != "depth layer") os << " (from the " << conv["depth_source"].get<std::string>() << ")";
    os << "\n";
    if (!d["hint"].is_null()) os << "  looks like " << d["hint"].get<std::string>() << "\n";
}

json deepJson(const FrameJob& job, const FramePasses& p) {
    const DeepLayers d = readJobDeepLayers(job, p);
    return {{"file", job.deepInput},          {"z", p.plan.deep.z},
            {"z_back", p.plan.deep.zBack},    {"layers", d.layers},
            {"max_layers", job.settings.deepLayers}, {"samples", d.samples},
            {"empty_pixels", d.emptyPixels},  {"dropped_samples", d.droppedSamples},
            {"unsorted_pixels", d.unsortedPixels}};
}

// Deep elements with no flat file: what their merge gave the passes.
json deepElementsJson(const FrameJob& job, const std::vector<std::string>& elements, const FrameReport& merge) {
    return {{"files", elements},
            {"layers", merge.deepLayers},
            {"max_layers", job.settings.deepLayers},
            {"empty_pixels", merge.deepEmptyPixels},
            {"dropped_samples", merge.deepDroppedSamples},
            {"truncated_pixels", merge.deepTruncatedPixels},
            {"passes", "the merge's: colour flattened front to back, depth of the nearest surface, normals from that depth"}};
}

// The keys of --report's camera, plus the field of view (or width) and the pose, row-major.
json cameraJson(const Camera& c, int displayWidth) {
    const bool perspective = c.projection == Projection::Perspective;
    json j = {{"projection", perspective ? "perspective" : "orthographic"},
              {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}, {"source", c.source}};
    if (perspective) j["horizontal_fov_deg"] = c.horizontalFovRad(displayWidth) * 180.0 / M_PI;
    else j["ortho_width"] = displayWidth / c.fx;
    json rows = nullptr;
    if (c.hasPose) {
        rows = json::array();
        for (int r = 0; r < 4; ++r)
            rows.push_back({c.cameraToWorld[0][r], c.cameraToWorld[1][r], c.cameraToWorld[2][r], c.cameraToWorld[3][r]});
    }
    j["camera_to_world"] = rows;
    if (c.fitResidualPx >= 0) j["fit_residual_px"] = c.fitResidualPx;
    return j;
}

void writeLayers(std::ostream& os, const json& j) {
    os << "layers:\n";
    for (const json& l : j["layers"]) {
        const LayerSummary s{l["part"], l["part_name"], l["name"], l["channels"], l["type"]};
        os << "  " << layerLine(s, j["multipart"].get<bool>()) << "\n";
    }
}

void writeRoles(std::ostream& os, const json& roles, const json& fills, const json& parts) {
    os << "roles:\n";
    for (Role r : allRoles()) {
        const json& channels = roles[roleName(r)];
        os << "  " << roleName(r) << ": ";
        if (channels.is_null()) os << "(not found) " << fills[roleName(r)].get<std::string>();
        for (size_t i = 0; i < channels.size(); ++i) os << (i ? ", " : "") << channels[i].get<std::string>();
        if (parts.contains(roleName(r))) os << " (part " << parts[roleName(r)].get<std::string>() << ")";
        os << "\n";
    }
}

void writeViews(std::ostream& os, const json& j) {
    if (j["views"].empty()) return;
    os << "views:   ";
    for (size_t i = 0; i < j["views"].size(); ++i) os << (i ? ", " : "") << j["views"][i].get<std::string>() << (i ? "" : " (default)");
    os << "; a run processes ";
    if (j.contains("views_unplanned")) os << "nothing (the problem below)";
    else if (j["views_processed"].empty()) os << "the file as one image (no view has a depth)";
    for (size_t i = 0; i < j["views_processed"].size(); ++i) os << (i ? ", " : "") << j["views_processed"][i].get<std::string>();
    if (!j["view"].is_null()) os << "; described below: " << j["view"].get<std::string>();
    os << "\n";
}

void writeCommand(std::ostream& os, const json& j) {
    for (const json& problem : j["problems"]) os << "problem: " << problem.get<std::string>() << "\n";
    for (const json& note : j["command_notes"]) os << "note:    " << note.get<std::string>() << "\n";
    if (j["command"].is_null()) os << "run:     no command can run on this file: " << j["command_problem"].get<std::string>() << "\n";
    else os << "run:     " << j["command"].get<std::string>() << "\n";
}

void writeDeep(std::ostream& os, const json& d) {
    os << "deep:    " << d["file"].get<std::string>() << " (" << d["z"].get<std::string>() << ", "
       << d["z_back"].get<std::string>() << "): " << d["layers"] << " layer(s) of at most " << d["max_layers"] << ", "
       << d["samples"] << " samples, " << d["empty_pixels"] << " empty pixels, " << d["dropped_samples"]
       << " dropped samples, " << d["unsorted_pixels"] << " unsorted pixels\n";
}

void writeDeepElements(std::ostream& os, const json& d) {
    const size_t n = d["files"].size();
    os << "deep:    " << n << (n == 1 ? " element, no flat file: " : " elements merged, no flat file: ")
       << d["layers"] << " layer(s) of at most " << d["max_layers"] << ", " << d["empty_pixels"] << " empty pixels, "
       << d["dropped_samples"] << " dropped samples\n         passes: " << d["passes"].get<std::string>() << "\n";
}

void writeCamera(std::ostream& os, const json& j) {
    const json& c = j["camera"];
    if (c.is_null()) {
        os << "camera:  none (" << j["camera_error"].get<std::string>() << ")\n";
        return;
    }
    os << "camera:  " << c["projection"].get<std::string>();
    if (c.contains("horizontal_fov_deg")) os << ", horizontal fov " << c["horizontal_fov_deg"].get<double>() << " deg";
    else os << ", width " << c["ortho_width"].get<double>();
    os << ", from " << c["source"].get<std::string>() << "\n";
    if (c["camera_to_world"].is_null()) return;
    os << "  camera-to-world (rows):";
    for (int r = 0; r < 3; ++r) {  // the fourth row of an affine pose is 0 0 0 1
        os << (r ? "\n                          " : " ");
        for (int col = 0; col < 4; ++col) os << (col ? " " : "") << c["camera_to_world"][r][col].get<double>();
    }
    os << "\n";
}

// The file's views, the one described and those a run would process.
void addViews(json& j, const FrameJob& job, const ExrInfo& info, const FramePasses* p) {
    j["views"] = fileViews(info);
    j["view"] = p && !p->view.empty() ? json(p->view) : json(nullptr);
    j["views_processed"] = json::array();
    try {
        const std::vector<std::string> processed = viewsToProcess(job, info);
        j["views_processed"] = processed;
        if (!p && !processed.empty()) j["view"] = processed.front();
    } catch (const Error&) {
        // A --view the file lacks, or a --layer a view lacks (loadFramePasses has reported it as
        // the problem): the roles are described as the file's default view holds them.
        j["views_unplanned"] = true;
        if (!p && !fileViews(info).empty()) j["view"] = fileViews(info).front();
    }
}

// The layers found; where a --layer names nothing (the problem reported), those the file offers
// without it; none when even that fails.
LayerPlan planOrNothing(const FrameJob& job, const ExrInfo& info, const std::string& view) {
    FrameJob plain = job;
    plain.layerOverrides.clear();
    for (const FrameJob* j : std::initializer_list<const FrameJob*>{&job, &plain}) {
        try {
            return planViewLayers(*j, info, view);
        } catch (const Error&) {
        }
    }
    LayerPlan none;
    none.preset = job.preset;
    return none;
}

std::string bindingName(const LayerBinding& b) { return "layer '" + (b.layer.empty() ? b.channels[0] : b.layer) + "'"; }

// How obscura fills each role: the layer found, or what it does without one.
json fillsJson(const FrameJob& job, const LayerPlan& plan) {
    const LayerBinding* depth = plan.find(Role::Depth);
    const LayerBinding* position = plan.find(Role::Position);
    json out = json::object();
    out["depth"] = depth      ? bindingName(*depth)
                   : position ? std::string("from the position pass and the camera")
                              : std::string("missing: obscura needs a depth layer (or a position pass); name one with "
                                            "--layer depth=NAME");
    out["normal"] = depth || position ? normalsSourceLine(job, plan) : std::string("reconstructed from depth, once there is one");
    out["position"] = position ? bindingName(*position) + ": fits the camera when nothing else gives it"
                               : std::string("not in the file: the camera comes from the flags, a sidecar or the header");
    for (Role r : {Role::Beauty, Role::Albedo, Role::DirectDiffuse}) {
        const LayerBinding* b = plan.find(r);
        out[roleName(r)] = b ? bindingName(*b) + ": read by --bounce (ssdo, hbao) and the relit layer"
                             : std::string("not in the file: only --bounce (ssdo, hbao) and the relit layer read it");
    }
    return out;
}

} // namespace

json inspectFrameJson(const FrameJob& job) {
    // Only a file that cannot be read at all is an error; everything after is reported.
    const ExrInfo info = readExrInfo(job.input, job.maxPixels, true);
    const std::vector<std::string> elements = deepElementsOf(job, &info);
    std::vector<std::string> problems;
    std::optional<FramePasses> p;
    DeepElementsInput merged;
    FrameReport merge;
    try {
        p = loadPassesForInspection(job, merged, merge, &info);
    } catch (const Error& e) {
        // Pixels that cannot be decoded make the file unreadable; anything else is reported.
        if (std::string(e.what()).find("': truncated or corrupt: ") != std::string::npos) throw;
        problems.push_back(firstLineOf(e.what()));
    }
    json j = {{"file", job.input}, {"multipart", info.multipart}, {"parts", info.parts.size()}};
    j["display_window"] = boxJson(p ? p->display : info.parts[0].displayWindow);
    j["data_window"] = boxJson(p ? p->data : info.parts[0].dataWindow);
    j["layers"] = layersJson(p && !elements.empty() ? p->info : info);  // a deep part lists no layers: the merge's
    addViews(j, job, info, p ? &*p : nullptr);
    const LayerPlan plan = p ? p->plan : planOrNothing(job, info, j["view"].is_null() ? "" : j["view"].get<std::string>());
    j["preset"] = plan.preset;
    j["roles"] = rolesJson(plan);
    j["role_parts"] = rolePartsJson(plan, p && !elements.empty() ? p->info : info);
    j["fills"] = fillsJson(job, plan);
    j["conventions"] = p ? conventionsJson(job, *p) : json(nullptr);
    j["depth_statistics"] = p ? depthStatisticsJson(p->depthStats) : json(nullptr);
    j["deep"] = job.deepInput.empty() || !p ? json(nullptr) : deepJson(job, *p);
    j["deep_elements"] = elements.empty() || !p ? json(nullptr) : deepElementsJson(job, elements, merge);
    j["camera"] = nullptr;
    j["camera_error"] = nullptr;
    if (p) {
        try {
            j["camera"] = cameraJson(resolveFrameCamera(job, *p), p->display.width());
        } catch (const Error& e) {
            j["camera_error"] = firstLineOf(e.what());
        }
    } else {
        j["camera_error"] = "not resolved: the passes could not be read";
    }
    j["write"] = describeWrite(job, info, p ? p->part : 0, p && !p->carried.empty());
    j["problems"] = problems;
    const SuggestedCommand command = suggestCommand(job, p ? &*p : nullptr);
    j["command"] = command.args.empty() ? json(nullptr) : json(commandLine(command.args));
    j["command_args"] = command.args.empty() ? json(nullptr) : json(command.args);
    j["command_notes"] = command.notes;
    j["command_problem"] = command.problem.empty() ? json(nullptr) : json(command.problem);
    j["device"] = nullptr;
    j["device_error"] = nullptr;
    try {
        j["device"] = describeDevice(job.settings);
    } catch (const Error& e) {
        j["device_error"] = e.what();
    }
    return j;
}

std::string inspectText(const json& j) {
    std::ostringstream os;
    const size_t parts = j["parts"];
    os << "file:    " << j["file"].get<std::string>() << (j["multipart"].get<bool>() ? " (multipart, " : " (")
       << parts << " part" << (parts > 1 ? "s)" : ")") << "\n";
    const json &display = j["display_window"], &data = j["data_window"];
    os << "display: " << display[2].get<int>() - display[0].get<int>() << "x"
       << display[3].get<int>() - display[1].get<int>() << "  data window: [" << data[0] << "," << data[1] << " - "
       << data[2] << "," << data[3] << ")\n";
    writeLayers(os, j);
    writeViews(os, j);
    os << "preset:  " << j["preset"].get<std::string>() << "\n";
    writeRoles(os, j["roles"], j["fills"], j["role_parts"]);
    const json& conv = j["conventions"];
    if (!conv.is_null()) {
        os << "depth:   " << conv["depth"].get<std::string>() << "   normals: " << conv["normals"].get<std::string>()
           << (conv["normals_left_handed"].get<bool>() ? " (left-handed, z flipped)" : "")
           << "   sky depth >= " << conv["sky_depth"].get<double>() << "\n";
        writeDepthStatistics(os, conv, j["depth_statistics"]);
        os << conv["normals_source"].get<std::string>() << "\n";
    }
    if (!j["deep"].is_null()) writeDeep(os, j["deep"]);
    if (!j["deep_elements"].is_null()) writeDeepElements(os, j["deep_elements"]);
    writeCamera(os, j);
    os << "write:   " << j["write"].get<std::string>() << "\n";
    if (j["device"].is_null()) os << "device:  unavailable (" << j["device_error"].get<std::string>() << ")\n";
    else os << "device:  " << j["device"].get<std::string>() << "\n";
    writeCommand(os, j);
    return os.str();
}

} // namespace obscura
