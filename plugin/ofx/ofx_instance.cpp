// The instance actions: create (find every clip and parameter handle once), destroy, and
// instance changed, which greys out the controls the current choices do not read.
#include "ofx_instance.h"

#include "ofx_actions.h"
#include "ofx_names.h"
#include "ofx_params.h"
#include "ofx_suites.h"

#include "core/methods.h"

#include <algorithm>
#include <memory>
#include <utility>
#include <string>
#include <vector>

namespace obscura::ofx {

namespace {

OfxParamHandle param(OfxParamSetHandle set, const char* name) {
    OfxParamHandle h = nullptr;
    check(gParam->paramGetHandle(set, name, &h, nullptr));
    return h;
}

OfxImageClipHandle clip(OfxImageEffectHandle effect, const char* name) {
    OfxImageClipHandle h = nullptr;
    check(gEffect->clipGetHandle(effect, name, &h, nullptr));
    return h;
}

void enable(OfxParamHandle h, bool on) {
    OfxPropertySetHandle p = nullptr;
    if (gParam->paramGetPropertySet(h, &p) == kOfxStatOK) gProp->propSetInt(p, kOfxParamPropEnabled, 0, on ? 1 : 0);
}

void updateEnabled(const Instance& in) {
    int projection = 0, normals = 0, output = 0, depthKind = 0, method = 0, giMethod = 0;
    gParam->paramGetValue(in.method, &method);
    gParam->paramGetValue(in.giMethod, &giMethod);
    gParam->paramGetValue(in.projection, &projection);
    gParam->paramGetValue(in.depthKind, &depthKind);
    gParam->paramGetValue(in.normalSpace, &normals);
    gParam->paramGetValue(in.output_, &output);
    const OutputKind kind = outputAt(output).kind;
    enable(in.fov, projection == 0);
    enable(in.orthoWidth, projection == 1);
    enable(in.focal, projection == 2);
    enable(in.aperture, projection == 2);
    enable(in.depthNear, depthKind == 3);  // normalized
    enable(in.depthFar, depthKind == 3);
    enable(in.cameraToWorld, normals == 0);
    // Method runs the AO outputs, GI Method GI and Relit, ssdo DO; Times Albedo concerns DO and GI only.
    enable(in.method, !outputAt(output).light);
    enable(in.giMethod, kind == OutputKind::Indirect || kind == OutputKind::Relit);
    // What the method does not read is greyed out, from the same table the CLI and Python refuse by.
    const std::string runs = methodFor(outputAt(output), method, giMethod);
    const std::vector<const MethodParam*> own = allMethodParams();
    for (size_t i = 0; i < own.size(); ++i)
        if (in.methodParams[i]) enable(in.methodParams[i], settingRefusal(runs, own[i]->key, Spelling::Key).empty());
    OfxParamSetHandle set = nullptr;
    gEffect->getParamSet(in.effect, &set);
    for (const MethodOption& o : methodOptions())
        if (o.ofx) enable(param(set, o.ofx), settingRefusal(runs, o.ofx, Spelling::Key).empty());
    enable(in.timesAlbedo, kind == OutputKind::Directional || kind == OutputKind::Indirect);
}

void bindClips(Instance& in, OfxImageEffectHandle effect) {
    const std::pair<OfxImageClipHandle Instance::*, const char*> clips[] = {
        {&Instance::source, kClipSource},     {&Instance::depth, kClipDepth},   {&Instance::normal, kClipNormal},
        {&Instance::position, kClipPosition}, {&Instance::albedo, kClipAlbedo}, {&Instance::output, kClipOutput}};
    for (const auto& [member, name] : clips) in.*member = clip(effect, name);
}

void bindParams(Instance& in, OfxParamSetHandle set) {
    const std::pair<OfxParamHandle Instance::*, const char*> params[] = {
        {&Instance::output_, kParamOutput},
        {&Instance::strength, kParamStrength},
        {&Instance::method, kParamMethod},
        {&Instance::giMethod, kParamGiMethod},
        {&Instance::radius, kParamRadius},
        {&Instance::directions, kParamDirections},
        {&Instance::steps, kParamSteps},
        {&Instance::weighting, kParamWeighting},
        {&Instance::falloff, kParamFalloff},
        {&Instance::blur, kParamBlur},
        {&Instance::projection, kParamProjection},
        {&Instance::fov, kParamFov},
        {&Instance::focal, kParamFocal},
        {&Instance::aperture, kParamAperture},
        {&Instance::orthoWidth, kParamOrthoWidth},
        {&Instance::cameraToWorld, kParamCameraToWorld},
        {&Instance::depthKind, kParamDepthKind},
        {&Instance::normalSpace, kParamNormalSpace},
        {&Instance::depthNear, kParamDepthNear},
        {&Instance::depthFar, kParamDepthFar},
        {&Instance::skyDepth, kParamSkyDepth},
        {&Instance::maxScreenRadius, kParamMaxScreenRadius},
        {&Instance::device, kParamDevice},
        {&Instance::threads, kParamThreads},
        {&Instance::ssdoSamples, kParamSsdoSamples},
        {&Instance::interleave, kParamInterleave},
        {&Instance::skyColour, kParamSkyColour},
        {&Instance::envMap, kParamEnvMap},
        {&Instance::envRotation, kParamEnvRotation},
        {&Instance::envIntensity, kParamEnvIntensity},
        {&Instance::upAxis, kParamUpAxis},
        {&Instance::timesAlbedo, kParamTimesAlbedo},
    };
    for (const auto& [member, name] : params) in.*member = param(set, name);
    for (const MethodParam* mp : allMethodParams()) in.methodParams.push_back(mp->ofx ? param(set, mp->key) : nullptr);
}

} // namespace

Instance* instanceOf(OfxImageEffectHandle effect) {
    void* p = nullptr;
    check(gProp->propGetPointer(effectProps(effect), kOfxPropInstanceData, 0, &p));
    if (!p) throw OfxFailure{kOfxStatErrBadHandle};
    return static_cast<Instance*>(p);
}

Instance* findInstance(OfxImageEffectHandle effect) noexcept {
    OfxPropertySetHandle props = nullptr;
    void* p = nullptr;
    if (!effect || gEffect->getPropertySet(effect, &props) != kOfxStatOK) return nullptr;
    if (gProp->propGetPointer(props, kOfxPropInstanceData, 0, &p) != kOfxStatOK) return nullptr;
    return static_cast<Instance*>(p);
}

OfxStatus onCreateInstance(OfxImageEffectHandle effect) {
    auto in = std::make_unique<Instance>();
    in->effect = effect;
    bindClips(*in, effect);
    OfxParamSetHandle set = nullptr;
    check(gEffect->getParamSet(effect, &set));
    bindParams(*in, set);
    updateEnabled(*in);  // before the host holds the instance: a throw here frees it
    check(gProp->propSetPointer(effectProps(effect), kOfxPropInstanceData, 0, in.get()));
    in.release();
    return kOfxStatOK;
}

OfxStatus onDestroyInstance(OfxImageEffectHandle effect) {
    void* p = nullptr;
    OfxPropertySetHandle props = effectProps(effect);
    if (gProp->propGetPointer(props, kOfxPropInstanceData, 0, &p) == kOfxStatOK && p) {
        delete static_cast<Instance*>(p);
        gProp->propSetPointer(props, kOfxPropInstanceData, 0, nullptr);
    }
    return kOfxStatOK;
}

OfxStatus onInstanceChanged(OfxImageEffectHandle effect) {
    updateEnabled(*instanceOf(effect));
    return kOfxStatOK;
}

} // namespace obscura::ofx
