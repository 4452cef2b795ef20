// The ray-traced side of the report, in-process with examples/reference's renderer:
// the converged reference render (cached as an EXR) and the renderer's own
// error-versus-time curve at a few AO ray counts.
#pragma once
#include "base/image.h"
#include "reference/camera.h"
#include "reference/integrators.h"
#include "reference/scene.h"
#include "reference/tracer.h"

#include <memory>
#include <string>
#include <vector>

namespace report {

struct ReferenceSettings {
    int width = 320, height = 240;
    int convergedRays = 1024;                        // AO rays per pixel and weighting, seed 1
    int giRays = 1024;                               // of the converged render: its beauty, Reference.GI (+ _unlimited)
    std::vector<int> curveRays = {1, 4, 16, 64, 256};  // the ray tracer's own curve, seed 2 (AO and DO rays; GI rays)
    int runs = 3;                                    // timed runs per point (median), after a warm-up for obscura
    double runBudgetSeconds = 2.0;                   // fewer runs (at least 1) once a point has taken this long
    int threads = 0;                                 // 0 = all cores
    double radiusScale = 1;                          // R = the scene's default radius x this (--radius-scale)
};

// A scene with its Embree BVH and camera, built once per scene; building is not timed.
struct SceneRig {
    SceneRig(const std::string& name, int width, int height);
    SceneRig(const SceneRig&) = delete;
    SceneRig& operator=(const SceneRig&) = delete;

    reference::Scene scene;
    std::unique_ptr<reference::Tracer> tracer;
    reference::PinholeCamera camera;
};

struct ConvergedReference {
    // <cacheDir>/<scene>_<W>x<H>_ao<N>_gi<M>_lit.exr (+ the .json camera sidecar); "_lit": the scene's sky
    // as the DO map and its sun in Reference.DO, with Reference.GI and GI_unlimited (older caches lack them).
    std::string path;
    bool cached = false;  // found on disk, not rendered now
    double seconds = 0;   // render time when rendered now
};

// The converged reference for this scene: reused when the cache holds it, rendered otherwise.
ConvergedReference ensureConvergedReference(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir);

// The deep reference (reference_render --deep): every solid along each primary ray; reused from
// the cache like the converged one, traced otherwise. Without colour: <scene>_<W>x<H>_deep.exr,
// primary rays only (a fraction of a second). `coloured`: <scene>_<W>x<H>_deep_gi<M>.exr, each span
// also with what its surface radiates (DiffDir x DiffCol from M sky rays, the converged render's
// seed), for the bounce of hbao+deep+bounce (M sky rays per span: 6 s for studio at 320 x 240 on
// two cores, where the converged render also traces the bounce's and the AO's rays).
std::string ensureDeepReference(const SceneRig& rig, const ReferenceSettings& s, const std::string& cacheDir,
                                bool coloured = false);

// Passes with overscan: the scene rendered `overscan` pixels past each edge of the display
// window (1 AO ray, no GI: only the passes are used), cached as
// <cacheDir>/<scene>_<W>x<H>_overscan<N>.exr. Returns its path.
std::string ensureOverscanPasses(const SceneRig& rig, const ReferenceSettings& s, int overscan,
                                 const std::string& cacheDir);

struct TracedAo {
    int rays = 0;
    int runs = 0;              // timed renders (fewer than asked when over the run budget)
    double medianSeconds = 0;  // whole render: primary rays, light shadow rays, AO rays of both weightings
    obscura::Image ao[reference::kAoLayers];  // every AO layer (reference::AoLayer order), one channel each
    obscura::Image directional;               // Reference.DO's quantity from the cosine rays, RGB
};

// Renders AO only (no GI) with `rays` AO rays per pixel, s.runs times (within the run budget),
// and keeps every AO layer (one render traces both weightings; the falloff is a weight).
// DO comes from the same cosine rays (the scene's sky as the map, its sun as a light).
TracedAo traceAo(const SceneRig& rig, const ReferenceSettings& s, int rays);

struct TracedGi {
    int rays = 0, runs = 0;
    double medianSeconds = 0;  // whole render: primary rays, lights, `rays` GI rays (+ 1 AO ray per weighting)
    obscura::Image gi;         // Reference.GI's quantity (within R), RGB
};
// The ray tracer's own GI curve: a render with `rays` cosine GI rays per pixel, timed like traceAo.
TracedGi traceGi(const SceneRig& rig, const ReferenceSettings& s, int rays);

} // namespace report
