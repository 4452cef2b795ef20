#include "io/frame_job.h"

#include "io/environment_map.h"
#include "io/exr_chunk_table.h"
#include "io/frame_outputs.h"
#include "io/stage_timer.h"

#include "base/error.h"
#include "core/hbao_plan.h"
#include "core/light_inputs.h"
#include "core/methods.h"
#include "io/colour.h"
#include "io/deep_file.h"
#include "io/deep_job.h"
#include "io/depth_encoding.h"
#include "io/views.h"

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <cstdlib>
#include <sstream>
#include <utility>


namespace obscura {

namespace {

namespace fs = std::filesystem;


std::string joinedLayers(const ExrInfo& info) {
    std::string found;
    for (const std::string& l : listLayers(info)) found += (found.empty() ? "" : "; ") + l;
    return found;
}

// The channel a --reference LAYER names: the exact channel, or the first of LAYER.{R,Y,V,Z,A,...}.
std::string findReferenceChannel(const ExrPart& part, const std::string& layer, const ExrInfo& info) {
    if (part.findChannel(layer) >= 0) return layer;
    for (const char* suffix : {"R", "Y", "V", "Z", "X", "A", "r", "y"}) {
        const std::string name = layer + "." + suffix;
        if (part.findChannel(name) >= 0) return name;
    }
    throw FileError(info.path, "no reference layer '" + layer + "'; layers found: " + joinedLayers(info));
}

bool sameFile(const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
}

// The sidecar the job names, or NAME.json next to the input.
std::string sidecarFor(const FrameJob& job) {
    return job.camera.sidecarPath.empty() ? findSidecar(job.input) : job.camera.sidecarPath;
}

bool cameraFullyGiven(const FrameJob& job) {
    const bool lens = job.camera.fovDeg || job.camera.focalMm || job.camera.orthoWidth;
    // Normals in camera space or from the depth need no pose.
    const bool pose = job.camera.cameraToWorld || (job.normalSpace && job.normalSpace != NormalSpace::World);
    return (lens && pose) || !sidecarFor(job).empty();
}

bool isSurface(float d, float sky) { return d > 0.0f && d < sky; }

// The squared lengths a normal may have: the kernels normalise in float, whose squares hold
// lengths from about 1e-19 to 1e19; 1e-6 keeps a normal that is rounding noise out.
constexpr double kMinNormalLength2 = 1e-12, kMaxNormalLength2 = 1e38;

std::string pixelText(const Box2i& data, size_t index, int width) {
    return std::to_string(data.x0 + (int)(index % width)) + "," + std::to_string(data.y0 + (int)(index / width));
}

// Checks the passes against the policy; counts non-unit normals for the report.
void validatePixels(const FrameJob& job, const FramePasses& p, float sky, FrameReport& report) {
    long long badDepth = 0, badNormal = 0, surface = 0, zeroNormal = 0;
    size_t firstBadDepth = 0, firstBadNormal = 0;
    const size_t n = p.depth.pixels.size();
    for (size_t i = 0; i < n; ++i) {
        const float d = p.depth.pixels[i];
        if (std::isnan(d) || d < 0.0f) {
            if (badDepth++ == 0) firstBadDepth = i;
            continue;
        }
        if (!isSurface(d, sky) || p.normalsFromDepth) continue;
        ++surface;
        // In double: a float's square under- or overflows where its length is 1e-23 or 2e19.
        const float* nv = &p.normal.pixels[i * 3];
        const double len2 = (double)nv[0] * nv[0] + (double)nv[1] * nv[1] + (double)nv[2] * nv[2];
        if (!(len2 > kMinNormalLength2 && len2 < kMaxNormalLength2)) {
            if (len2 == 0.0) ++zeroNormal;
            if (badNormal++ == 0) firstBadNormal = i;
        } else if (std::abs(std::sqrt(len2) - 1.0f) > 0.01f) {
            ++report.nonUnitNormalPixels;
        }
    }
    const std::string& path = job.input;
    if (surface > 0 && zeroNormal == surface)
        throw FileError(path, "the normal pass is zero on every surface pixel; check --layer normal=NAME");
    if (job.badPixels == BadPixelPolicy::Skip) {
        if (badDepth) report.warnings.push_back(std::to_string(badDepth) + " NaN or negative depth pixels treated as holes");
        if (badNormal) report.warnings.push_back(std::to_string(badNormal) + " surface pixels without a usable normal");
        return;
    }
    if (badDepth)
        throw FileError(path, "depth has " + std::to_string(badDepth) + " NaN or negative pixel(s), first at " +
                    pixelText(p.data, firstBadDepth, p.depth.width) + "; use --bad-pixels skip to treat them as holes");
    if (badNormal)
        throw FileError(path, "" + std::to_string(badNormal) +
                    " surface pixel(s) have a normal that is zero, not finite, or of a length outside 1e-6 to 1e19, first at " +
                    pixelText(p.data, firstBadNormal, p.depth.width) + "; use --bad-pixels skip to accept them");
}

// R, G, B channel names of a layer in a part ("" layer: the top-level R, G, B).
std::vector<std::string> rgbChannels(const ExrPart& part, const std::string& layer, const ExrInfo& info,
                                     const char* what) {
    std::vector<std::string> names;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = layer.empty() ? c : layer + "." + c;
        if (part.findChannel(name) < 0) {
            throw FileError(info.path, std::string("no ") + what + " layer '" + layer + "' with R, G, B; layers found: " +
                                           joinedLayers(info));
        }
        names.push_back(name);
    }
    return names;
}

// The R, G, B of a role's layer, in whichever part holds it (a part per layer, as Nuke writes).
std::vector<ChannelRef> roleRgb(const LayerPlan& plan, Role role) {
    const LayerBinding* b = plan.find(role);
    if (!b) return {};
    std::vector<ChannelRef> refs;
    for (size_t c = 0; c < std::min<size_t>(3, b->channels.size()); ++c) refs.push_back({b->part, b->channels[c]});
    return refs;
}

// The map through plugin/io's one reader, its colour decisions in the report.
Image loadEnvironment(const std::string& path, const std::string& colourSpace, long long maxPixels,
                      FrameReport& report) {
    EnvironmentMap map = readEnvironmentMap(path, colourSpace, maxPixels);
    for (std::string& w : map.warnings) report.warnings.push_back(std::move(w));
    report.plan.push_back("environment colour: " + map.colourSpace + " (" + map.source + ") -> " +
                          colourManager().workingSpace());
    return std::move(map.rgb);
}

} // namespace

