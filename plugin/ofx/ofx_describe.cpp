// The describe actions: the plugin's properties, then in the General context its clips and
// parameters, page by group. Ranges, device names and which method reads what come from
// plugin/core (core/settings_schema.h, core/devices.h, core/methods.h); the node keeps none.
#include "ofx_actions.h"
#include "ofx_names.h"
#include "ofx_params.h"
#include "ofx_suites.h"

#include "base/error.h"
#include "core/devices.h"
#include "core/methods.h"
#include "core/settings.h"
#include "core/settings_schema.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace obscura::ofx {

namespace {

void defineClip(OfxImageEffectHandle effect, const char* name, std::initializer_list<const char*> comps, bool optional,
                const char* hint) {
    OfxPropertySetHandle c = nullptr;
    check(gEffect->clipDefine(effect, name, &c));
    setStrings(c, kOfxImageEffectPropSupportedComponents, comps);
    gProp->propSetInt(c, kOfxImageClipPropOptional, 0, optional ? 1 : 0);
    gProp->propSetInt(c, kOfxImageEffectPropTemporalClipAccess, 0, 0);
    gProp->propSetInt(c, kOfxImageEffectPropSupportsTiles, 0, 1);
    gProp->propSetInt(c, kOfxImageClipPropIsMask, 0, 0);
    if (hint) gProp->propSetString(c, kOfxPropLabel, 0, hint);
}

// A shared numeric setting's range as the node stores it (core/settings_schema.h).
double lo(const char* ofx) { return numberSetting(ofx).ofxMin; }
double hi(const char* ofx) { return numberSetting(ofx).max; }

// A method parameter of the method table (core/methods.h), by key.
const MethodParam& tableParam(const char* key) {
    for (const MethodParam* mp : allMethodParams())
        if (std::string(mp->key) == key) return *mp;
    throw Error(std::string("the method table has no parameter ") + key);
}

// Defines the parameters one by one, remembering every name (the method table's parameters not
// defined yet get their own groups) and the controls (the page's children: no groups, no pages).
struct ParamDef {
    OfxParamSetHandle set;
    std::vector<std::string> controls;
    std::vector<std::string> defined;

