#include "io/frame_job.h"
#include "io/environment_map.h"

#include "base/error.h"
#include "core/methods.h"
#include "io/colour.h"
#include "io/deep_file.h"
#include "io/exr_append.h"
#include "io/oiio_module.h"
#include "io/preview.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <utility>

#include <signal.h>
#include <unistd.h>

#include <cerrno>

namespace obscura {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct StageTimer {
    std::vector<StageTiming>* stages;
    std::string name;
    Clock::time_point t0 = Clock::now();
    ~StageTimer() {
        if (stages) stages->push_back({name, std::chrono::duration<double>(Clock::now() - t0).count()});
    }
};

// The channel a --reference LAYER names: the exact channel, or the first of LAYER.{R,Y,V,Z,A,...}.
std::string findReferenceChannel(const ExrPart& part, const std::string& layer, const ExrInfo& info) {
    if (part.findChannel(layer) >= 0) return layer;
    for (const char* suffix : {"R", "Y", "V", "Z", "X", "A", "r", "y"}) {
        const std::string name = layer + "." + suffix;
        if (part.findChannel(name) >= 0) return name;
    }
    std::string found;
    for (const std::string& l : listLayers(info)) found += (found.empty() ? "" : "; ") + l;
    throw FileError(info.path, "no reference layer '" + layer + "'; layers found: " + found);
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
    const bool lens = job.camera.fovDeg || job.camera.orthoWidth;
    const bool pose = job.camera.cameraToWorld || job.normalSpace == NormalSpace::Camera;
    return (lens && pose) || !sidecarFor(job).empty();
}

bool isSurface(float d, float sky) { return d > 0.0f && d < sky; }

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
        if (!isSurface(d, sky)) continue;
        ++surface;
        const float* nv = &p.normal.pixels[i * 3];
        const float len2 = nv[0] * nv[0] + nv[1] * nv[1] + nv[2] * nv[2];
        if (!(len2 > 1e-12f && std::isfinite(len2))) {
            if (len2 == 0.0f) ++zeroNormal;
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
                    " surface pixel(s) have a zero or non-finite normal, first at " +
                    pixelText(p.data, firstBadNormal, p.depth.width) + "; use --bad-pixels skip to accept them");
}

// R, G, B channel names of a layer in a part ("" layer: the top-level R, G, B).
std::vector<std::string> rgbChannels(const ExrPart& part, const std::string& layer, const ExrInfo& info,
                                     const char* what) {
    std::vector<std::string> names;
    for (const char* c : {"R", "G", "B"}) {
        const std::string name = layer.empty() ? c : layer + "." + c;
        if (part.findChannel(name) < 0) {
            std::string found;
            for (const std::string& l : listLayers(info)) found += (found.empty() ? "" : "; ") + l;
            throw FileError(info.path, std::string("no ") + what + " layer '" + layer + "' with R, G, B; layers found: " +
                        found);
        }
        names.push_back(name);
    }
    return names;
}