bool parse(const std::string& s, WriteMode& out) {
    if (s == "copy") out = WriteMode::Copy;
    else if (s == "new") out = WriteMode::New;
    else if (s == "append") out = WriteMode::Append;
    else return false;
    return true;
}

const char* toString(WriteMode m) { return m == WriteMode::New ? "new" : m == WriteMode::Append ? "append" : "copy"; }

bool normalsFromDepth(const FrameJob& job, const LayerPlan& plan) {
    return job.normalSpace == NormalSpace::Depth || !plan.find(Role::Normal);
}

std::string normalsSourceLine(const FrameJob& job, const LayerPlan& plan) {
    if (!normalsFromDepth(job, plan)) {
        const LayerBinding& b = *plan.find(Role::Normal);
        return "normals: layer '" + (b.layer.empty() ? b.channels[0] : b.layer) + "', " +
               toString(job.normalSpace.value_or(plan.normalSpace)) + " space";
    }
    return std::string("normals: reconstructed from depth (") +
           (job.normalSpace == NormalSpace::Depth ? "--normals depth" : "no normal layer") + ")";
}

void requestBounce(FrameJob& job) {
    job.writeIndirect = true;
    job.writeRelit = true;
}

std::string outLayerProblem(const std::string& name) {
    if (name.empty()) return "is empty";
    if (name.front() == '.' || name.back() == '.' || name.find("..") != std::string::npos)
        return "'" + name + "' has an empty part: a layer name is words between dots";
    constexpr size_t kMost = 200;
    if (name.size() > kMost)
        return "is " + std::to_string(name.size()) + " characters long; at most " + std::to_string(kMost) +
               " leaves a view and a channel room in OpenEXR's 255";
    return "";
}

bool readsColour(const FrameJob& job) {
    const std::string& method = job.settings.method;
    return methodOutputs(method, "do") || (methodOutputs(method, "gi") && (job.writeIndirect || job.writeRelit));
}

bool readsDeepColour(const FrameJob& job) {
    return readsDeepLayers(job.settings) && methodOutputs(job.settings.method, "gi") && (job.writeIndirect || job.writeRelit);
}

void warnIfDeepLayersIgnored(const FrameJob& job, FrameReport& report) {
    if (methodReads(job.settings.method, "deep") && !readsDeepLayers(job.settings))
        report.warnings.push_back("linear falloff (the default) ignores the deep layers: only the visible surface "
                                  "occludes; give --falloff none for the hidden surfaces to occlude (docs/deep.md)");
}

void noteDeepColour(bool coloured, FrameReport& report) {
    if (coloured) report.plan.push_back("deep colour: each hidden layer radiates its R, G, B");
    else report.warnings.push_back("the deep input has no R, G, B: its hidden layers send no light");
}

