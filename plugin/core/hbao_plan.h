// HBAO's plan: which model of occluders the kernel runs, decided once, here, from the settings
// and the input. Both devices specialise kernels/hbao.glsl on it: the CPU by template
// (cpu/lane_tile_impl.h), OpenGL by defines (gpu/gl_kernels.cpp). docs/hbao.md has the maths.
#pragma once
#include "core/settings.h"

#include <string>

namespace obscura {
namespace glsl {
struct KernelParams;
}

// What a sample hides along its slice.
enum class HbaoModel {
    Horizon,           // everything below the highest sample: a height field (Bavoil et al. 2008)
    FixedThickness,    // the angles from a sample's front to T behind it: a visibility bitmask
                       // (Therrien et al. 2023)
    MeasuredThickness, // the same, each occluder as deep as it is wide along the slice, at most T
    Deep,              // the renderer's surfaces along each sample's ray (deep input), and the
                       // texel's footprint; point samples T deep
};

// What a sample past the buffer's edge sees, where there is no overscan (Settings::border).
enum class HbaoBorder { Open = kBorderOpen, Clamp = kBorderClamp, Tangent = kBorderTangent };

struct HbaoPlan {
    HbaoModel model = HbaoModel::Horizon;
    // Samples are applied per occluder crossed (a run of them) when it ends, not one by one:
    // the measured thickness needs the run's width, and linear falloff with a thickness weights
    // each occluder's rise once.
    bool runs = false;
    Weighting weighting = Weighting::Uniform;
    Falloff falloff = Falloff::Linear;
    HbaoBorder border = HbaoBorder::Tangent;
    // T in world units: +inf for Horizon and for Deep asked for no thickness; MeasuredThickness's
    // cap (0.85 R for `auto`), also for Deep with `auto` (no runs there: each point sample).
    float thickness = kThicknessInfinite;
    float depthPerWidth = 0.0f; // MeasuredThickness: a run's depth per unit of its width; else 0
    float runJump = 0.0f;       // runs and Deep's footprints: the largest depth change within one
                                // occluder (world units); else 0
    int deepLayers = 0;         // Deep: surfaces read per texel; else 0
};

// The plan for `s` with deep input of `deepInputLayers` (front, back) pairs per texel, 0 for flat
// input. Deep input is read with falloff none only (linear falloff keeps the flat model).
HbaoPlan planHbao(const Settings& s, int deepInputLayers);

// Whether a run with `s` uses deep layers: a method that reads them (the method table) with
// falloff none. Otherwise deep input is flattened or ignored, and its layers are not worth reading.
bool readsDeepLayers(const Settings& s);

// The plan's fields of the kernels' parameter block (hbaoModel, hbaoRuns, hbaoBorder, thickness,
// runDepthPerWidth, runJump, deepLayers).
void fillHbaoParams(const HbaoPlan& plan, glsl::KernelParams& p);

// One line, e.g. "fixed thickness 0.3 by runs, linear falloff, uniform weighting, tangent border".
std::string describe(const HbaoPlan& plan);
const char* toString(HbaoModel model);
const char* toString(HbaoBorder border);

} // namespace obscura