std::vector<std::string> roleRgb(const LayerPlan& plan, Role role) {
    const LayerBinding* b = plan.find(role);
    if (!b) return {};
    return {b->channels.begin(), b->channels.begin() + std::min<size_t>(3, b->channels.size())};
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

// Three channels <layer>.R/G/B of an RGB image.
void addRgbLayer(std::vector<NewChannel>& add, int part, const std::string& layer, const Image& rgb, Imf::PixelType type) {
    for (int c = 0; c < 3; ++c) {
        NewChannel ch;
        ch.part = part;
        ch.name = layer + "." + "RGB"[c];
        ch.plane = Image(rgb.width, rgb.height, 1);
        for (size_t i = 0; i < ch.plane.pixels.size(); ++i) ch.plane.pixels[i] = rgb.pixels[3 * i + c];
        ch.type = type;
        add.push_back(std::move(ch));
    }
}

// DO or GI as its layer holds it: irradiance E, or with --times-albedo albedo x E / pi.
Image ssdoLayerImage(const FrameJob& job, const FramePasses& p, const Image& e) {
    Image r = e;
    if (job.timesAlbedo)
        for (size_t i = 0; i < r.pixels.size(); ++i) r.pixels[i] *= p.albedo.pixels[i] * (float)(1.0 / M_PI);
    return r;
}

// albedo x (DO + GI) / pi, plus the render's direct diffuse light with --relit-direct.
Image relitImage(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out) {
    Image relit = out.directional;
    for (size_t i = 0; i < relit.pixels.size(); ++i) {
        relit.pixels[i] = p.albedo.pixels[i] * (relit.pixels[i] + out.indirect.pixels[i]) * (float)(1.0 / M_PI);
        if (job.relitWithDirect) relit.pixels[i] += p.albedo.pixels[i] * p.directDiffuse.pixels[i];
    }
    return relit;
}

// DO, GI and relit as the request asks. Irradiance E by default; --times-albedo writes
// albedo x E / pi, the outgoing radiance of the diffuse receiver. relit = albedo (DO + GI) / pi
// (+ albedo x direct diffuse), the units a renderer's beauty uses for diffuse light.
std::vector<std::string> addSsdoLayers(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out,
                                       int outPart, Imf::PixelType type, std::vector<NewChannel>& add,
                                       std::vector<StringAttribute>& attrs) {
    std::vector<std::string> layers;
    auto emit = [&](const std::string& layer, const Image& rgb) {
        addRgbLayer(add, outPart, layer, rgb, type);
        layers.push_back(layer);
        attrs.push_back({outPart, "obscura/" + layer + "/units", job.timesAlbedo ? "radiance (albedo E / pi)" : "irradiance E"});
    };
    if (job.writeDirectional) emit(job.doLayer, ssdoLayerImage(job, p, out.directional));
    if (job.writeIndirect) emit(job.giLayer, ssdoLayerImage(job, p, out.indirect));
    if (job.writeRelit) {
        addRgbLayer(add, outPart, job.relitLayer, relitImage(job, p, out), type);
        layers.push_back(job.relitLayer);
    }
    return layers;
}

// The part of a data-window plane inside the display window (all of it when they do not meet).
Image displayPart(const Image& img, const FramePasses& p) {
    const Box2i crop = intersect(p.data, p.display).empty() ? p.data : intersect(p.data, p.display);
    Image part(crop.width(), crop.height(), img.channels);
    for (int y = 0; y < crop.height(); ++y)
        for (int x = 0; x < crop.width(); ++x)
            for (int c = 0; c < img.channels; ++c)
                part.at(x, y)[c] = img.at(x + crop.x0 - p.data.x0, y + crop.y0 - p.data.y0)[c];
    return part;
}

// --preview: the display window's part of the frame (overscan is not part of it) of the AO, or
// for ssdo of the relit layer when it is written, else of the DO layer, converted from the
// working space to sRGB's primaries where the config has them. AO is a fraction, shown as it
// is; light has no fixed scale (a sunlit floor is far above 1), so it is exposed automatically
// unless --preview-exposure says how. Returns the report's plan line.
std::string writeFramePreview(const FrameJob& job, const FramePasses& p, const OperatorOutputs& out, bool ssdo) {
    const Image colour = !ssdo ? Image() : job.writeRelit ? relitImage(job, p, out) : ssdoLayerImage(job, p, out.directional);
    Image view = displayPart(ssdo ? colour : out.ao, p);
    if (ssdo) {
        const ColourManager& cm = colourManager();
        if (const std::string rec709 = cm.resolve("lin_rec709"); !rec709.empty()) cm.convert(view, cm.workingSpace(), rec709);
    }
    const float ev = job.previewExposure ? *job.previewExposure : ssdo ? autoExposureEv(view) : 0.0f;
    writePreviewPng(job.previewPath, view, ev);
    char line[160];
    std::snprintf(line, sizeof line, "preview: %s, exposure %+.2f EV%s", !ssdo ? "AO" : job.writeRelit ? "relit" : "DO",
                  ev, job.previewExposure || !ssdo ? "" : " (auto: the 99th percentile of the largest channel at 0.8)");
    return line;
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

std::string describeWrite(const FrameJob& job, const ExrInfo& info, int part) {
    const Imf::Compression in = info.parts.at(part).header.compression();
    const Imf::Compression out = losslessFor(in);
    std::string codec = compressionName(out);
    if (out != in) codec += " (the input's " + compressionName(in) + " is lossy)";
    if (job.write == WriteMode::New) return "new: only the new layers, " + codec;
    if (job.write == WriteMode::Append)
        return "append: the input's parts copied as compressed chunks, the new layers in a part of their own ('" +
               layersPartName(info) + "'), " + codec;
    if (out != in) return "copy: the input plus the new layers in a part of their own ('" + layersPartName(info) + "'), " + codec;
    return "copy: the input plus the new layers, " + codec;
}

void requestBounce(FrameJob& job) {
    job.writeIndirect = true;
    job.writeRelit = true;
}

SsdoReads planSsdoReads(const FrameJob& job, const FramePasses& p) {
    SsdoReads r;
    if (!methodOutputs(job.settings.method, "do")) return r;  // AO alone reads no colour pass
    const ExrPart& part = p.info.parts[p.part];
    const bool bounce = job.writeIndirect || job.writeRelit;
    if (bounce) {
        if (job.bounceSource == "direct-diffuse") {
            r.radiance = roleRgb(p.plan, Role::DirectDiffuse);
            if (r.radiance.empty())
                throw FileError(job.input, "no direct-diffuse layer for the bounce; use --bounce-source beauty "
                            "or --layer direct-diffuse=NAME");
            r.senderAlbedo = true;
        } else if (job.bounceSource == "beauty") {
            r.radiance = roleRgb(p.plan, Role::Beauty);
            if (r.radiance.empty()) throw FileError(job.input, "no beauty layer for the bounce");
        } else {
            r.radiance = rgbChannels(part, job.bounceSource, p.info, "bounce source");
        }
    }
    if ((bounce && r.senderAlbedo) || job.writeRelit || job.timesAlbedo) {
        r.albedo = roleRgb(p.plan, Role::Albedo);
        if (r.albedo.empty() && (job.writeRelit || job.timesAlbedo))
            throw FileError(job.input, "no albedo layer (needed for relit or --times-albedo); use --layer albedo=NAME, "
                                       "or --out-layer gi=NAME for the bounce without relit");
    }
    if (job.relitWithDirect) {
        r.directDiffuse = roleRgb(p.plan, Role::DirectDiffuse);
        if (r.directDiffuse.empty()) throw FileError(job.input, "no direct-diffuse layer for --relit-direct");
    }
    return r;
}

void requireOutputDirectory(const std::string& path) {
    const fs::path dir = fs::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw FileError(path, "cannot write: directory '" + dir.string() + "' does not exist");
}

Image interleavePlanes(const std::vector<Image>& planes, size_t first, int channels) {
    Image out(planes[first].width, planes[first].height, channels);
    for (int c = 0; c < channels; ++c) {
        const Image& src = planes[first + c];
        for (size_t i = 0, n = (size_t)src.width * src.height; i < n; ++i) out.pixels[i * channels + c] = src.pixels[i];
    }
    return out;
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    auto fail = [&] {
        const int err = errno;
        std::remove(tmp.c_str());
        return FileError(path, std::string("cannot write: ") + std::strerror(err));
    };
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text << "\n";
        if (!f.good()) throw fail();
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw fail();
}

std::string frameFailureJson(const FrameJob& job, int frame, const std::string& error) {
    const nlohmann::json j = {{"obscura", OBSCURA_VERSION_STRING}, {"frame", frame}, {"input", job.input},
                              {"output", job.output}, {"error", error}};
    return j.dump(2);
}

std::vector<std::string> atomicWriteTemps(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string prefix = p.filename().string() + ".tmp-";
    std::vector<std::string> found;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
            name.find_first_not_of("0123456789", prefix.size()) == std::string::npos)
            found.push_back((p.parent_path() / name).string());
    }
    std::sort(found.begin(), found.end());
    return found;
}

