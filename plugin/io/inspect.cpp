#include "io/inspect.h"

#include "base/error.h"
#include "core/operator.h"

#include <cmath>
#include <cstdio>
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

void writeRoles(std::ostream& os, const json& roles) {
    os << "roles:\n";
    for (Role r : allRoles()) {
        const json& channels = roles[roleName(r)];
        os << "  " << roleName(r) << ": ";
        if (channels.is_null()) os << "(not found)";
        for (size_t i = 0; i < channels.size(); ++i) os << (i ? ", " : "") << channels[i].get<std::string>();
        os << "\n";
    }
}

void writeDeep(std::ostream& os, const json& d) {
    os << "deep:    " << d["file"].get<std::string>() << " (" << d["z"].get<std::string>() << ", "
       << d["z_back"].get<std::string>() << "): " << d["layers"] << " layer(s) of at most " << d["max_layers"] << ", "
       << d["samples"] << " samples, " << d["empty_pixels"] << " empty pixels, " << d["dropped_samples"]
       << " dropped samples, " << d["unsorted_pixels"] << " unsorted pixels\n";
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

} // namespace

json inspectFrameJson(const FrameJob& job) {
    const FramePasses p = loadFramePasses(job, false);
    json j = {{"file", job.input},
              {"multipart", p.info.multipart},
              {"parts", p.info.parts.size()},
              {"display_window", boxJson(p.display)},
              {"data_window", boxJson(p.data)},
              {"layers", layersJson(p.info)},
              {"preset", p.plan.preset},
              {"roles", rolesJson(p.plan)},
              {"conventions", conventionsJson(job, p)},
              {"depth_statistics", depthStatisticsJson(p.depthStats)},
              {"deep", job.deepInput.empty() ? json(nullptr) : deepJson(job, p)},
              {"camera", nullptr},
              {"camera_error", nullptr},
              {"write", describeWrite(job, p.info, p.part)},
              {"device", nullptr},
              {"device_error", nullptr}};
    try {
        j["camera"] = cameraJson(resolveFrameCamera(job, p), p.display.width());
    } catch (const Error& e) {
        j["camera_error"] = e.what();
    }
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
    os << "preset:  " << j["preset"].get<std::string>() << "\n";
    writeRoles(os, j["roles"]);
    const json& conv = j["conventions"];
    os << "depth:   " << conv["depth"].get<std::string>() << "   normals: " << conv["normals"].get<std::string>()
       << (conv["normals_left_handed"].get<bool>() ? " (left-handed, z flipped)" : "")
       << "   sky depth >= " << conv["sky_depth"].get<double>() << "\n";
    writeDepthStatistics(os, conv, j["depth_statistics"]);
    os << conv["normals_source"].get<std::string>() << "\n";
    if (!j["deep"].is_null()) writeDeep(os, j["deep"]);
    writeCamera(os, j);
    os << "write:   " << j["write"].get<std::string>() << "\n";
    if (j["device"].is_null()) os << "device:  unavailable (" << j["device_error"].get<std::string>() << ")\n";
    else os << "device:  " << j["device"].get<std::string>() << "\n";
    return os.str();
}

} // namespace obscura