SsdoReads planSsdoReads(const FrameJob& job, const FramePasses& p) {
    SsdoReads r;
    if (!readsColour(job)) return r;  // AO alone reads no colour pass
    const ExrPart& part = p.info.parts[p.part];
    const bool bounce = job.writeIndirect || job.writeRelit;
    if (bounce) {
        if (job.bounceSource == "direct-diffuse") {
            r.radiance = roleRgb(p.plan, Role::DirectDiffuse);
            // Both of what is missing at once, where the file lacks an albedo too.
            const std::string relitToo = job.writeRelit && roleRgb(p.plan, Role::Albedo).empty()
                                             ? ", and GI alone (--out-layer gi=NAME in place of --bounce: relit "
                                               "needs an albedo)"
                                             : "";
            if (r.radiance.empty())
                throw FileError(job.input, (p.carried.empty() ? std::string("no direct-diffuse layer for the bounce; use "
                                                                            "--bounce-source beauty or --layer "
                                                                            "direct-diffuse=NAME")
                                                              : std::string("deep elements hold R, G, B and A only: the "
                                                                            "bounce needs --bounce-source beauty")) +
                                               relitToo);
            r.senderAlbedo = true;
        } else if (job.bounceSource == "beauty") {
            r.radiance = roleRgb(p.plan, Role::Beauty);
            if (r.radiance.empty()) throw FileError(job.input, "no beauty layer for the bounce");
        } else {
            for (const std::string& c : rgbChannels(part, job.bounceSource, p.info, "bounce source"))
                r.radiance.push_back({p.part, c});
        }
    }
    if ((bounce && r.senderAlbedo) || job.writeRelit || job.timesAlbedo) {
        r.albedo = roleRgb(p.plan, Role::Albedo);
        // --bounce asks for relit too; GI alone is named in its place (requestBounce).
        if (r.albedo.empty() && (job.writeRelit || job.timesAlbedo))
            throw FileError(job.input, "no albedo layer for the relit image (--bounce) or --times-albedo; use "
                                       "--layer albedo=NAME, or ask for GI alone with --out-layer gi=NAME in place "
                                       "of --bounce");
    }
    if (job.relitWithDirect) {
        r.directDiffuse = roleRgb(p.plan, Role::DirectDiffuse);
        if (r.directDiffuse.empty()) throw FileError(job.input, "no direct-diffuse layer for --relit-direct");
    }
    return r;
}

Image interleavePlanes(const std::vector<Image>& planes, size_t first, int channels) {
    Image out(planes[first].width, planes[first].height, channels);
    for (int c = 0; c < channels; ++c) {
        const Image& src = planes[first + c];
        for (size_t i = 0, n = (size_t)src.width * src.height; i < n; ++i) out.pixels[i * channels + c] = src.pixels[i];
    }
    return out;
}

std::string aoChannelName(const std::string& layer) {
    const size_t dot = layer.rfind('.');
    if (dot != std::string::npos && dot + 2 == layer.size() && std::isupper((unsigned char)layer.back())) return layer;
    return layer + ".Y";
}