int removeStaleTemps(const std::string& path) {
    int removed = 0;
    for (const std::string& tmp : atomicWriteTemps(path)) {
        const long pid = std::atol(tmp.c_str() + tmp.rfind('-') + 1);
        // kill(pid, 0) probes without signalling: ESRCH means no such process here.
        if (pid > 0 && pid != (long)::getpid() && ::kill((pid_t)pid, 0) == 0) continue;
        if (pid > 0 && pid != (long)::getpid() && errno != ESRCH) continue;
        if (std::remove(tmp.c_str()) == 0) ++removed;
    }
    return removed;
}

std::string aoChannelName(const std::string& layer) {
    const size_t dot = layer.rfind('.');
    if (dot != std::string::npos && dot + 2 == layer.size() && std::isupper((unsigned char)layer.back())) return layer;
    return layer + ".Y";
}

namespace {
FramePasses loadPasses(const FrameJob& job, bool keepAll, std::vector<StageTiming>* stages, bool alwaysReadPosition) {
    StageTimer timer{stages, "read"};
    FramePasses p;
    p.info = readExrInfo(job.input, job.maxPixels, job.write == WriteMode::Append);  // deep parts: copied
    p.plan = planLayers(p.info, job.preset, job.layerOverrides);
    requireRoles(p.plan, p.info, {Role::Depth, Role::Normal});
    const LayerBinding& depth = *p.plan.find(Role::Depth);
    const LayerBinding& normal = *p.plan.find(Role::Normal);
    p.part = depth.part;
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
    samePixels(normal);

    std::vector<ChannelRef> wanted = channelRefs(depth);
    for (const ChannelRef& c : channelRefs(normal)) wanted.push_back(c);
    const LayerBinding* position = p.plan.find(Role::Position);
    const bool readPosition = position && (alwaysReadPosition ? p.info.parts[position->part].dataWindow == p.data
                                                              : !cameraFullyGiven(job));
    if (readPosition) {
        samePixels(*position);
        for (const ChannelRef& c : channelRefs(*position)) wanted.push_back(c);
    }
    if (!job.referenceLayer.empty())
        wanted.push_back({p.part, findReferenceChannel(part, job.referenceLayer, p.info)});
    const SsdoReads ssdo = planSsdoReads(job, p);
    for (const std::vector<std::string>* rgb : {&ssdo.radiance, &ssdo.albedo, &ssdo.directDiffuse})
        for (const std::string& c : *rgb) wanted.push_back({p.part, c});

    // The passes obscura computes from are read at full resolution only.
    for (const ChannelRef& c : wanted) {
        const ExrPart& owner = p.info.parts[c.part];
        const int i = owner.findChannel(c.name);
        if (i >= 0 && (owner.channels[i].xSampling != 1 || owner.channels[i].ySampling != 1))
            throw FileError(job.input, "channel '" + c.name + "' is subsampled (" +
                        std::to_string(owner.channels[i].xSampling) + "x" + std::to_string(owner.channels[i].ySampling) +
                        "); obscura reads the passes it computes from at full resolution only");
    }
    std::vector<Image> planes = readExrChannels(job.input, p.info, wanted, keepAll, keepAll ? &p.raw : nullptr);
    size_t next = 0;
    p.depth = std::move(planes[next++]);
    p.normal = interleavePlanes(planes, next, 3);
    next += 3;
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
    return p;
}

} // namespace

