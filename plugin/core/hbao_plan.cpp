#include "core/hbao_plan.h"

#include "base/kernel_params.h"
#include "core/methods.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace obscura {

// The kernels spell the models as the parameter block's integers (kernels/kernel_params.glsl).
static_assert((int)HbaoModel::Horizon == glsl::HBAO_HORIZON && (int)HbaoModel::FixedThickness == glsl::HBAO_FIXED_THICKNESS &&
                  (int)HbaoModel::MeasuredThickness == glsl::HBAO_MEASURED_THICKNESS &&
                  (int)HbaoModel::Deep == glsl::HBAO_DEEP,
              "HbaoModel must match the kernels' HBAO_* constants");
static_assert((int)HbaoBorder::Open == glsl::HBAO_BORDER_OPEN && (int)HbaoBorder::Clamp == glsl::HBAO_BORDER_CLAMP &&
                  (int)HbaoBorder::Tangent == glsl::HBAO_BORDER_TANGENT,
              "HbaoBorder must match the kernels' HBAO_BORDER_* constants");

namespace {
// thickness auto: an occluder's depth is k times its width across the slice (k = 1: a cylinder
// is as deep as it is wide), at most 0.85 R; a depth change above 1.5 R between samples ends an
// occluder (docs/hbao.md has the sweeps on the report's scenes).
constexpr float kDepthPerWidth = 1.0f;
constexpr float kRunJumpPerRadius = 1.5f;
} // namespace

HbaoPlan planHbao(const Settings& s, int deepInputLayers) {
    HbaoPlan plan;
    plan.weighting = s.weighting;
    plan.falloff = s.falloff;
    plan.border = static_cast<HbaoBorder>(s.border);
    plan.thickness = resolvedThickness(s);
    const bool linear = s.falloff == Falloff::Linear;
    if (deepInputLayers > 0 && !linear) {
        plan.model = HbaoModel::Deep;
        plan.deepLayers = std::min(s.deepLayers, deepInputLayers);
    } else if (!std::isfinite(plan.thickness)) {
        plan.model = HbaoModel::Horizon;
    } else if (s.thickness == kThicknessAuto) {
        plan.model = HbaoModel::MeasuredThickness;
        plan.depthPerWidth = kDepthPerWidth;
    } else {
        plan.model = HbaoModel::FixedThickness;
    }
    plan.runs = plan.model == HbaoModel::MeasuredThickness || (plan.model == HbaoModel::FixedThickness && linear);
    if (plan.runs || plan.model == HbaoModel::Deep) plan.runJump = kRunJumpPerRadius * s.radius;
    return plan;
}

bool readsDeepLayers(const Settings& s) { return methodReads(s.method, "deep") && s.falloff != Falloff::Linear; }

void fillHbaoParams(const HbaoPlan& plan, glsl::KernelParams& p) {
    p.hbaoModel = (int)plan.model;
    p.hbaoRuns = plan.runs ? 1 : 0;
    p.hbaoBorder = (int)plan.border;
    p.thickness = plan.thickness;
    p.runDepthPerWidth = plan.depthPerWidth;
    p.runJump = plan.runJump;
    p.deepLayers = plan.deepLayers;
}

const char* toString(HbaoModel model) {
    switch (model) {
    case HbaoModel::Horizon: return "horizon";
    case HbaoModel::FixedThickness: return "fixed thickness";
    case HbaoModel::MeasuredThickness: return "measured thickness";
    case HbaoModel::Deep: return "deep layers";
    }
    return "?";
}

const char* toString(HbaoBorder border) {
    switch (border) {
    case HbaoBorder::Open: return "open";
    case HbaoBorder::Clamp: return "clamp";
    case HbaoBorder::Tangent: return "tangent";
    }
    return "?";
}

std::string describe(const HbaoPlan& plan) {
    std::ostringstream o;
    o << toString(plan.model);
    if (plan.model == HbaoModel::Deep) o << " (" << plan.deepLayers << ")";
    if (std::isfinite(plan.thickness)) o << (plan.model == HbaoModel::MeasuredThickness ? " up to " : " ") << plan.thickness;
    if (plan.runs) o << " by runs";
    o << ", " << toString(plan.falloff) << " falloff, " << toString(plan.weighting) << " weighting, "
      << toString(plan.border) << " border";
    return o.str();
}

} // namespace obscura
