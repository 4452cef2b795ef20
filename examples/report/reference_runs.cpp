#include "reference_runs.h"

#include "reference/deep_output.h"
#include "reference/environment.h"
#include "reference/exr_output.h"
#include "reference/render.h"
#include "timing.h"

#include <cstdio>
#include <filesystem>

namespace report {

namespace {
constexpr uint32_t kConvergedSeed = 1;
constexpr uint32_t kCurveSeed = 2;  // independent of the converged samples: a prefix of them would flatter the curve
} // namespace

SceneRig::SceneRig(const std::string& name, int width, int height)
    : scene(reference::makeScene(name)),
      tracer(std::make_unique<reference::Tracer>(scene)),
      camera(reference::PinholeCamera::lookAt(scene.camera, width, height)) {}

namespace {

// The lights of DO: the scene's sky as the map and its sun (what its direct pass is lit by).
void addSceneLights(const SceneRig& rig, reference::RenderSettings& rs) {
    rs.environment = std::make_shared<const reference::EnvironmentMap>(reference::skyMap(rig.scene.lighting));
    rs.sunInDo = true;
}

// Renders s.runs times (within the run budget); returns the last frame and the median time.
reference::Frame timedRender(const SceneRig& rig, const ReferenceSettings& s, const reference::RenderSettings& rs,
                             int& runs, double& medianSeconds) {
    const reference::Integrator integrator(rig.scene, *rig.tracer, rig.camera, rs);
    std::vector<double> seconds;
    reference::Frame frame;
    double spent = 0;
    for (int run = 0; run < std::max(1, s.runs) && (run == 0 || spent < s.runBudgetSeconds); ++run) {
        const Clock::time_point t0 = Clock::now();
        frame = reference::render(integrator, rs);
        seconds.push_back(secondsSince(t0));
        spent += seconds.back();
    }
    runs = int(seconds.size());
    medianSeconds = median(seconds);
    return frame;
}

obscura::Image rgbImage(const reference::Frame& frame, glm::vec3 reference::PixelResult::*member) {
    obscura::Image out(frame.width, frame.height, 3);
    for (int y = 0; y < frame.height; ++y)
        for (int x = 0; x < frame.width; ++x)
            for (int c = 0; c < 3; ++c) out.at(x, y)[c] = (frame.at(x, y).*member)[c];
    return out;
}

// <cacheDir>/<scene>_<W>x<H>_<what>.exr
std::string cachePath(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir,
                      const std::string& what) {
    char scale[32] = "";
    if (s.radiusScale != 1) std::snprintf(scale, sizeof scale, "_r%g", s.radiusScale);
    return (std::filesystem::path(cacheDir) /
            (rig.scene.name + "_" + std::to_string(s.width) + "x" + std::to_string(s.height) + "_" + what + scale + ".exr"))
        .string();
}

// The settings of a cached reference render with these rays and overscan (seed 1; lit when it bounces).
reference::RenderSettings cachedRenderSettings(const SceneRig& rig, const ReferenceSettings& s, int aoRays, int giRays,
                                               int overscan) {
    reference::RenderSettings rs;
    rs.width = s.width;
    rs.height = s.height;
    rs.radius = rig.scene.defaultRadius * s.radiusScale;
    rs.aoRays = aoRays;
    rs.giRays = giRays;
    rs.seed = kConvergedSeed;
    rs.threads = s.threads;
    rs.overscan = overscan;
    if (giRays > 0) addSceneLights(rig, rs);
    return rs;
}

// A reference render (passes, AO layers, camera sidecar) with these rays and overscan, from
// the cache when it holds both files, rendered and cached otherwise.
ConvergedReference ensureRender(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir,
                                const std::string& what, int aoRays, int giRays, int overscan) {
    ConvergedReference out;
    out.path = cachePath(rig, s, cacheDir, what);
    const std::string sidecar = out.path.substr(0, out.path.size() - 4) + ".json";
    if (std::filesystem::exists(out.path) && std::filesystem::exists(sidecar)) {
        out.cached = true;
        return out;
    }
    const reference::RenderSettings rs = cachedRenderSettings(rig, s, aoRays, giRays, overscan);
    const Clock::time_point t0 = Clock::now();
    const reference::Integrator integrator(rig.scene, *rig.tracer, rig.camera, rs);
    const reference::Frame frame = reference::render(integrator, rs);
    out.seconds = secondsSince(t0);
    reference::writeReference(out.path, frame, rig.camera, {rig.scene.name, rs, reference::summarise(frame)});
    return out;
}

} // namespace

ConvergedReference ensureConvergedReference(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir) {
    return ensureRender(rig, s, cacheDir,
                        "ao" + std::to_string(s.convergedRays) + "_gi" + std::to_string(s.giRays) + "_lit",
                        s.convergedRays, s.giRays, 0);
}

std::string ensureDeepReference(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir,
                                bool coloured) {
    // The coloured file's name carries its GI rays: a cache written before deep colour existed
    // ("_deep") is never taken for one.
    const std::string path = cachePath(rig, s, cacheDir, coloured ? "deep_gi" + std::to_string(s.giRays) : "deep");
    if (std::filesystem::exists(path)) return path;
    if (!coloured) {
        reference::writeDeep(path, reference::traceDeep(*rig.tracer, rig.camera, s.threads));
        return path;
    }
    // The converged render's settings and seed: the first span's colour is its DiffDir x DiffCol.
    const reference::RenderSettings rs = cachedRenderSettings(rig, s, s.convergedRays, s.giRays, 0);
    const reference::Integrator integrator(rig.scene, *rig.tracer, rig.camera, rs);
    reference::writeDeep(path, reference::traceDeep(*rig.tracer, rig.camera, s.threads, &integrator));
    return path;
}

// Only the passes are used: 1 AO ray, no GI.
std::string ensureOverscanPasses(const SceneRig& rig, const ReferenceSettings& s, int overscan,
                                 const std::string& cacheDir) {
    return ensureRender(rig, s, cacheDir, "overscan" + std::to_string(overscan), 1, 0, overscan).path;
}

TracedAo traceAo(const SceneRig& rig, const ReferenceSettings& s, int rays) {
    reference::RenderSettings rs;
    rs.width = s.width;
    rs.height = s.height;
    rs.radius = rig.scene.defaultRadius * s.radiusScale;
    rs.aoRays = rays;
    rs.giRays = 0;  // AO only: the sky light and the bounce are not part of an AO render
    rs.seed = kCurveSeed;
    rs.threads = s.threads;
    addSceneLights(rig, rs);  // DO from the cosine rays: a map lookup per ray and one sun ray
    TracedAo out;
    out.rays = rays;
    const reference::Frame frame = timedRender(rig, s, rs, out.runs, out.medianSeconds);
    for (int layer = 0; layer < reference::kAoLayers; ++layer) {
        out.ao[layer] = obscura::Image(frame.width, frame.height, 1);
        for (int y = 0; y < frame.height; ++y)
            for (int x = 0; x < frame.width; ++x) *out.ao[layer].at(x, y) = float(frame.at(x, y).ao[layer]);
    }
    out.directional = rgbImage(frame, &reference::PixelResult::directionalOcclusion);
    return out;
}

TracedGi traceGi(const SceneRig& rig, const ReferenceSettings& s, int rays) {
    reference::RenderSettings rs;
    rs.width = s.width;
    rs.height = s.height;
    rs.radius = rig.scene.defaultRadius * s.radiusScale;
    rs.aoRays = 1;  // the least AO the integrator traces
    rs.giRays = rays;
    rs.seed = kCurveSeed;
    rs.threads = s.threads;
    TracedGi out;
    out.rays = rays;
    const reference::Frame frame = timedRender(rig, s, rs, out.runs, out.medianSeconds);
    out.gi = rgbImage(frame, &reference::PixelResult::giNear);
    return out;
}

} // namespace report
