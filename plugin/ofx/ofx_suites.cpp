// The host's suites and the property helpers (ofx_suites.h).
#include "ofx_suites.h"

namespace obscura::ofx {

OfxHost* gHost = nullptr;
const OfxPropertySuiteV1* gProp = nullptr;
const OfxImageEffectSuiteV1* gEffect = nullptr;
const OfxParameterSuiteV1* gParam = nullptr;
const OfxMessageSuiteV1* gMessage = nullptr;
const OfxMessageSuiteV2* gMessageV2 = nullptr;

OfxStatus fetchSuites() {
    if (!gHost) return kOfxStatErrMissingHostFeature;
    gProp = static_cast<const OfxPropertySuiteV1*>(gHost->fetchSuite(gHost->host, kOfxPropertySuite, 1));
    gEffect = static_cast<const OfxImageEffectSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxImageEffectSuite, 1));
    gParam = static_cast<const OfxParameterSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxParameterSuite, 1));
    gMessage = static_cast<const OfxMessageSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxMessageSuite, 1));
    gMessageV2 = static_cast<const OfxMessageSuiteV2*>(gHost->fetchSuite(gHost->host, kOfxMessageSuite, 2));
    if (!suitesLoaded()) return kOfxStatErrMissingHostFeature;
    return kOfxStatOK;
}

bool suitesLoaded() { return gProp && gEffect && gParam; }

std::string getString(OfxPropertySetHandle p, const char* name, int index) {
    char* v = nullptr;
    if (gProp->propGetString(p, name, index, &v) != kOfxStatOK || !v) return {};
    return v;
}

int getInt(OfxPropertySetHandle p, const char* name, int fallback, int index) {
    int v = fallback;
    if (gProp->propGetInt(p, name, index, &v) != kOfxStatOK) return fallback;
    return v;
}

double getDouble(OfxPropertySetHandle p, const char* name, double fallback, int index) {
    double v = fallback;
    if (gProp->propGetDouble(p, name, index, &v) != kOfxStatOK) return fallback;
    return v;
}

void setStrings(OfxPropertySetHandle p, const char* name, std::initializer_list<const char*> values) {
    int i = 0;
    for (const char* v : values) gProp->propSetString(p, name, i++, v);
}

OfxPropertySetHandle effectProps(OfxImageEffectHandle effect) {
    OfxPropertySetHandle p = nullptr;
    check(gEffect->getPropertySet(effect, &p));
    return p;
}

OfxPropertySetHandle clipProps(OfxImageClipHandle clip) {
    OfxPropertySetHandle p = nullptr;
    check(gEffect->clipGetPropertySet(clip, &p));
    return p;
}

bool connected(OfxImageClipHandle clip) {
    return clip && getInt(clipProps(clip), kOfxImageClipPropConnected, 0) != 0;
}

void postMessage(OfxImageEffectHandle effect, const char* type, const std::string& text) {
    if (gMessageV2 && gMessageV2->setPersistentMessage(effect, type, "", "%s", text.c_str()) == kOfxStatOK) return;
    postTransientMessage(effect, type, text);
}

void postTransientMessage(OfxImageEffectHandle effect, const char* type, const std::string& text) {
    if (gMessage) gMessage->message(effect, type, nullptr, "%s", text.c_str());
}

void clearPersistentMessage(OfxImageEffectHandle effect) {
    if (gMessageV2) gMessageV2->clearPersistentMessage(effect);
}

bool colourManaged(OfxPropertySetHandle p) {
    const std::string style = getString(p, kOfxImageEffectPropColourManagementStyle);
    return !style.empty() && style != kOfxImageEffectColourManagementNone;
}

} // namespace obscura::ofx
