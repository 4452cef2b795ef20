// --inspect's command line: one that would run on the file (declared in io/inspect.h).
#include "io/inspect.h"

#include "base/error.h"
#include "core/methods.h"
#include "io/deep_job.h"
#include "io/views.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

namespace obscura {

namespace {

// Where a lens is needed and nothing gives one: a 50 mm lens on a 36 mm film back, about 40
// degrees across. An assumption, said so wherever it is used.
constexpr double kAssumedFovDeg = 40;

std::string number(double v) {
    std::ostringstream os;
    os.precision(9);
    os << v;
    return os.str();
}

// NAME_ao.exr beside the input, or NAME_ao_2.exr, ... where that exists: the command the user
// copies must not replace an earlier output. A frame's number stays last (shot.1001.exr ->
// shot_ao.1001.exr), where sequence tools look for it.
std::string defaultOutput(const std::string& input, std::vector<std::string>& notes) {
    namespace fs = std::filesystem;
    const fs::path in(input);
    std::string name = in.stem().string(), frame;
    const size_t dot = name.rfind('.');
    if (dot != std::string::npos && dot + 1 < name.size() &&
        std::all_of(name.begin() + dot + 1, name.end(), [](char c) { return std::isdigit((unsigned char)c); }))
        frame = name.substr(dot), name.resize(dot);
    const auto named = [&](int k) {
        return (in.parent_path() / (name + "_ao" + (k > 1 ? "_" + std::to_string(k) : "") + frame + ".exr")).string();
    };
    std::error_code ec;
    int k = 1;
    while (fs::exists(named(k), ec)) ++k;
    if (k > 1) notes.push_back("output: " + named(1) + " exists; the command writes " + named(k));
    return named(k);
}

// The flags that give `job` what it holds beside the defaults (in --help's spelling).
std::vector<std::string> argsFor(const FrameJob& job) {
    std::vector<std::string> a = {"obscura"};
    if (!job.deepInput.empty()) a.insert(a.end(), {job.deepInput, "--flat", job.input});
    else if (!job.deepElements.empty()) a.insert(a.end(), job.deepElements.begin(), job.deepElements.end());
    else a.push_back(job.input);
    a.insert(a.end(), {"-o", job.output});
    if (job.settings.method != Settings{}.method) a.insert(a.end(), {"--method", job.settings.method});
    if (job.write != WriteMode::Copy) a.insert(a.end(), {"--write", toString(job.write)});
    if (job.settings.falloff != Settings{}.falloff) a.insert(a.end(), {"--falloff", toString(job.settings.falloff)});
    if (job.perElementAo) a.push_back("--per-element-ao");
    if (job.preset != "auto") a.insert(a.end(), {"--preset", job.preset});
    for (const auto& [role, name] : job.layerOverrides) a.insert(a.end(), {"--layer", std::string(roleName(role)) + "=" + name});
    if (job.depthEncoding) a.insert(a.end(), {"--depth", toString(*job.depthEncoding)});
    if (job.depthRange) a.insert(a.end(), {"--depth-range", number((*job.depthRange)[0]) + "," + number((*job.depthRange)[1])});
    if (job.normalSpace) a.insert(a.end(), {"--normals", toString(*job.normalSpace)});
    if (job.skyDepth) a.insert(a.end(), {"--sky-depth", number(*job.skyDepth)});
    if (job.badPixels == BadPixelPolicy::Skip) a.insert(a.end(), {"--bad-pixels", "skip"});
    const CameraRequest& c = job.camera;
    if (!c.sidecarPath.empty()) a.insert(a.end(), {"--camera", c.sidecarPath});
    if (c.fovDeg) a.insert(a.end(), {"--fov-deg", number(*c.fovDeg)});
    if (c.focalMm) a.insert(a.end(), {"--focal-mm", number(*c.focalMm)});
    if (c.apertureMm) a.insert(a.end(), {"--aperture-mm", number(*c.apertureMm)});
    if (c.orthoWidth) a.insert(a.end(), {"--ortho-width", number(*c.orthoWidth)});
    if (c.cameraToWorld) {
        std::string m;
        for (double v : *c.cameraToWorld) m += (m.empty() ? "" : ",") + number(v);
        a.insert(a.end(), {"--camera-to-world", m});
    }
    if (!job.views.empty()) {
        std::string v;
        for (const std::string& name : job.views) v += (v.empty() ? "" : ",") + name;
        a.insert(a.end(), {"--view", v});
    }
    return a;
}

// The camera the run would use, adding an assumed lens when nothing gives one.
Camera cameraForRun(FrameJob& run, const FramePasses& p, std::vector<std::string>& notes) {
    try {
        return resolveFrameCamera(run, p);
    } catch (const Error&) {
        if (run.camera.fovDeg || run.camera.focalMm || run.camera.orthoWidth) throw;
    }
    run.camera.fovDeg = kAssumedFovDeg;
    notes.push_back("camera: none in the file; the command assumes --fov-deg " + number(kAssumedFovDeg) +
                    " (a 50 mm lens on a 36 mm film back); give your camera's lens as --fov-deg, or "
                    "--focal-mm with --aperture-mm");
    return resolveFrameCamera(run, p);
}

// A channel that looks like a depth where the preset found neither a depth nor a position pass:
// its last name component is Z, its name says depth, or it is Mantra's Pz. Named as the view
// described sees it.
std::string depthCandidate(const FrameJob& job) {
    const ExrInfo info = readExrInfo(job.input, job.maxPixels);
    const std::vector<std::string> views = viewsToProcess(job, info);
    const std::string view = views.empty() ? (fileViews(info).empty() ? "" : fileViews(info).front()) : views.front();
    const LayerPlan plan = planViewLayers(job, info, view);
    if (plan.find(Role::Depth) || plan.find(Role::Position)) return "";
    for (const ExrPart& part : (view.empty() ? info : viewOfFile(info, view).info).parts)
        for (const ExrChannel& ch : part.channels) {
            std::string lower = ch.name;
            for (char& c : lower) c = (char)std::tolower((unsigned char)c);
            const size_t dot = lower.rfind('.');
            const std::string last = lower.substr(dot == std::string::npos ? 0 : dot + 1);
            if (last == "z" || last == "pz" || lower.find("depth") != std::string::npos)
                return ch.name;
        }
    return "";
}

// Makes `run` one that runs: the camera and normals it needs added, each addition noted. Its
// passes are `loaded` where given, else read.
void completeRun(FrameJob& run, std::vector<std::string>& notes, const FramePasses* loaded) {
    std::optional<FramePasses> read;
    if (!loaded) {
        DeepElementsInput merged;
        FrameReport merge;
        read = loadPassesForInspection(run, merged, merge);
    }
    const FramePasses& p = loaded ? *loaded : *read;
    const bool deep = !run.deepInput.empty() || !p.carried.empty();  // carried: deep elements' flattened image
    if (deep && run.settings.falloff == Falloff::Linear && methodReads(run.settings.method, "deep")) {
        run.settings.falloff = Falloff::None;
        notes.push_back("falloff: linear falloff ignores the deep layers; the command adds --falloff none so that "
                        "the hidden surfaces occlude (docs/deep.md)");
    }
    const Camera camera = cameraForRun(run, p, notes);
    const NormalSpace space = p.normalsFromDepth ? NormalSpace::Depth : run.normalSpace.value_or(p.plan.normalSpace);
    long long bad = 0;
    for (float d : p.depth.pixels) bad += std::isnan(d) || d < 0.0f;
    if (bad > 0 && run.badPixels == BadPixelPolicy::Error) {
        run.badPixels = BadPixelPolicy::Skip;
        notes.push_back("depth: " + std::to_string(bad) + " NaN or negative pixel(s); the command treats them as "
                        "holes (--bad-pixels skip)");
    }
    if (space == NormalSpace::World && !camera.hasPose) {
        run.normalSpace = NormalSpace::Depth;
        notes.push_back("normals: the file's are in world space and no camera pose is known; the command "
                        "reconstructs them from depth (--normals depth): give --camera-to-world to use them");
    }
    // A scene within a unit of the camera is stored so too: the command cannot tell, so it says.
    if (!p.depthStats.hint.empty())
        notes.push_back("depth: the command reads it as a distance, but it looks like " + p.depthStats.hint);
}

} // namespace

std::string shellQuoted(const std::string& arg) {
    const bool plain = !arg.empty() && arg.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                             "0123456789_-+=.,/:@%") == std::string::npos;
    if (plain) return arg;
    std::string q = "'";
    for (char ch : arg) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
}

SuggestedCommand suggestCommand(const FrameJob& job, const FramePasses* loaded) {
    SuggestedCommand s;
    FrameJob run = job;
    if (run.output.empty()) run.output = defaultOutput(job.deepInput.empty() ? job.input : job.deepInput, s.notes);
    for (bool retried = false;; retried = true) {
        try {
            completeRun(run, s.notes, retried ? nullptr : loaded);
            break;
        } catch (const Error& e) {
            std::string candidate;
            try {
                candidate = retried || run.layerOverrides.count(Role::Depth) ? "" : depthCandidate(run);
            } catch (const Error&) {
                // No better guess: the first failure is the answer.
            }
            if (candidate.empty()) {
                s.problem = firstLineOf(e.what());
                return s;
            }
            run.layerOverrides[Role::Depth] = candidate;
            s.notes.push_back("depth: no layer the preset knows; the command takes '" + candidate +
                              "' (--layer depth=" + candidate + "): check that it is the depth");
        }
    }
    s.args = argsFor(run);
    return s;
}

std::string commandLine(const std::vector<std::string>& args) {
    std::string line;
    for (const std::string& a : args) line += (line.empty() ? "" : " ") + shellQuoted(a);
    return line;
}

} // namespace obscura