namespace {

// The channel's pixel type as --inspect names it.
std::string pixelTypeName(const FramePasses& p, const ChannelRef& c) {
    const ExrPart& part = p.info.parts[c.part];
    const int i = part.findChannel(c.name);
    const Imf::PixelType t = i < 0 ? Imf::FLOAT : part.channels[i].type;
    return t == Imf::HALF ? "half" : t == Imf::UINT ? "uint" : "float";
}

// The depth the operator reads, from the stored depth (its statistics kept for --inspect,
// then decoded: --depth, --depth-range) or, with no depth layer, from the position pass and the
// camera.
void finishDepth(const FrameJob& job, FramePasses& p) {
    const float sky = job.skyDepth.value_or(p.plan.skyDepth);
    if (p.depthFromPosition) {
        p.depthEncoding = DepthEncoding::Planar;
        p.depth = depthFromPositions(p.position, resolveFrameCamera(job, p));
        p.depthStats = depthStatistics(p.depth, sky, pixelTypeName(p, channelRefs(*p.plan.find(Role::Position))[0]));
        return;
    }
    p.depthStats = depthStatistics(p.depth, sky, pixelTypeName(p, channelRefs(*p.plan.find(Role::Depth))[0]));
    if (p.depthEncoding == DepthEncoding::Inverse || p.depthEncoding == DepthEncoding::Normalized) p.depthStats.hint.clear();
    decodeDepth(p.depth, DepthDecoding{p.depthEncoding, job.depthRange});
}

// The colour passes' channels, checked to cover the depth's pixels.
void addSsdoChannels(const FrameJob& job, const FramePasses& p, const SsdoReads& ssdo, std::vector<ChannelRef>& wanted) {
    for (const std::vector<ChannelRef>* rgb : {&ssdo.radiance, &ssdo.albedo, &ssdo.directDiffuse}) {
        if (!rgb->empty() && p.info.parts[rgb->front().part].dataWindow != p.data)
            throw FileError(job.input, "the colour pass '" + rgb->front().name + "' covers a different data window than the depth");
        wanted.insert(wanted.end(), rgb->begin(), rgb->end());
    }
}

// The passes obscura computes from are read at full resolution only.
void requireFullResolution(const FrameJob& job, const FramePasses& p, const std::vector<ChannelRef>& wanted) {
    for (const ChannelRef& c : wanted) {
        const ExrPart& owner = p.info.parts[c.part];
        const int i = owner.findChannel(c.name);
        if (i >= 0 && (owner.channels[i].xSampling != 1 || owner.channels[i].ySampling != 1))
            throw FileError(job.input, "channel '" + c.name + "' is subsampled (" +
                        std::to_string(owner.channels[i].xSampling) + "x" + std::to_string(owner.channels[i].ySampling) +
                        "); obscura reads the passes it computes from at full resolution only");
    }
}

FramePasses loadPasses(const FrameJob& job, const std::vector<int>& rawParts, std::vector<StageTiming>* stages, bool alwaysReadPosition,
                       const ExrInfo* headers) {
    StageTimer timer{stages, "read"};
    FramePasses p;
    // Deep parts are refused unless appending, which copies them (the caller's headers are checked).
    p.info = headers ? *headers : readExrInfo(job.input, job.maxPixels, job.write == WriteMode::Append);
    const std::vector<std::string> views = viewsToProcess(job, p.info);
    p.fileViews = fileViews(p.info);
    p.view = views.empty() ? "" : views.front();
    p.plan = planViewLayers(job, p.info, p.view);
    const LayerBinding* depth = p.plan.find(Role::Depth);
    const LayerBinding* position = p.plan.find(Role::Position);
    if (!depth && !position && !p.view.empty())
        throw FileError(job.input, "view '" + p.view + "' has no depth layer; its layers: " +
                                       joinedLayers(viewOfFile(p.info, p.view).info));
    if (!depth && !position) requireRoles(p.plan, p.info, {Role::Depth});
    p.depthFromPosition = !depth;  // a position pass and a camera, no depth: the depth from them
    p.depthEncoding = job.depthEncoding.value_or(p.plan.depthKind == DepthKind::Radial ? DepthEncoding::Radial
                                                                                       : DepthEncoding::Planar);
    if (depth) requireDecodable(DepthDecoding{p.depthEncoding, job.depthRange});
    p.normalsFromDepth = normalsFromDepth(job, p.plan);
    const LayerBinding* normal = p.normalsFromDepth ? nullptr : p.plan.find(Role::Normal);
    p.part = depth ? depth->part : position->part;
    const ExrPart& part = p.info.parts[p.part];
    p.display = part.displayWindow;
    p.data = part.dataWindow;
    p.pixelAspect = part.header.pixelAspectRatio();
    if (p.data.empty()) throw FileError(job.input, "the data window is empty (0 pixels)");
    auto samePixels = [&](const LayerBinding& b) {
        if (p.info.parts[b.part].dataWindow != p.data)
            throw FileError(job.input, std::string("the ") + roleName(b.role) + " layer '" + b.layer +
                        "' covers a different data window than the depth");
    };
    std::vector<ChannelRef> wanted = depth ? channelRefs(*depth) : std::vector<ChannelRef>{};
    if (normal) {
        samePixels(*normal);
        for (const ChannelRef& c : channelRefs(*normal)) wanted.push_back(c);
    }
    const bool readPosition =
        position && (p.depthFromPosition || (alwaysReadPosition ? p.info.parts[position->part].dataWindow == p.data
                                                                : !cameraFullyGiven(job)));
    if (readPosition) {
        samePixels(*position);
        for (const ChannelRef& c : channelRefs(*position)) wanted.push_back(c);
    }
    if (!job.referenceLayer.empty())
        wanted.push_back({p.part, findReferenceChannel(part, job.referenceLayer, p.info)});
    const SsdoReads ssdo = planSsdoReads(job, p);
    addSsdoChannels(job, p, ssdo, wanted);
    requireFullResolution(job, p, wanted);
    // p.raw always gets the file's parts: a copy whose layers all go to a part of their own keeps
    // none raw, and still writes every part.
    std::vector<Image> planes = readExrChannels(job.input, p.info, wanted, rawParts, &p.raw);
    size_t next = 0;
    if (depth) p.depth = std::move(planes[next++]);
    if (normal) {
        p.normal = interleavePlanes(planes, next, 3);
        next += 3;
    }
    if (readPosition) {
        p.position = interleavePlanes(planes, next, 3);
        next += 3;
    }
    if (!job.referenceLayer.empty()) p.reference = std::move(planes[next++]);
    for (auto [names, image] : {std::pair{&ssdo.radiance, &p.radiance}, std::pair{&ssdo.albedo, &p.albedo},
                                std::pair{&ssdo.directDiffuse, &p.directDiffuse}}) {
        if (names->empty()) continue;
        *image = interleavePlanes(planes, next, 3);
        next += 3;
    }
    finishDepth(job, p);
    return p;
}

} // namespace

