#include "io/deep_job.h"

#include "base/error.h"
#include "core/hbao_plan.h"
#include "core/methods.h"
#include "io/deep_merge.h"
#include "io/stage_timer.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfPartType.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>

namespace obscura {

namespace {

// The deep part's header as a flat scanline part's, without channels (the writer adds them).
ExrPart flatPart(const ExrPart& deep) {
    ExrPart part = deep;
    part.header = headerWithout(deep.header, [](const char* name) {
        for (const char* dropped : {"version", "chunkCount", "name", "tiles", "maxSamplesPerPixel"})
            if (std::strcmp(name, dropped) == 0) return true;
        return false;
    });
    part.header.setType(Imf::SCANLINEIMAGE);
    part.header.channels() = Imf::ChannelList();
    part.name.clear();
    part.channels.clear();
    part.tiled = false;
    part.deep = false;
    return part;
}

// The RGB of an SSDO read, from the flattened planes by name.
Image flattenedRgb(const std::vector<ChannelRef>& refs, const std::vector<NewChannel>& flat) {
    if (refs.empty()) return Image();
    std::vector<Image> planes;
    for (const ChannelRef& r : refs)
        for (const NewChannel& c : flat)
            if (c.name == r.name) planes.push_back(c.plane);
    return interleavePlanes(planes, 0, 3);
}

std::string cameraDifference(const Camera& a, const Camera& b) {
    auto differs = [](double x, double y, double scale) { return std::abs(x - y) > 1e-4 * scale; };
    char text[160];
    if (a.projection != b.projection) return "one is perspective, the other orthographic";
    if (differs(a.fx, b.fx, b.fx) || differs(a.fy, b.fy, b.fy)) {
        std::snprintf(text, sizeof text, "focal length %.6g px against %.6g px", a.fx, b.fx);
        return text;
    }
    if (differs(a.cx, b.cx, b.fx) || differs(a.cy, b.cy, b.fx)) {
        std::snprintf(text, sizeof text, "principal point (%.6g, %.6g) against (%.6g, %.6g)", a.cx, a.cy, b.cx, b.cy);
        return text;
    }
    if (a.hasPose != b.hasPose) return a.hasPose ? "it has a pose, the other none" : "it has no pose, the other one";
    double scale = 1.0;
    for (int c = 0; c < 4; ++c) scale = std::max(scale, std::abs(b.cameraToWorld[3][c]));
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (a.hasPose && differs(a.cameraToWorld[c][r], b.cameraToWorld[c][r], scale)) return "its pose differs";
    return "";
}

// Elements rendered apart are merged in one camera's image: each one's camera (header, sidecar
// or flags, as for a flat input) must be the first's.
void requireSameCameras(const FrameJob& job, const std::vector<DeepElement>& elements, const FramePasses& p) {
    auto cameraOf = [&](const DeepElement& e) {
        CameraRequest request = job.camera;
        if (request.sidecarPath.empty()) request.sidecarPath = findSidecar(e.path);
        return resolveCamera(request, &e.part.header, ConstPlane{}, p.data, p.display, p.pixelAspect);
    };
    Camera first;
    try {
        first = cameraOf(elements[0]);
    } catch (const Error&) {
        return;  // the frame's own camera resolution says why, naming the file
    }
    for (size_t i = 1; i < elements.size(); ++i) {
        Camera mine;
        try {
            mine = cameraOf(elements[i]);
        } catch (const Error& e) {
            throw FileError(elements[i].path, "no camera (" + firstLineOf(e.what()) + "), while '" + elements[0].path +
                                                  "' has one (" + first.source + ")");
        }
        const std::string diff = cameraDifference(mine, first);
        if (!diff.empty())
            throw FileError(elements[i].path, "its camera (" + mine.source + ") is not that of '" + elements[0].path +
                                                  "': " + diff);
    }
}

void refuseWhatDeepElementsCannotDo(const FrameJob& job) {
    if (job.write == WriteMode::Append)
        throw Error("--write append copies the input's parts, and deep elements have no flat part to copy; "
                    "use --write copy or new");
    if (job.depthEncoding && *job.depthEncoding != DepthEncoding::Planar && *job.depthEncoding != DepthEncoding::Radial)
        throw Error("a deep sample's Z is a distance: --depth planar or radial only");
    if (!job.referenceLayer.empty()) throw Error("--reference compares with a layer of a flat input, not of deep elements");
    const std::string problem = perElementAoProblem(job, Spelling::Flag);
    if (!problem.empty()) throw Error(problem);
}

// The report's lines and counts for the merge.
void reportMerge(const std::vector<std::string>& paths, const DeepMerge& m, FrameReport& report) {
    report.deepElements = (int)paths.size();
    report.deepLayers = m.layerCount;
    report.deepEmptyPixels = m.emptyPixels;
    report.deepDroppedSamples = m.droppedSamples;
    report.deepTruncatedPixels = m.truncatedPixels;
    report.plan.push_back("deep elements: " + std::to_string(paths.size()) + " merged (" + std::to_string(m.samples) +
                          " samples), flattened front to back; " +
                          (m.layerCount ? std::to_string(m.layerCount) + " layer(s)" : "no layers (falloff none uses them)"));
    if (m.droppedSamples)
        report.warnings.push_back(std::to_string(m.droppedSamples) +
                                  " deep samples with NaN, -inf or non-positive Z skipped");
}

} // namespace

std::string perElementAoProblem(const FrameJob& job, Spelling s) {
    if (!job.perElementAo) return "";
    const std::string flag = s == Spelling::Flag ? "--per-element-ao" : "per_element_ao";
    if (!methodReads(job.settings.method, "deep"))
        return flag + " works with " + (s == Spelling::Flag ? "--method " : "method=") + methodNames(", ", "deep") + " only";
    if (job.settings.falloff == Falloff::Linear)
        return flag + " needs " + (s == Spelling::Flag ? "--falloff none" : "falloff='none'") +
               ": linear falloff ignores the deep layers, through which the other elements occlude each element";
    return "";
}

std::vector<std::string> deepElementsOf(const FrameJob& job, const ExrInfo* input) {
    if (!job.deepElements.empty()) return job.deepElements;
    if (!job.deepInput.empty()) return {};
    return input->parts[0].deep ? std::vector<std::string>{job.input} : std::vector<std::string>{};
}

FramePasses loadPassesForInspection(const FrameJob& job, DeepElementsInput& deep, FrameReport& report,
                                    const ExrInfo* input) {
    std::optional<ExrInfo> read;
    if (!input && job.deepElements.empty()) read = readExrInfo(job.input, job.maxPixels, true);
    const ExrInfo* headers = input ? input : read ? &*read : nullptr;
    const std::vector<std::string> elements = deepElementsOf(job, headers);
    if (!elements.empty()) return loadDeepElements(job, elements, deep, report, true);
    if (job.write != WriteMode::Append) requireFlatParts(*headers);  // as a run checks the headers it passes on
    return loadFramePasses(job, {}, nullptr, false, headers);
}

FramePasses loadDeepElements(const FrameJob& job, const std::vector<std::string>& paths, DeepElementsInput& deep,
                             FrameReport& report, bool allLayers) {
    refuseWhatDeepElementsCannotDo(job);
    std::vector<DeepElement> elements;
    LayerPlan elementPlan;
    {
        StageTimer timer{&report.stages, "read"};
        // The preset (and so the deep channels' names and the depth's kind) from the first element.
        ExrInfo firstInfo = readExrInfo(paths[0], job.maxPixels, true);
        firstInfo.parts.resize(1);
        firstInfo.parts[0].channels = headerChannels(firstInfo.parts[0].header);
        elementPlan = planLayers(firstInfo, job.preset);
        elements = readDeepElements(paths, elementPlan.deep, job.maxPixels, job.settings.threads);
    }
    StageTimer timer{&report.stages, "merge"};
    const int layers = allLayers || readsDeepLayers(job.settings) ? job.settings.deepLayers : 0;
    if (layers == 0) warnIfDeepLayersIgnored(job, report);
    DeepMerge m = mergeDeepElements(elements, layers, job.perElementAo, job.settings.threads, readsDeepColour(job));
    if (readsDeepColour(job)) noteDeepColour(!m.colour.empty(), report);
    for (DeepElement& e : elements) e.samples = DeepChannels();  // merged: only headers and paths are read on

    FramePasses p;
    const ExrPart part = flatPart(elements[0].part);
    p.raw.info.path = p.info.path = paths[0];
    p.raw.info.parts = {part};
    p.raw.raw.resize(1);
    p.info.parts = {part};
    p.info.parts[0].channels = m.channels;
    p.info.parts[0].channels.push_back({elementPlan.deep.z, Imf::FLOAT, 1, 1});
    std::map<Role, std::string> overrides = job.layerOverrides;
    overrides[Role::Depth] = elementPlan.deep.z;
    p.plan = planLayers(p.info, job.preset, overrides);
    // Flattened normals or positions would be averages across surfaces: the depth gives both.
    p.plan.bindings.erase(std::remove_if(p.plan.bindings.begin(), p.plan.bindings.end(),
                                         [](const LayerBinding& b) { return b.role == Role::Normal || b.role == Role::Position; }),
                          p.plan.bindings.end());
    p.display = m.display;
    p.data = m.data;
    p.pixelAspect = part.header.pixelAspectRatio();
    p.normalsFromDepth = true;
    p.depthEncoding = job.depthEncoding.value_or(p.plan.depthKind == DepthKind::Radial ? DepthEncoding::Radial
                                                                                       : DepthEncoding::Planar);
    p.depth = m.front;
    p.depthStats = depthStatistics(p.depth, job.skyDepth.value_or(p.plan.skyDepth), "float");
    for (size_t c = 0; c < m.channels.size(); ++c)
        p.carried.push_back({0, m.channels[c].name, std::move(m.flat[c]), m.channels[c].type});
    p.carried.push_back({0, elementPlan.deep.z, std::move(m.front), Imf::FLOAT});
    const SsdoReads reads = planSsdoReads(job, p);
    p.radiance = flattenedRgb(reads.radiance, p.carried);
    p.albedo = flattenedRgb(reads.albedo, p.carried);
    p.directDiffuse = flattenedRgb(reads.directDiffuse, p.carried);
    requireSameCameras(job, elements, p);
    reportMerge(paths, m, report);
    deep.layers = std::move(m.layers);
    deep.colour = std::move(m.colour);
    deep.names = elementLayerNames(paths);
    deep.front = std::move(m.elementFront);
    deep.elementLayers = std::move(m.elementLayers);
    return p;
}

std::vector<NewChannel> elementAoLayers(const FrameJob& job, const OperatorInputs& in, const Settings& settings,
                                        const DeepElementsInput& deep, FrameReport& report) {
    std::vector<NewChannel> layers;
    Settings aoAlone = settings;  // each element's AO only: the light is the merge's
    aoAlone.bounce = false;
    for (size_t e = 0; e < deep.front.size(); ++e) {
        OperatorInputs one = in;
        one.depth = deep.front[e].view();
        one.deepLayers = deep.elementLayers[e].view();
        one.deepColour = ConstPlane{};
        NewChannel c;
        c.name = aoChannelName(job.aoLayer + "." + deep.names[e]);
        {
            StageTimer timer{&report.stages, "compute " + deep.names[e]};
            c.plane = runOperator(one, aoAlone).ao;
        }
        c.type = job.aoFloat ? Imf::FLOAT : Imf::HALF;
        layers.push_back(std::move(c));
    }
    if (!layers.empty())
        report.plan.push_back("per-element AO: " + std::to_string(layers.size()) +
                              " layer(s), each element's own surface with all elements as occluders");
    return layers;
}

std::vector<std::string> elementLayerNames(const std::vector<std::string>& paths) {
    std::vector<std::string> names;
    for (const std::string& path : paths) {
        std::string stem = std::filesystem::path(path).stem().string();
        size_t end = stem.size();
        while (end > 0 && std::isdigit((unsigned char)stem[end - 1])) --end;
        if (end > 1 && end < stem.size() && (stem[end - 1] == '.' || stem[end - 1] == '_')) stem.resize(end - 1);
        for (char& ch : stem)
            if (!std::isalnum((unsigned char)ch) && ch != '_' && ch != '-') ch = '_';
        if (stem.empty()) stem = "element";
        std::string name = stem;
        for (int k = 2; std::find(names.begin(), names.end(), name) != names.end(); ++k) name = stem + "_" + std::to_string(k);
        names.push_back(name);
    }
    return names;
}

} // namespace obscura