FramePasses loadFramePasses(const FrameJob& job, bool keepAll, std::vector<StageTiming>* stages,
                             bool alwaysReadPosition) {
    return blameInput(job.input, [&] { return loadPasses(job, keepAll, stages, alwaysReadPosition); });
}

Camera resolveFrameCamera(const FrameJob& job, const FramePasses& p) {
    CameraRequest request = job.camera;
    request.sidecarPath = sidecarFor(job);
    const ConstPlane position = p.position.empty() ? ConstPlane{} : p.position.view();
    return resolveCamera(request, &p.info.parts[p.part].header, position, p.data, p.display, p.pixelAspect);
}

DeepLayers readJobDeepLayers(const FrameJob& job, const FramePasses& p) {
    return blameInput(job.deepInput,
                      [&] { return readDeepLayers(job.deepInput, job.settings.deepLayers, p.plan.deep, job.maxPixels); });
}

namespace {

// The deep file's surfaces over the flat passes' data window, or an empty image without one.
Image readDeepInput(const FrameJob& job, const FramePasses& p, FrameReport& report) {
    if (job.deepInput.empty()) return Image();
    StageTimer timer{&report.stages, "deep"};
    DeepLayers deep = readJobDeepLayers(job, p);
    return blameInput(job.deepInput, [&] {
        if (deep.display != p.display)
            throw Error("its display window (" + std::to_string(deep.display.width()) + "x" +
                        std::to_string(deep.display.height()) + ") is not the flat passes' (" +
                        std::to_string(p.display.width()) + "x" + std::to_string(p.display.height()) + ")");
        report.deepLayers = deep.layers;
        report.deepEmptyPixels = deep.emptyPixels;
        report.deepDroppedSamples = deep.droppedSamples;
        report.deepUnsortedPixels = deep.unsortedPixels;
        report.deepTruncatedPixels = deep.truncatedPixels;
        report.plan.push_back("deep: " + std::to_string(deep.layers) + " layer(s) from " + job.deepInput);
        if (deep.droppedSamples)
            report.warnings.push_back(std::to_string(deep.droppedSamples) + " deep samples with NaN, infinite or non-positive Z skipped");
        if (deep.unsortedPixels)
            report.warnings.push_back(std::to_string(deep.unsortedPixels) + " deep pixels with unsorted samples sorted by Z");
        return deepPlanesOver(std::move(deep), p.data);
    });
}

FrameReport runJob(const FrameJob& job) {
    if (job.output.empty()) throw Error("no output file: give -o OUTPUT.exr");
    if (!job.inPlace && sameFile(job.input, job.output))
        throw FileError(job.input, "refusing to overwrite the input (use --in-place)");
    if (job.inPlace && job.write == WriteMode::New)
        throw Error("--write new cannot replace the input in place: the output holds only the new layers");
    // Every destination is checked before any work, so a bad one leaves nothing behind.
    requireOutputDirectory(job.output);
    if (!job.previewPath.empty()) requireOutputDirectory(job.previewPath);
    setExrThreads(job.settings.threads);
    setColourThreads(job.settings.threads);

    FrameReport report;
    const bool copy = job.write == WriteMode::Copy;
    FramePasses p = loadFramePasses(job, copy, &report.stages);
    {
        StageTimer timer{&report.stages, "camera"};
        report.camera = resolveFrameCamera(job, p);
    }
    report.depthKind = job.depthKind.value_or(p.plan.depthKind);
    report.normalSpace = job.normalSpace.value_or(p.plan.normalSpace);
    report.skyDepth = job.skyDepth.value_or(p.plan.skyDepth);
    // Left-handed camera-space normals (+z forward) become OpenGL's (-z forward).
    if (p.plan.normalsLeftHanded && report.normalSpace == NormalSpace::Camera && !job.normalSpace)
        for (size_t i = 2; i < p.normal.pixels.size(); i += 3) p.normal.pixels[i] = -p.normal.pixels[i];
    validatePixels(job, p, report.skyDepth, report);

    OperatorInputs in;
    in.displayWindow = p.display;
    in.dataWindow = p.data;
    in.depth = p.depth.view();
    in.normal = p.normal.view();
    in.depthKind = report.depthKind;
    in.normalSpace = report.normalSpace;
    in.camera = report.camera;
    Settings settings = job.settings;
    settings.skyDepth = report.skyDepth;
    const Image deepPlanes = readDeepInput(job, p, report);
    if (!deepPlanes.empty()) in.deepLayers = deepPlanes.view();
    const bool ssdo = methodOutputs(settings.method, "do");
    Image environment;
    if (ssdo) {
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
        report.plan.push_back(std::string("ssdo") + (settings.bounce ? " + bounce from " + job.bounceSource : " (no bounce)"));
    } else {
        report.plan.push_back(settings.method);
    }
    OperatorOutputs out;
    {
        StageTimer timer{&report.stages, "compute"};
        out = runOperator(in, settings);
    }
    report.stats = out.stats;
    for (const std::string& note : out.stats.notes) report.warnings.push_back(note);

    if (!p.reference.empty()) {
        const float sky = report.skyDepth;
        report.reference = compareChannels(std::as_const(out.ao).view(), 0, std::as_const(p.reference).view(), 0, [&](int x, int y) {
            return isSurface(*p.depth.at(x, y), sky);
        });
    }

    report.aoChannel = aoChannelName(job.aoLayer);
    const bool append = job.write == WriteMode::Append;
    {
        StageTimer timer{append ? nullptr : &report.stages, "write"};  // append times its own stages
        const Imf::PixelType type = job.aoFloat ? Imf::FLOAT : Imf::HALF;
        // Copy: into the depth's part of the input, or a part of their own when that part's
        // codec is lossy (AO, DO and GI are data). New and append: into the one part of a fresh
        // file, which append adds to the input's parts.
        ExrPixels fresh;
        if (!copy) fresh = layersOnlyFile(p.info, p.part);
        ExrPixels& target = copy ? p.raw : fresh;
        const bool ownPart = !copy || isLossy(p.info.parts[p.part].header.compression());
        const int outPart = !copy ? 0 : ownPart ? addLayersPart(target, p.part) : p.part;
        report.writeDescription = describeWrite(job, p.info, p.part);
        std::vector<NewChannel> add(1);
        add[0].part = outPart;
        add[0].name = report.aoChannel;
        add[0].plane = out.ao;
        add[0].type = type;
        std::vector<StringAttribute> attrs = {
            {outPart, "obscura/version", OBSCURA_VERSION_STRING},
            {outPart, "obscura/settings", frameReportJson(job, FrameReport{})},
        };
        std::vector<std::string> colourLayers;
        if (ssdo) colourLayers = addSsdoLayers(job, p, out, outPart, type, add, attrs);
        // AO is data (raw); DO, GI and relit are in the config's working space.
        std::string note;
        const ColourManager& cm = colourManager();
        // A part of our own holds no colour channels but ours, in the working space; an appended
        // one shares the input's chromaticities, so it is tagged as the depth's part would be.
        const std::string inputSpace = ownPart && !append ? cm.workingSpace()
                                       : report.inputColourSpace.empty()
                                           ? cm.detectColourSpace(p.info.parts[p.part].header, job.colourSpace).name
                                           : report.inputColourSpace;
        for (StringAttribute& a : cm.tagOutputPart(target.info.parts[outPart].header, outPart, inputSpace,
                                                   colourLayers, {report.aoChannel}, &note, append))
            attrs.push_back(std::move(a));
        if (!note.empty()) report.plan.push_back(note);
        for (const NewChannel& c : add) report.written.push_back(c.name);
        if (append)
            writeAppended(job.output, p.info, target, add, attrs, job.inPlace, &report.stages);
        else
            writeExrWithNewChannels(job.output, target, add, job.inPlace, attrs);
    }
    if (!job.previewPath.empty()) {
        StageTimer timer{&report.stages, "preview"};
        report.plan.push_back(writeFramePreview(job, p, out, ssdo));
    }
    return report;
}

} // namespace