FramePasses loadFramePasses(const FrameJob& job, const std::vector<int>& rawParts, std::vector<StageTiming>* stages,
                             bool alwaysReadPosition, const ExrInfo* headers) {
    return blameInput(job.input, [&] { return loadPasses(job, rawParts, stages, alwaysReadPosition, headers); });
}

Camera resolveFrameCamera(const FrameJob& job, const FramePasses& p) {
    CameraRequest request = job.camera;
    request.sidecarPath = sidecarFor(job);
    const ConstPlane position = p.position.empty() ? ConstPlane{} : p.position.view();
    return resolveCamera(request, &p.info.parts[p.part].header, position, p.data, p.display, p.pixelAspect);
}

DeepLayers readJobDeepLayers(const FrameJob& job, const FramePasses& p, bool windowsOnly) {
    return blameInput(job.deepInput, [&] {
        if (windowsOnly) return readDeepLayerWindows(job.deepInput, p.plan.deep, job.maxPixels);
        return readDeepLayers(job.deepInput, job.settings.deepLayers, p.plan.deep, job.maxPixels, readsDeepColour(job));
    });
}

namespace {

// The deep file's surfaces over the flat passes' data window, or an empty image without one; their
// colours into `colour` when the bounce reads them and the file has some.
Image readDeepInput(const FrameJob& job, const FramePasses& p, Image& colour, FrameReport& report) {
    if (job.deepInput.empty()) return Image();
    StageTimer timer{&report.stages, "deep"};
    const bool used = readsDeepLayers(job.settings);  // else only the header is checked: the layers would go unused
    DeepLayers deep = readJobDeepLayers(job, p, !used);
    return blameInput(job.deepInput, [&] {
        if (deep.display != p.display)
            throw Error("its display window (" + std::to_string(deep.display.width()) + "x" +
                        std::to_string(deep.display.height()) + ") is not the flat passes' (" +
                        std::to_string(p.display.width()) + "x" + std::to_string(p.display.height()) + ")");
        if (!used) {
            report.plan.push_back("deep: " + job.deepInput + " not read (its layers are used with falloff none only)");
            warnIfDeepLayersIgnored(job, report);
            return Image();
        }
        report.deepLayers = deep.layers;
        report.deepEmptyPixels = deep.emptyPixels;
        report.deepDroppedSamples = deep.droppedSamples;
        report.deepUnsortedPixels = deep.unsortedPixels;
        report.deepTruncatedPixels = deep.truncatedPixels;
        report.plan.push_back("deep: " + std::to_string(deep.layers) + " layer(s) from " + job.deepInput);
        if (deep.droppedSamples)
            report.warnings.push_back(std::to_string(deep.droppedSamples) + " deep samples with NaN, -inf or non-positive Z skipped");
        if (deep.unsortedPixels)
            report.warnings.push_back(std::to_string(deep.unsortedPixels) + " deep pixels with unsorted samples sorted by Z");
        if (readsDeepColour(job)) noteDeepColour(!deep.colour.empty(), report);
        if (!deep.colour.empty()) colour = deepPlanesOver(std::move(deep.colour), deep.data, p.data, 0.0f);
        return deepPlanesOver(std::move(deep), p.data);
    });
}

// Every destination is checked before any work, so a bad one leaves nothing behind.
void checkDestinations(const FrameJob& job) {
    if (job.output.empty()) throw Error("no output file: give -o OUTPUT.exr");
    if (!job.inPlace && sameFile(job.input, job.output))
        throw FileError(job.input, "refusing to overwrite the input (use --in-place)");
    if (job.inPlace && job.write == WriteMode::New)
        throw Error("--write new cannot replace the input in place: the output holds only the new layers");
    requireWritableDestination(job.output);
    if (!job.previewPath.empty()) requireWritableDestination(job.previewPath);
}

// The camera and the conventions (flags over the preset), then the pixels checked against them.
void resolveConventions(const FrameJob& job, FramePasses& p, FrameReport& report) {
    {
        StageTimer timer{&report.stages, "camera"};
        report.camera = resolveFrameCamera(job, p);
    }
    report.depthKind = decodedKind(p.depthEncoding);
    report.depthEncoding = p.depthEncoding;
    if (p.depthFromPosition) report.plan.push_back("depth: from the position pass and the camera (no depth layer)");
    report.normalSpace = p.normalsFromDepth ? NormalSpace::Depth : job.normalSpace.value_or(p.plan.normalSpace);
    if (p.normalsFromDepth) report.plan.push_back(normalsSourceLine(job, p.plan));
    report.skyDepth = job.skyDepth.value_or(p.plan.skyDepth);
    // Left-handed camera-space normals (+z forward) become OpenGL's (-z forward).
    if (p.plan.normalsLeftHanded && report.normalSpace == NormalSpace::Camera && !job.normalSpace)
        for (size_t i = 2; i < p.normal.pixels.size(); i += 3) p.normal.pixels[i] = -p.normal.pixels[i];
    validatePixels(job, p, report.skyDepth, report);
}

// SSDO's light: the colour passes in the working space, the bounce source, the map.
void addSsdoInputs(const FrameJob& job, FramePasses& p, Settings& settings, OperatorInputs& in, Image& environment,
                   FrameReport& report) {
    const SsdoReads reads = planSsdoReads(job, p);
    settings.bounce = job.writeIndirect || job.writeRelit;
    settings.zUp = job.zUp.value_or(p.plan.preset == "blender");  // Blender's world is Z-up
    if (!p.radiance.empty() || !p.albedo.empty() || !p.directDiffuse.empty()) {
        // Colour passes enter the working space of the OpenColorIO config; data passes stay as they are.
        const ColourManager& cm = colourManager();
        const ColourSpaceGuess space = cm.detectColourSpace(p.info.parts[p.part].header, job.colourSpace);
        if (!space.warning.empty()) report.warnings.push_back(space.warning);
        for (Image* img : {&p.radiance, &p.albedo, &p.directDiffuse})
            if (!img->empty()) cm.toWorkingSpace(*img, space.name);
        report.plan.push_back("colour: " + space.name + " (" + space.source + ") -> " + cm.workingSpace());
        report.inputColourSpace = space.name;
        // The light, relit and --times-albedo read them: a NaN, an infinity or a huge value is black
        // there (core/light_inputs.h), and said so here, by the layer's role.
        for (auto [img, role] : {std::pair{&p.radiance, "the bounce source"}, {&p.albedo, "the albedo"},
                                 {&p.directDiffuse, "the direct diffuse layer"}})
            if (const long long bad = img->empty() ? 0 : zeroUnphysical(img->view()))
                report.warnings.push_back(unphysicalNote(role, bad));
        in.lightChecked = true;
    }
    if (!p.radiance.empty()) in.radiance = p.radiance.view();
    if (reads.senderAlbedo && !p.albedo.empty()) in.albedo = p.albedo.view();
    if (!job.envPath.empty()) {  // loaded only when the method lights with it
        StageTimer timer{&report.stages, "environment"};
        environment = loadEnvironment(job.envPath, job.envColourSpace, job.maxPixels, report);
        in.environment = &environment;
        report.plan.push_back("environment " + job.envPath + " (" + std::to_string(environment.width) + "x" +
                              std::to_string(environment.height) + ")");
    }
    report.plan.push_back(settings.method + (settings.bounce ? " + bounce from " + job.bounceSource : " (no bounce)"));
}

// What the operator computes from: the passes' planes, the conventions and, as the method asks,
// the deep layers (and their colours) and SSDO's light (owned by `deep`, `deepColour` and
// `environment`, which outlive the call).
OperatorInputs operatorInputs(const FrameJob& job, FramePasses& p, Settings& settings, Image& deep, Image& deepColour,
                              Image& environment, FrameReport& report) {
    OperatorInputs in;
    in.displayWindow = p.display;
    in.dataWindow = p.data;
    in.depth = p.depth.view();
    if (!p.normalsFromDepth) in.normal = p.normal.view();
    in.depthKind = report.depthKind;
    in.normalSpace = report.normalSpace;
    in.camera = report.camera;
    settings.skyDepth = report.skyDepth;
    if (deep.empty()) deep = readDeepInput(job, p, deepColour, report);  // deep elements bring their merge's
    if (!deep.empty() && readsDeepLayers(settings)) in.deepLayers = deep.view();
    if (!deepColour.empty() && readsDeepColour(job)) in.deepColour = deepColour.view();
    if (readsColour(job)) addSsdoInputs(job, p, settings, in, environment, report);
    else report.plan.push_back(settings.method);
    return in;
}

// --reference: the AO against the render's own layer, over surface pixels.
void compareWithReference(const FramePasses& p, const OperatorOutputs& out, FrameReport& report) {
    if (p.reference.empty()) return;
    const float sky = report.skyDepth;
    report.reference = compareChannels(std::as_const(out.ao).view(), 0, std::as_const(p.reference).view(), 0,
                                       [&](int x, int y) { return isSurface(*p.depth.at(x, y), sky); });
}

// What the depth's values say, where the run would otherwise give an answer without a word: no
// surface at all (AO 1 everywhere), or values that look like 1/Z or a normalised depth.
void warnOfTheDepth(const FramePasses& p, FrameReport& report) {
    const DepthStatistics& s = p.depthStats;
    if (s.skyShare >= 1.0)
        report.warnings.push_back("the depth holds no surface: every pixel is 0, NaN, infinite or at or beyond the sky "
                                  "depth, so the AO is 1 everywhere; check the depth layer (--layer depth=NAME) and --depth");
    else if (!s.hint.empty())
        report.warnings.push_back("the depth is read as a distance, though it looks like " + s.hint);
}

} // namespace