    OfxPropertySetHandle define(const char* type, const char* name, const char* label, const char* hint,
                                const char* parent = nullptr) {
        OfxPropertySetHandle p = nullptr;
        check(gParam->paramDefine(set, type, name, &p));
        defined.push_back(name);
        gProp->propSetString(p, kOfxPropLabel, 0, label);
        gProp->propSetString(p, kOfxParamPropScriptName, 0, name);
        // A parameter only some methods read says which (the method table), and starts greyed
        // out unless the default method reads it; the instance follows the Method choice.
        const std::vector<std::string> readers = methodsReading(name);
        std::string text = hint ? hint : "";
        if (!readers.empty()) {
            text += " [read by";
            for (const std::string& m : readers) text += " " + m;
            text += "]";
            gProp->propSetInt(p, kOfxParamPropEnabled, 0, settingRefusal(Settings{}.method, name, Spelling::Key).empty());
        }
        if (!text.empty()) gProp->propSetString(p, kOfxParamPropHint, 0, text.c_str());
        if (parent) gProp->propSetString(p, kOfxParamPropParent, 0, parent);
        if (std::strcmp(type, kOfxParamTypeGroup) != 0 && std::strcmp(type, kOfxParamTypePage) != 0)
            controls.push_back(name);
        return p;
    }
    void choice(const char* name, const char* label, const char* hint, std::vector<const char*> options, int def,
                const char* parent = nullptr) {
        OfxPropertySetHandle p = define(kOfxParamTypeChoice, name, label, hint, parent);
        for (int i = 0; i < (int)options.size(); ++i) gProp->propSetString(p, kOfxParamPropChoiceOption, i, options[i]);
        gProp->propSetInt(p, kOfxParamPropDefault, 0, def);
        gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    }
    void integer(const char* name, const char* label, const char* hint, int def, int lo, int hi, int dlo, int dhi,
                 const char* parent = nullptr) {
        OfxPropertySetHandle p = define(kOfxParamTypeInteger, name, label, hint, parent);
        gProp->propSetInt(p, kOfxParamPropDefault, 0, def);
        gProp->propSetInt(p, kOfxParamPropMin, 0, lo);
        gProp->propSetInt(p, kOfxParamPropMax, 0, hi);
        gProp->propSetInt(p, kOfxParamPropDisplayMin, 0, dlo);
        gProp->propSetInt(p, kOfxParamPropDisplayMax, 0, dhi);
    }
    // An integer of the method table with a control of its own: the table's range and the
    // Settings default, as the method groups below take them.
    void tableInteger(const char* name, const char* label, const char* hint, int dlo, int dhi,
                      const char* parent = nullptr) {
        const MethodParam& mp = tableParam(name);
        integer(name, label, hint, Settings{}.*(mp.intField), (int)mp.min, (int)mp.max, dlo, dhi, parent);
    }
    void real(const char* name, const char* label, const char* hint, double def, double lo, double hi, double dlo,
              double dhi, const char* parent = nullptr, const char* doubleType = kOfxParamDoubleTypePlain) {
        OfxPropertySetHandle p = define(kOfxParamTypeDouble, name, label, hint, parent);
        gProp->propSetString(p, kOfxParamPropDoubleType, 0, doubleType);
        gProp->propSetDouble(p, kOfxParamPropDefault, 0, def);
        gProp->propSetDouble(p, kOfxParamPropMin, 0, lo);
        gProp->propSetDouble(p, kOfxParamPropMax, 0, hi);
        gProp->propSetDouble(p, kOfxParamPropDisplayMin, 0, dlo);
        gProp->propSetDouble(p, kOfxParamPropDisplayMax, 0, dhi);
        gProp->propSetInt(p, kOfxParamPropDigits, 0, 4);
    }
    // A boolean or a string that does not animate (a string: one line, or a file path).
    void boolean(const char* name, const char* label, const char* hint, bool def, const char* parent) {
        OfxPropertySetHandle p = define(kOfxParamTypeBoolean, name, label, hint, parent);
        gProp->propSetInt(p, kOfxParamPropDefault, 0, def ? 1 : 0);
        gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    }
    void group(const char* name, const char* label) {
        OfxPropertySetHandle p = define(kOfxParamTypeGroup, name, label, nullptr);
        gProp->propSetInt(p, kOfxParamPropGroupOpen, 0, 1);
    }
};

void defineClips(OfxImageEffectHandle effect) {
    defineClip(effect, kClipSource, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, true, nullptr);
    defineClip(effect, kClipDepth, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, false, nullptr);
    defineClip(effect, kClipNormal, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipPosition, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipAlbedo, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipOutput, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, false, nullptr);
}

// The top of the page: what the node outputs and how the occlusion is sampled.
void describeMain(ParamDef& d) {
    std::vector<const char*> outputs;
    for (const OutputOption& o : kOutputOptions) outputs.push_back(o.label);
    d.choice(kParamOutput, "Output",
             "What the Output clip carries: the AO (RGB = AO, A = 1); the beauty (Source) multiplied by the AO; "
             "SSDO's directional occlusion (DO) or one-bounce indirect light (GI, bounced from Source), as "
             "irradiance (RGB, A = 1); or Relit = Albedo x (DO + GI) / pi (alpha of Source)",
             outputs, 0);
    d.real(kParamStrength, "Strength", "Blend of the AO towards 1 (0 = off: the effect passes the beauty through)",
           1.0, 0.0, 1.0, 0.0, 1.0);
    // From the method table, in its order: hosts store the index, and methods are only appended.
    std::vector<const char*> methodChoices;
    for (const MethodInfo& m : methods()) methodChoices.push_back(m.name);
    d.choice(kParamMethod, "Method",
             "Occlusion method for the AO outputs (--method); DO uses ssdo, GI and Relit the GI Method", methodChoices,
             0);
    d.choice(kParamGiMethod, "GI Method",
             "Method of the GI and Relit outputs: ssdo (its point samples), or hbao (the light its horizon march "
             "finds, as --method hbao --bounce); both bounce Source",
             giMethods(), ssdoGiMethodIndex());
    d.real(kParamRadius, "Radius", "Radius in world units (--radius)", 1.0, lo(kParamRadius), hi(kParamRadius), 0.01, 10.0);
    d.tableInteger(kParamDirections, "Directions", "Slices per pixel (--directions)", 1, 32);
    d.tableInteger(kParamSteps, "Steps", "Samples per slice (--steps)", 1, 32);
    d.choice(kParamWeighting, "Weighting",
             "uniform: the HBAO paper's solid angle; cosine: projected solid angle, as a ray tracer's AO pass "
             "(--weighting)",
             {kWeightings[0], kWeightings[1]}, 0);
    d.choice(kParamFalloff, "Falloff", "linear: W(r) = 1 - r/R; none: binary visibility within R (--falloff)",
             {kFalloffs[0], kFalloffs[1]}, 0);
    d.integer(kParamBlur, "Blur",
              "Geometry-aware blur radius in pixels, 0 = off; -1: the default, 1 (the medium preset's), and for "
              "ssdo as wide as the interleave block (--blur)",
              kBlurAuto, (int)lo(kParamBlur), (int)hi(kParamBlur), kBlurAuto, 16);
}

void describeCamera(ParamDef& d) {
    d.group(kGroupCamera, "Camera");
    d.choice(kParamProjection, "Projection",
             "Perspective from the field of view, orthographic (width), or perspective from the focal length and "
             "horizontal aperture (film back) as a compositing app's camera node",
             {kProjections[0], kProjections[1], kProjections[2]}, 0, kGroupCamera);
    d.real(kParamFov, "Field of View", "Horizontal field of view across the project format, degrees (--fov-deg)",
           39.5977, lo(kParamFov), hi(kParamFov), 1.0, 120.0, kGroupCamera, kOfxParamDoubleTypeAngle);
    d.real(kParamFocal, "Focal Length", "Focal length, mm (--focal-mm)", 50.0, lo(kParamFocal), hi(kParamFocal), 5.0,
           300.0, kGroupCamera);
    d.real(kParamAperture, "Horizontal Aperture",
           "Horizontal film back, mm, spanning the project format's width (--aperture-mm); 36 with a 50 mm focal "
           "length is the default field of view",
           36.0, lo(kParamAperture), hi(kParamAperture), 5.0, 50.0, kGroupCamera);
    d.real(kParamOrthoWidth, "Ortho Width", "World units across the project format (--ortho-width)", 10.0,
           lo(kParamOrthoWidth), hi(kParamOrthoWidth), 0.1, 100.0, kGroupCamera);
    OfxPropertySetHandle p = d.define(kOfxParamTypeString, kParamCameraToWorld, "Camera to World",
                                      "16 numbers m00,...,m33, row-major, OpenGL convention (camera looks down -Z); "
                                      "needed for world-space normals (--camera-to-world)",
                                      kGroupCamera);
    gProp->propSetString(p, kOfxParamPropDefault, 0, "");
    gProp->propSetString(p, kOfxParamPropStringMode, 0, kOfxParamStringIsSingleLine);
    gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    d.choice(kParamDepthKind, "Depth",
             "How the Depth clip stores it: planar: camera-space Z; radial: distance to the eye; inverse: 1/Z "
             "(Nuke's ScanlineRender); normalized: 0 at Depth Near, 1 at Depth Far (--depth)",
             {kDepthKinds[0], kDepthKinds[1], kDepthKinds[2], kDepthKinds[3]}, 0, kGroupCamera);
    // --depth-range A,B as its two ends; (0, 0) is unset, refused when normalized is chosen.
    const NumberSetting& range = numberSetting("depth_range");
    d.real(kParamDepthNear, "Depth Near", "normalized: the distance stored as 0 (--depth-range A,B: A)", 0.0,
           range.ofxMin, range.max, 0.0, 1000.0, kGroupCamera);
    d.real(kParamDepthFar, "Depth Far",
           "normalized: the distance stored as 1 (--depth-range A,B: B; below Depth Near when white is near)", 0.0,
           range.ofxMin, range.max, 0.0, 1000.0, kGroupCamera);
    d.choice(kParamNormalSpace, "Normals",
             "Space of the Normal clip's RGB, or depth: reconstructed from the Depth clip, as they are without "
             "a Normal clip (--normals)",
             {kNormalSpaces[0], kNormalSpaces[1], kNormalSpaces[2]}, 0, kGroupCamera);
}

void describeAdvanced(ParamDef& d) {
    d.group(kGroupAdvanced, "Advanced");
    d.real(kParamSkyDepth, "Sky Depth", "Depth at or beyond which a pixel is sky (--sky-depth)", 1e9,
           lo(kParamSkyDepth), hi(kParamSkyDepth), 1.0, 1e10, kGroupAdvanced);
    d.real(kParamMaxScreenRadius, "Max Screen Radius",
           "Cap on the projected radius in pixels; it is also the apron requested around each tile. "
           "0 = automatic (the frame's extent, as the command line: every tile then reads the whole frame)",
           256.0, 0.0, 1e6, 0.0, 1024.0, kGroupAdvanced);
    std::vector<const char*> deviceChoices;  // the one list (core/devices.h), in its stored order
    for (const DeviceName& dn : deviceNames()) deviceChoices.push_back(dn.name);
    d.choice(kParamDevice, "Device", "Compute device (--device); auto = a hardware GPU if present, else the CPU",
             deviceChoices, 1, kGroupAdvanced);
    d.integer(kParamThreads, "Threads", "CPU threads, 0 = all cores (--threads)", 0, (int)lo(kParamThreads),
              (int)hi(kParamThreads), 0, 64, kGroupAdvanced);
}

// SSDO's sampling, its light (the sky colour or an environment map) and its outputs' units.
void describeSsdo(ParamDef& d) {
    d.group(kGroupSsdo, "SSDO");
    d.tableInteger(kParamSsdoSamples, "Samples", "Sample set N shared by an interleaving block (--samples)", 1, 256,
                   kGroupSsdo);
    d.tableInteger(kParamInterleave, "Interleave",
                   "M: an M x M block of pixels splits the sample set, N / M^2 each, gathered back by a blur "
                   "(--interleave)",
                   1, 8, kGroupSsdo);
    OfxPropertySetHandle sky = d.define(kOfxParamTypeRGB, kParamSkyColour, "Sky Colour",
                                        "Constant sky radiance when there is no environment map (--sky)", kGroupSsdo);
    for (int c = 0; c < 3; ++c) {
        gProp->propSetDouble(sky, kOfxParamPropDefault, c, 1.0);
        gProp->propSetDouble(sky, kOfxParamPropMin, c, 0.0);
        gProp->propSetDouble(sky, kOfxParamPropMax, c, kMaxLight);
        gProp->propSetDouble(sky, kOfxParamPropDisplayMin, c, 0.0);
        gProp->propSetDouble(sky, kOfxParamPropDisplayMax, c, 4.0);
    }
    OfxPropertySetHandle env =
        d.define(kOfxParamTypeString, kParamEnvMap, "Environment Map",
                 "Lat-long radiance map, any format OpenImageIO reads, converted from its colour space to the "
                 "working space as the CLI does (--env); empty = the sky colour",
                 kGroupSsdo);
    gProp->propSetString(env, kOfxParamPropDefault, 0, "");
    gProp->propSetString(env, kOfxParamPropStringMode, 0, kOfxParamStringIsFilePath);
    gProp->propSetInt(env, kOfxParamPropStringFilePathExists, 0, 1);
    gProp->propSetInt(env, kOfxParamPropAnimates, 0, 0);
    d.real(kParamEnvRotation, "Env Rotation", "Turns the environment about the up axis, degrees (--env-rotate)", 0.0,
           lo(kParamEnvRotation), hi(kParamEnvRotation), -180.0, 180.0, kGroupSsdo, kOfxParamDoubleTypeAngle);
    d.real(kParamEnvIntensity, "Env Intensity", "Multiplies the environment map (--env-intensity)", 1.0,
           lo(kParamEnvIntensity), hi(kParamEnvIntensity), 0.0, 4.0, kGroupSsdo);
    d.choice(kParamUpAxis, "Up Axis", "World up axis for the environment: y, or z for Blender renders (--up)",
             {kUpAxes[0], kUpAxes[1]}, 0, kGroupSsdo);
    d.boolean(kParamTimesAlbedo, "Times Albedo",
              "DO and GI as albedo x E / pi (needs the Albedo clip), the outgoing radiance of the diffuse receiver, "
              "instead of irradiance E (--times-albedo)",
              false, kGroupSsdo);
}

// A method parameter's label from its flag: --ssao-samples is "SSAO Samples".
std::string labelOf(const MethodParam& mp) {
    std::string label, word;
    const std::string flag = std::string(mp.flag).substr(2);
    for (size_t i = 0; i <= flag.size(); ++i) {
        if (i < flag.size() && flag[i] != '-') {
            word += flag[i];
            continue;
        }
        const bool method = findMethod(word) != nullptr;
        for (size_t k = 0; k < word.size(); ++k)
            if (method || k == 0) word[k] = (char)std::toupper((unsigned char)word[k]);
        label += (label.empty() ? "" : " ") + word;
        word.clear();
    }
    return label;
}

// The table's help, and the numbers this node stores for its words (the node has no words).
std::string hintOf(const MethodParam& mp) {
    std::string hint = mp.help, words;
    for (const NamedValue& n : mp.named) {
        char one[64];
        std::snprintf(one, sizeof one, "%s%g = %s", words.empty() ? "" : ", ", n.hostValue, n.word);
        words += one;
    }
    return words.empty() ? hint : hint + " (this node: " + words + ")";
}

// The methods' own parameters that have no control above (ssao's, rtao's), from the method
// table, with its ranges and the Settings defaults, in a group per method.
void describeMethodParams(ParamDef& d) {
    const Settings defaults;
    for (const MethodInfo& m : methods()) {
        bool grouped = false;
        for (const MethodParam& mp : m.params) {
            if (!mp.ofx || std::find(d.defined.begin(), d.defined.end(), mp.key) != d.defined.end()) continue;
            if (!grouped) d.group(m.name, m.name);
            grouped = true;
            const std::string label = labelOf(mp), hint = hintOf(mp);
            if (mp.boolField) {
                d.boolean(mp.key, label.c_str(), hint.c_str(), defaults.*(mp.boolField), m.name);
            } else if (mp.intField) {
                d.integer(mp.key, label.c_str(), hint.c_str(), defaults.*(mp.intField), (int)mp.min, (int)mp.max,
                          (int)mp.min, (int)std::min(mp.max, 256.0), m.name);
            } else {
                // Named values (auto, inf) are plain numbers here: their hostValue, inside the range.
                double def = defaults.*(mp.floatField), lo = mp.min, hi = std::min(mp.max, 1e9);
                for (const NamedValue& n : mp.named) {
                    if (def == n.value) def = n.hostValue;
                    lo = std::min(lo, n.hostValue);
                    hi = std::max(hi, n.hostValue);
                }
                d.real(mp.key, label.c_str(), hint.c_str(), def, lo, hi, lo, std::min(mp.max, 10.0), m.name);
            }
        }
    }
}

// One page holding every control, in definition order: a page's children are parameters, never
// groups (ofxParam.h, kOfxParamPropPageChild); hosts that lay out by group still show the groups.
void describePage(ParamDef& d) {
    OfxPropertySetHandle page = d.define(kOfxParamTypePage, kPage, "Controls", nullptr);
    for (int i = 0; i < (int)d.controls.size(); ++i)
        gProp->propSetString(page, kOfxParamPropPageChild, i, d.controls[i].c_str());
}

} // namespace