FrameReport runFrameJob(const FrameJob& job) {
    return blameInput(job.input, [&] { return runJob(job); });
}

std::string frameReportJson(const FrameJob& job, const FrameReport& r) {
    using nlohmann::json;
    const Settings& s = job.settings;
    json j;
    j["obscura"] = OBSCURA_VERSION_STRING;
    j["input"] = job.input;
    j["output"] = job.output;
    j["settings"] = {{"method", s.method},          {"radius", s.radius},
                     {"directions", s.directions},  {"steps", s.steps},
                     {"weighting", toString(s.weighting)}, {"falloff", toString(s.falloff)},
                     {"blur", resolvedBlur(s)},     {"threads", s.threads},
                     {"device", s.device}};
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
                                 {"env", job.envPath},
                                 {"env_rotate_deg", s.envRotationDeg},
                                 {"env_intensity", s.envIntensity},
                                 {"sky", {s.skyRadiance[0], s.skyRadiance[1], s.skyRadiance[2]}},
                                 {"lights", lights},
                                 {"times_albedo", job.timesAlbedo}};
    }
    if (!r.aoChannel.empty()) {
        j["output_channels"] = {{"ao", r.aoChannel}};
        if (methodOutputs(s.method, "do")) {
            if (job.writeDirectional) j["output_channels"]["do"] = job.doLayer;
            if (job.writeIndirect) j["output_channels"]["gi"] = job.giLayer;
            if (job.writeRelit) j["output_channels"]["relit"] = job.relitLayer;
        }
        j["conventions"] = {{"depth", toString(r.depthKind)}, {"normals", toString(r.normalSpace)},
                            {"sky_depth", r.skyDepth}};
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
        if (!job.deepInput.empty())
            j["deep"] = {{"file", job.deepInput}, {"layers", r.deepLayers}, {"empty_pixels", r.deepEmptyPixels},
                         {"dropped_samples", r.deepDroppedSamples}, {"unsorted_pixels", r.deepUnsortedPixels},
                         {"truncated_pixels", r.deepTruncatedPixels}};
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
    }
    return j.dump(r.aoChannel.empty() ? -1 : 2);
}

} // namespace obscura
