// What the host asks about the output before a render: the clips' components, premultiplication
// and colourspaces (clip preferences, OFX 1.5's output colourspace), and whether the effect
// is an identity on Source. Every clip is float already: the plugin declares no other depth and
// no mixed depths, so the host maps them and the plugin may not set them.
#include "ofx_actions.h"
#include "ofx_instance.h"
#include "ofx_names.h"
#include "ofx_params.h"
#include "ofx_suites.h"

#include <string>
#include <utility>

namespace obscura::ofx {

namespace {

// The Output option stored now (clip preferences are not asked at a time).
const OutputOption& currentOutput(const Instance& in) {
    int outputIndex = 0;
    check(gParam->paramGetValue(in.output_, &outputIndex));
    return outputAt(outputIndex);
}

} // namespace

OfxStatus onGetClipPreferences(OfxImageEffectHandle effect, OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    const OutputOption& o = currentOutput(in);
    // The general context's default Output is Alpha unless an input is RGBA (a Depth clip alone
    // gives Alpha): the colour outputs ask for RGBA. Depth and Source, the inputs that take Alpha,
    // keep the components they have, so a host that remaps inputs to the Output's does not move
    // an Alpha depth out of channel 0 (RGB, which no clip takes, is left to the host's RGBA).
    if (o.kind != OutputKind::Ao)
        gProp->propSetString(outArgs, (std::string(kOfxImageClipPropComponentsPrefix) + kClipOutput).c_str(), 0,
                             kOfxImageComponentRGBA);
    const std::pair<OfxImageClipHandle, const char*> inputs[] = {{in.source, kClipSource}, {in.depth, kClipDepth}};
    for (const auto& [clip, name] : inputs) {
        const std::string own = connected(clip) ? getString(clipProps(clip), kOfxImageClipPropUnmappedComponents) : "";
        if (own == kOfxImageComponentRGBA || own == kOfxImageComponentAlpha)
            gProp->propSetString(outArgs, (std::string(kOfxImageClipPropComponentsPrefix) + name).c_str(), 0, own.c_str());
    }
    if (keepsSourceAlpha(o.kind) && connected(in.source)) {
        const std::string premult = getString(clipProps(in.source), kOfxImageEffectPropPreMultiplication);
        gProp->propSetString(outArgs, kOfxImageEffectPropPreMultiplication, 0,
                             premult.empty() ? kOfxImagePreMultiplied : premult.c_str());
    } else {
        gProp->propSetString(outArgs, kOfxImageEffectPropPreMultiplication, 0, kOfxImageOpaque);
    }
    // Depth, normals and positions are data: never colour-convert them.
    if (colourManaged(effectProps(effect)))
        for (const char* name : {kClipDepth, kClipNormal, kClipPosition})
            gProp->propSetString(outArgs, (std::string(kOfxImageClipPropPreferredColourspacesPrefix) + name).c_str(), 0,
                                 kOfxColourspaceOfxRaw);
    return kOfxStatOK;
}

// OFX 1.5: the host asks which colourspace the Output clip is in. The AO is data; the beauty
// product and the SSDO light are in the Source's space (a cross-reference to that clip).
OfxStatus onGetOutputColourspace(OfxImageEffectHandle effect, OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    if (!colourManaged(effectProps(effect))) return kOfxStatReplyDefault;
    const bool colour = currentOutput(in).kind != OutputKind::Ao;
    if (colour && !connected(in.source)) return kOfxStatReplyDefault;
    const std::string space = colour ? std::string(kOfxColourspaceClipPrefix) + kClipSource : kOfxColourspaceOfxRaw;
    check(gProp->propSetString(outArgs, kOfxImageClipPropColourspace, 0, space.c_str()));
    return kOfxStatOK;
}

OfxStatus onIsIdentity(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs, OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    const OfxTime t = getDouble(inArgs, kOfxPropTime, 0);
    const Params p = readParams(in, t);
    // Off (strength 0): the beauty passes through untouched.
    if (p.strength <= 0 && p.output == OutputKind::BeautyTimesAo && connected(in.source)) {
        gProp->propSetString(outArgs, kOfxPropName, 0, kClipSource);
        gProp->propSetDouble(outArgs, kOfxPropTime, 0, t);
        return kOfxStatOK;
    }
    return kOfxStatReplyDefault;
}

} // namespace obscura::ofx