OfxStatus onDescribe(OfxImageEffectHandle effect) {
    OfxPropertySetHandle p = effectProps(effect);
    gProp->propSetString(p, kOfxPropLabel, 0, "obscura AO");
    gProp->propSetString(p, kOfxPropShortLabel, 0, "obscura");
    gProp->propSetString(p, kOfxPropLongLabel, 0, "obscura ambient occlusion");
    gProp->propSetString(p, kOfxImageEffectPluginPropGrouping, 0, "obscura");
    gProp->propSetString(p, kOfxPropPluginDescription, 0,
                         "Screen-space ambient occlusion (HBAO), and directional occlusion with one bounce "
                         "(SSDO), from the depth and normal passes of a render. Shuffle each pass into its "
                         "clip: Depth (first channel), Normal (RGB; optional: without it the normals are "
                         "reconstructed from the depth), optional Albedo (RGB) and Position; "
                         "Source is the beauty (also the bounce source).");
    gProp->propSetInt(p, kOfxPropVersion, 0, (int)kVersionMajor);
    gProp->propSetInt(p, kOfxPropVersion, 1, (int)kVersionMinor);
    gProp->propSetString(p, kOfxPropVersionLabel, 0, OBSCURA_OFX_VERSION_STRING);
    setStrings(p, kOfxImageEffectPropSupportedContexts, {kOfxImageEffectContextGeneral});
    setStrings(p, kOfxImageEffectPropSupportedPixelDepths, {kOfxBitDepthFloat});
    gProp->propSetInt(p, kOfxImageEffectPluginPropSingleInstance, 0, 0);
    // Renders share nothing: per-render buffers, read-only instance data, GL contexts per thread.
    gProp->propSetString(p, kOfxImageEffectPluginRenderThreadSafety, 0, kOfxImageEffectRenderFullySafe);
    // The operator spreads a render over all cores itself.
    gProp->propSetInt(p, kOfxImageEffectPluginPropHostFrameThreading, 0, 0);
    // Proxy renders: the camera, Blur and Max Screen Radius follow the render scale.
    gProp->propSetInt(p, kOfxImageEffectPropSupportsMultiResolution, 0, 1);
    gProp->propSetInt(p, kOfxImageEffectPropSupportsTiles, 0, 1);
    gProp->propSetInt(p, kOfxImageEffectPropTemporalClipAccess, 0, 0);
    gProp->propSetInt(p, kOfxImageEffectPropSupportsMultipleClipDepths, 0, 0);
    gProp->propSetInt(p, kOfxImageEffectPropSupportsMultipleClipPARs, 0, 0);
    gProp->propSetInt(p, kOfxImageEffectPluginPropFieldRenderTwiceAlways, 0, 0);
    // GetClipPreferences reads Output (premultiplication, colourspace): re-run it when it changes.
    gProp->propSetString(p, kOfxImageEffectPropClipPreferencesSlaveParam, 0, kParamOutput);
    if (gHost && colourManaged(gHost->host)) {
        gProp->propSetString(p, kOfxImageEffectPropColourManagementStyle, 0, kOfxImageEffectColourManagementBasic);
        gProp->propSetString(p, kOfxImageEffectPropColourManagementAvailableConfigs, 0, kOfxConfigIdentifier);
    }
    return kOfxStatOK;
}

OfxStatus onDescribeInContext(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs) {
    // A context the plugin did not declare is a feature it lacks (the specification's status).
    if (getString(inArgs, kOfxImageEffectPropContext) != kOfxImageEffectContextGeneral)
        return kOfxStatErrMissingHostFeature;
    defineClips(effect);
    ParamDef d;
    check(gEffect->getParamSet(effect, &d.set));
    describeMain(d);
    describeCamera(d);
    describeAdvanced(d);
    describeSsdo(d);
    describeMethodParams(d);
    describePage(d);
    return kOfxStatOK;
}

} // namespace obscura::ofx
