// The obscura side of the report: one frame's passes loaded once (as the CLI would read
// them), then runOperator timed per method, preset and device.
#pragma once
#include "core/metrics.h"
#include "core/operator.h"
#include "io/frame_job.h"

#include <string>
#include <utility>
#include <vector>

namespace report {

// The passes of a reference EXR, the camera from its sidecar, and the reference layer.
struct LoadedFrame {
    obscura::FramePasses passes;  // depth, normal, reference (and the plan's conventions)
    obscura::Camera camera;       // from the sidecar next to the EXR
    float skyDepth = 1e9f;
    double radius = 1;            // the reference's AO distance (sidecar "ao_distance")
    // withBounce only: passes.radiance = ViewLayer.DiffDir, passes.albedo = ViewLayer.DiffCol (what the
    // CLI's --bounce-source direct-diffuse reads).
};

// Reads `exrPath` with the Blender preset and `referenceLayer` (e.g. Reference.AO_cosine_none);
// with `withBounce`, also the bounce source and the albedo.
LoadedFrame loadFrame(const std::string& exrPath, const std::string& referenceLayer, bool withBounce = false);
// The operator's inputs: views into `frame`, valid while it lives; with `withBounce`, the bounce
// source (radiance = DiffDir, albedo = DiffCol: senders radiate DiffDir x DiffCol); with
// `depthNormals`, no normal pass (the operator reconstructs the normals from the depth).
obscura::OperatorInputs operatorInputs(const LoadedFrame& frame, bool withBounce = false, bool depthNormals = false);

struct TimedOperator {
    int runs = 0;              // timed runs (fewer than asked when over the budget)
    double medianSeconds = 0;  // runOperator, wall clock
    std::vector<std::pair<std::string, double>> stageMedians;  // seconds, in the operator's stage order
    std::string deviceDetail;  // OperatorStats::device
    obscura::Image ao;         // from the last run
    obscura::Image directional;  // SSDO: DO irradiance, RGB, from the last run
    obscura::Image indirect;   // with bounce: GI irradiance E, RGB, from the last run
};

// One warm-up run, then `runs` timed runs of runOperator, stopping early (after at least
// one) once the timed runs have taken `budgetSeconds`.
TimedOperator timeOperator(const obscura::OperatorInputs& in, const obscura::Settings& s, int runs,
                           double budgetSeconds);

// `ao` against `reference` over the frame's non-sky pixels (depth in (0, sky)).
obscura::ErrorMetrics nonSkyError(const obscura::Image& ao, const obscura::Image& reference, const LoadedFrame& frame);

} // namespace report