int copyLayersPart(const FrameJob& job, const ExrInfo& info, int depthPart, const std::string& view) {
    // The AO's name in this view: a part of the view's own holds it as it is (so does an earlier
    // run's part for that view, which carries its view attribute), else the view is in the name.
    const std::string ownView = partView(info.parts.at(depthPart));
    std::string ao = aoChannelName(job.aoLayer);
    const std::vector<std::string> views = fileViews(info);
    const auto at = std::find(views.begin(), views.end(), view);
    if (!view.empty() && ownView.empty() && at != views.end()) ao = nameInView(ao, views, (size_t)(at - views.begin()));
    const Box2i data = info.parts[depthPart].dataWindow;  // the new layers' pixels
    for (size_t p = 0; p < info.parts.size(); ++p) {
        const ExrPart& part = info.parts[p];
        if (partView(part) == ownView && part.dataWindow == data && part.findChannel(ao) >= 0 && layersGoInPlace(part))
            return (int)p;
    }
    return layersGoInPlace(info.parts[depthPart]) ? depthPart : -1;
}

namespace {

// The parts of the input a copy writes new layers into (copyLayersPart, for each processed
// view's depth part, or its position part without a depth). Those are decoded whole; of the
// others only the passes read, and they are copied chunk for chunk.
std::vector<int> partsTakingLayers(const FrameJob& job, const ExrInfo& info, const std::vector<std::string>& views) {
    std::vector<int> parts;
    for (const std::string& view : views.empty() ? std::vector<std::string>{""} : views) {
        const LayerPlan plan = planViewLayers(job, info, view);
        const LayerBinding* b = plan.find(Role::Depth) ? plan.find(Role::Depth) : plan.find(Role::Position);
        const int into = b ? copyLayersPart(job, info, b->part, view) : -1;
        if (into >= 0 && std::find(parts.begin(), parts.end(), into) == parts.end()) parts.push_back(into);
    }
    return parts;
}

// Copy's parts to keep raw, the chunk tables checked before any work: a file whose table
// OpenEXR would rebuild has every part decoded and encoded again, as copy always did.
std::vector<int> copiedRawParts(const FrameJob& job, const ExrInfo& info, const std::vector<std::string>& views,
                                bool& copyChunks, bool& checked) {
    std::vector<int> parts = partsTakingLayers(job, info, views);
    copyChunks = true;
    checked = false;
    if (parts.size() == info.parts.size()) return parts;  // every part taken: nothing copied raw
    try {
        checkChunkTables(info.path, info);
        checked = true;
    } catch (const Error&) {
        copyChunks = false;
        parts.clear();
        for (int p = 0; p < (int)info.parts.size(); ++p) parts.push_back(p);
    }
    return parts;
}

// One view's (or the merged deep elements') passes through the operator. `merged`: deep
// elements, whose surfaces are the deep input and whose per-element AO goes to `elementAo`.
ViewResult computeView(const FrameJob& job, FramePasses passes, FrameReport& report,
                       DeepElementsInput* merged = nullptr, std::vector<NewChannel>* elementAo = nullptr) {
    ViewResult r{std::move(passes), {}};
    FramePasses& p = r.passes;
    resolveConventions(job, p, report);
    warnOfTheDepth(p, report);
    Settings settings = job.settings;
    Image deep = merged ? std::move(merged->layers) : Image{}, environment;
    Image deepColour = merged ? std::move(merged->colour) : Image{};
    const OperatorInputs in = operatorInputs(job, p, settings, deep, deepColour, environment, report);
    {
        StageTimer timer{&report.stages, "compute"};
        r.out = runOperator(in, settings);
    }
    report.stats = r.out.stats;
    for (const std::string& note : r.out.stats.notes) report.warnings.push_back(note);
    compareWithReference(p, r.out, report);
    if (merged) *elementAo = elementAoLayers(job, in, settings, *merged, report);
    return r;
}

// A later view's report into the first's: its plan and warnings named by the view (a warning
// the first view gave in the same words, such as the file's colour space, is not repeated), its
// stages added to the first's of the same name, its pixels counted.
void mergeViewReport(const std::string& view, FrameReport& from, FrameReport& into) {
    for (const std::string& line : from.plan) into.plan.push_back("view " + view + ": " + line);
    for (const std::string& line : from.warnings)
        if (std::find(into.warnings.begin(), into.warnings.end(), line) == into.warnings.end())
            into.warnings.push_back("view " + view + ": " + line);
    for (const StageTiming& t : from.stages) {
        auto same = std::find_if(into.stages.begin(), into.stages.end(), [&](const StageTiming& s) { return s.name == t.name; });
        if (same == into.stages.end()) into.stages.push_back(t);
        else same->seconds += t.seconds;
    }
    into.stats.pixels += from.stats.pixels;
    into.stats.skyPixels += from.stats.skyPixels;
    into.stats.invalidDepthPixels += from.stats.invalidDepthPixels;
    into.stats.zeroNormalPixels += from.stats.zeroNormalPixels;
    into.nonUnitNormalPixels += from.nonUnitNormalPixels;
}

// A view of the file left out because its own channels hold no depth (nor position) is said, with
// what it holds, while the others get their AO: a stereo plate with one eye unprocessed would
// otherwise look done. A file none of whose views has a depth runs as one image, unsaid.
void warnOfViewsWithoutDepth(const FrameJob& job, const ExrInfo& info, FrameReport& report) {
    if (!job.views.empty() || report.views.empty()) return;
    for (const std::string& v : fileViews(info))
        if (std::find(report.views.begin(), report.views.end(), v) == report.views.end())
            report.warnings.push_back("view '" + v + "' has no depth of its own and gets no AO; its layers: " +
                                      joinedLayers(viewOfFile(info, v).info));
}

// A flat input with no deep file: the per-element AO, an output it cannot have, is refused
// before anything is written; the deep layers, a setting with no effect, are said to be unread.
void checkDeepSettingsRead(const FrameJob& job, FrameReport& report) {
    if (!job.deepInput.empty()) return;
    if (job.perElementAo)
        throw FileError(job.input, "holds no deep data: the per-element AO is made of deep elements (docs/deep.md)");
    if (job.settings.deepLayers != Settings{}.deepLayers)
        report.warnings.push_back("the deep layers setting is read with deep input only; the input is flat");
}

FrameReport runJob(const FrameJob& job) {
    checkDestinations(job);
    setExrThreads(job.settings.threads);
    setColourThreads(job.settings.threads);
    FrameReport report;
    report.sources = stampsOf(filesReadBy(job));  // before reading: a file changed meanwhile leaves the frame stale
    std::vector<ViewResult> results;
    std::vector<NewChannel> elementAo;
    // The input's headers, read once for the frame (each read opens and checks the file).
    std::optional<ExrInfo> headers;
    if (job.deepElements.empty()) headers = readExrInfo(job.input, job.maxPixels, true);
    const std::vector<std::string> elements = deepElementsOf(job, headers ? &*headers : nullptr);
    if (!elements.empty()) {
        DeepElementsInput merged;
        FramePasses p = loadDeepElements(job, elements, merged, report);
        results.push_back(computeView(job, std::move(p), report, &merged, &elementAo));
    } else {
        if (job.write != WriteMode::Append) requireFlatParts(*headers);
        checkDeepSettingsRead(job, report);
        report.views = viewsToProcess(job, *headers);
        warnOfViewsWithoutDepth(job, *headers, report);
        bool copyChunks = true, tablesChecked = false;
        const std::vector<int> copied = job.write == WriteMode::Copy
                                            ? copiedRawParts(job, *headers, report.views, copyChunks, tablesChecked)
                                            : std::vector<int>{};
        if (!copyChunks)
            report.warnings.push_back("the input's chunk tables are damaged (OpenEXR rebuilds them as it reads): copy "
                                      "decodes and encodes every part again, so a lossy part loses more and a "
                                      "mip-mapped part keeps its level 0 only; --write new is unaffected");
        // Every view processed runs on its own passes; one camera serves them all unless each
        // view's part carries its own. The first view's read keeps the parts a copy writes into.
        for (size_t v = 0; v < std::max<size_t>(1, report.views.size()); ++v) {
            FrameJob viewJob = job;
            if (!report.views.empty()) viewJob.views = {report.views[v]};
            FrameReport viewReport;
            FrameReport& into = v == 0 ? report : viewReport;
            const std::vector<int> raw = v == 0 ? copied : std::vector<int>{};
            FramePasses passes = loadFramePasses(viewJob, raw, &into.stages, false, &*headers);
            passes.raw.copyChunks = copyChunks;
            passes.raw.chunkTablesChecked = tablesChecked;
            results.push_back(computeView(viewJob, std::move(passes), into));
            if (v > 0) mergeViewReport(report.views[v], viewReport, report);
        }
    }
    writeFrameOutputs(job, results, report, std::move(elementAo));
    if (!job.previewPath.empty()) {
        StageTimer timer{&report.stages, "preview"};
        report.plan.push_back(writeFramePreview(job, results[0].passes, results[0].out, readsColour(job)));
    }
    return report;
}

} // namespace

FrameReport runFrameJob(const FrameJob& job) {
    return blameInput(job.input, [&] { return runJob(job); });
}

} // namespace obscura
