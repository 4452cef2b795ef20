// HBAO's planner (core/hbao_plan.h): every combination of the settings that choose the model,
// and what runs for it.
#include "core/hbao_plan.h"
#include "core/operator.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace obscura;

namespace {

struct Row {
    float thickness;    // the setting: kThicknessInfinite, a T, or kThicknessAuto
    Falloff falloff;
    int deepInput;      // (front, back) pairs per texel of the input, 0: flat
    HbaoModel model;
    bool runs;
    float planned;      // the plan's thickness
    int deepLayers;
};

constexpr float kInf = kThicknessInfinite;
constexpr float kAuto = kThicknessAuto;
constexpr Falloff kNone = Falloff::None, kLinear = Falloff::Linear;
// With R = 2 and --deep-layers 4: auto's cap is 0.85 R = 1.7.
const Row kTable[] = {
    // flat input
    {kInf, kNone, 0, HbaoModel::Horizon, false, kInf, 0},
    {kInf, kLinear, 0, HbaoModel::Horizon, false, kInf, 0},
    {0.3f, kNone, 0, HbaoModel::FixedThickness, false, 0.3f, 0},
    {0.3f, kLinear, 0, HbaoModel::FixedThickness, true, 0.3f, 0}, // linear falloff weights each occluder once
    {kAuto, kNone, 0, HbaoModel::MeasuredThickness, true, 1.7f, 0},
    {kAuto, kLinear, 0, HbaoModel::MeasuredThickness, true, 1.7f, 0},
    // deep input: read with falloff none; linear falloff keeps the flat model
    {kInf, kNone, 6, HbaoModel::Deep, false, kInf, 4},
    {kInf, kLinear, 6, HbaoModel::Horizon, false, kInf, 0},
    {0.3f, kNone, 6, HbaoModel::Deep, false, 0.3f, 4},
    {0.3f, kLinear, 6, HbaoModel::FixedThickness, true, 0.3f, 0},
    {kAuto, kNone, 6, HbaoModel::Deep, false, 1.7f, 4}, // point samples take the cap; no runs
    {kAuto, kLinear, 6, HbaoModel::MeasuredThickness, true, 1.7f, 0},
    {kInf, kNone, 2, HbaoModel::Deep, false, kInf, 2}, // fewer layers in the input than asked for
};

Settings settingsFor(const Row& r) {
    Settings s;
    s.radius = 2.0f;
    s.thickness = r.thickness;
    s.falloff = r.falloff;
    s.deepLayers = 4;
    return s;
}

std::string name(const Row& r) {
    const std::string t = r.thickness == kInf ? "inf" : r.thickness == kAuto ? "auto" : std::to_string(r.thickness);
    return "--thickness " + t + " --falloff " + toString(r.falloff) + (r.deepInput ? " (deep input)" : "");
}

} // namespace

TEST(HbaoPlan, EachSettingsCombinationHasItsModel) {
    for (const Row& r : kTable)
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
            for (int border : {kBorderOpen, kBorderClamp, kBorderTangent}) {
                SCOPED_TRACE(name(r));
                Settings s = settingsFor(r);
                s.weighting = w;
                s.border = border;
                const HbaoPlan plan = planHbao(s, r.deepInput);
                EXPECT_EQ(plan.model, r.model);
                EXPECT_EQ(plan.runs, r.runs);
                EXPECT_EQ(plan.thickness, r.planned);
                EXPECT_EQ(plan.deepLayers, r.deepLayers);
                EXPECT_EQ(plan.weighting, w);
                EXPECT_EQ(plan.falloff, r.falloff);
                EXPECT_EQ((int)plan.border, border);
                // Only the measured thickness scales runs by their width; runs and footprints end at 1.5 R.
                EXPECT_EQ(plan.depthPerWidth, r.model == HbaoModel::MeasuredThickness ? 1.0f : 0.0f);
                EXPECT_EQ(plan.runJump, r.runs || r.model == HbaoModel::Deep ? 3.0f : 0.0f);
            }
}

// The question the planner answers in one place.
TEST(HbaoPlan, DescribesWhatRuns) {
    Settings s;
    s.thickness = 0.3f;
    s.falloff = Falloff::Linear;
    EXPECT_EQ(describe(planHbao(s, 0)), "fixed thickness 0.3 by runs, linear falloff, uniform weighting, tangent border");
    s.thickness = kThicknessInfinite;
    s.falloff = Falloff::None;
    s.weighting = Weighting::Cosine;
    s.border = kBorderOpen;
    EXPECT_EQ(describe(planHbao(s, 0)), "horizon, none falloff, cosine weighting, open border");
    EXPECT_EQ(describe(planHbao(s, 3)), "deep layers (3), none falloff, cosine weighting, open border");
    s.thickness = kThicknessAuto;
    s.radius = 2.0f;
    EXPECT_EQ(describe(planHbao(s, 0)), "measured thickness up to 1.7 by runs, none falloff, cosine weighting, open border");
}

// The parameter block carries the plan as it is: no sentinel stands in for an infinite thickness.
TEST(HbaoPlan, ParameterBlockCarriesThePlan) {
    const test::SceneBuffers sb = test::renderScene(test::cornerScene(), test::cornerCamera(32, 24), 32, 24);
    for (const Row& r : kTable) {
        if (r.deepInput) continue; // the block's deep fields need a deep plane (test_deep)
        SCOPED_TRACE(name(r));
        const glsl::KernelParams p = makeKernelParams(sb.inputs(), settingsFor(r));
        EXPECT_EQ(p.hbaoModel, (int)r.model);
        EXPECT_EQ(p.hbaoRuns, r.runs ? 1 : 0);
        EXPECT_EQ(p.thickness, r.planned);
        EXPECT_EQ(p.deepLayers, 0);
    }
}
