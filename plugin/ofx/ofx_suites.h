// The host's suites, fetched once at load and read-only afterwards, and small helpers over
// the property suite that every action uses.
#pragma once
#include "ofx_api.h"

#include <initializer_list>
#include <string>

namespace obscura::ofx {

extern OfxHost* gHost;
extern const OfxPropertySuiteV1* gProp;
extern const OfxImageEffectSuiteV1* gEffect;
extern const OfxParameterSuiteV1* gParam;
extern const OfxMessageSuiteV1* gMessage;    // optional
extern const OfxMessageSuiteV2* gMessageV2;  // optional: persistent messages, where the host has them

// kOfxActionLoad: fetches the suites; a host without the required three lacks a feature.
OfxStatus fetchSuites();
// Whether every required suite is there (no action but Load runs without them).
bool suitesLoaded();

// A suite call that failed: the entry point answers the host with its status.
struct OfxFailure {
    OfxStatus status;
};

inline void check(OfxStatus st) {
    if (st != kOfxStatOK) throw OfxFailure{st};
}

// Property reads that fall back when the host does not set the property.
std::string getString(OfxPropertySetHandle p, const char* name, int index = 0);
int getInt(OfxPropertySetHandle p, const char* name, int fallback, int index = 0);
double getDouble(OfxPropertySetHandle p, const char* name, double fallback, int index = 0);
void setStrings(OfxPropertySetHandle p, const char* name, std::initializer_list<const char*> values);

OfxPropertySetHandle effectProps(OfxImageEffectHandle effect);
OfxPropertySetHandle clipProps(OfxImageClipHandle clip);
bool connected(OfxImageClipHandle clip);
// What the user should see on the node (an action's failure: kOfxMessageError; a render that
// mended its inputs: kOfxMessageWarning): a persistent message where the host has version 2 of
// the message suite, else a transient one.
void postMessage(OfxImageEffectHandle effect, const char* type, const std::string& text);
// The message suite's one-off message: what a descriptor (no instance yet) may be told, where
// setPersistentMessage takes an instance only.
void postTransientMessage(OfxImageEffectHandle effect, const char* type, const std::string& text);
// The node's persistent message cleared (version 2 of the message suite; else nothing to clear).
void clearPersistentMessage(OfxImageEffectHandle effect);

// OFX 1.5 colour management: the host offers a style on its own properties, the plugin
// declares the one it supports at describe (Basic: it only names basic spaces, ofx_raw and
// clip cross-references), and the host puts the negotiated style on each instance. A
// pre-1.5 host sets nothing, which means none.
bool colourManaged(OfxPropertySetHandle p);

} // namespace obscura::ofx
