// Reading the node's parameters into Settings (ofx_params.h).
#include "ofx_params.h"

#include "ofx_suites.h"

#include "core/devices.h"
#include "core/methods.h"

#include <algorithm>
#include <iterator>
#include <mutex>
#include <string>
#include <vector>

namespace obscura::ofx {

namespace {

// A parameter's value at time `t`; a choice clamps its stored index to the options.
int choiceAt(OfxParamHandle h, OfxTime t, int count) {
    int v = 0;
    check(gParam->paramGetValueAtTime(h, t, &v));
    return std::clamp(v, 0, count - 1);
}
int intAt(OfxParamHandle h, OfxTime t) {
    int v = 0;
    check(gParam->paramGetValueAtTime(h, t, &v));
    return v;
}
double doubleAt(OfxParamHandle h, OfxTime t) {
    double v = 0;
    check(gParam->paramGetValueAtTime(h, t, &v));
    return v;
}
void rgbAt(OfxParamHandle h, OfxTime t, float out[3]) {
    double r = 0, g = 0, b = 0;
    check(gParam->paramGetValueAtTime(h, t, &r, &g, &b));
    out[0] = (float)r, out[1] = (float)g, out[2] = (float)b;
}
std::string stringAt(OfxParamHandle h, OfxTime t) {
    char* v = nullptr;
    check(gParam->paramGetValueAtTime(h, t, &v));
    return v ? std::string(v) : std::string();
}

// "auto" means a real GPU when there is one. Probing costs a context creation, so the
// answer (a property of the machine, not of an instance) is found once per process.
std::string resolveDevice(const std::string& requested) {
    if (requested != "auto") return requested;
    static std::once_flag once;
    static bool hardware = false;
    std::call_once(once, [] {
        try {
            Settings probe;
            probe.device = "auto";
            hardware = chooseDevice(probe).hardware;
        } catch (...) {
            hardware = false;
        }
    });
    return hardware ? "auto" : "cpu";
}

// The methods' own parameters the node offers, from the method table; the rest keep the
// Settings defaults.
void readMethodParams(const Instance& in, OfxTime t, Settings& s) {
    const std::vector<const MethodParam*> own = allMethodParams();
    for (size_t i = 0; i < own.size(); ++i) {
        if (!own[i]->ofx) continue;  // not offered: the Settings default stands
        if (own[i]->boolField) s.*(own[i]->boolField) = intAt(in.methodParams[i], t) != 0;
        else if (own[i]->intField) s.*(own[i]->intField) = intAt(in.methodParams[i], t);
        else s.*(own[i]->floatField) = (float)fromHostValue(*own[i], doubleAt(in.methodParams[i], t));
    }
}

// The camera group and the frame's screen-radius cap.
void readCamera(const Instance& in, OfxTime t, Params& p) {
    const int projection = choiceAt(in.projection, t, (int)std::size(kProjections));
    p.projection = projection == 1 ? Projection::Orthographic : Projection::Perspective;
    p.filmBack = projection == 2;
    p.fovDeg = doubleAt(in.fov, t);
    p.focalMm = doubleAt(in.focal, t);
    p.apertureMm = doubleAt(in.aperture, t);
    p.orthoWidth = doubleAt(in.orthoWidth, t);
    p.cameraToWorld = stringAt(in.cameraToWorld, t);
    const DepthEncoding encodings[] = {DepthEncoding::Planar, DepthEncoding::Radial, DepthEncoding::Inverse,
                                       DepthEncoding::Normalized};
    p.depthEncoding = encodings[choiceAt(in.depthKind, t, (int)std::size(kDepthKinds))];
    p.depthKind = decodedKind(p.depthEncoding);
    p.depthRange[0] = doubleAt(in.depthNear, t);
    p.depthRange[1] = doubleAt(in.depthFar, t);
    // Without a Normal clip the normals come from the depth, as the CLI's for a file without a normal layer.
    const NormalSpace spaces[] = {NormalSpace::World, NormalSpace::Camera, NormalSpace::Depth};
    p.normalSpace = connected(in.normal) ? spaces[choiceAt(in.normalSpace, t, 3)] : NormalSpace::Depth;
    p.maxScreenRadius = std::max(0.0, doubleAt(in.maxScreenRadius, t));
}

} // namespace

std::vector<const char*> giMethods() {
    std::vector<const char*> names;
    for (const MethodInfo& m : methods())
        if (methodOutputs(m.name, "gi")) names.push_back(m.name);
    return names;
}

int ssdoGiMethodIndex() {
    const std::vector<const char*> names = giMethods();
    for (size_t i = 0; i < names.size(); ++i)
        if (std::string(names[i]) == "ssdo") return (int)i;
    return 0;
}

std::string methodFor(const OutputOption& o, int method, int giMethod) {
    if (!o.light) return methods()[std::clamp(method, 0, (int)methods().size() - 1)].name;
    if (o.kind == OutputKind::Directional) return "ssdo";
    const std::vector<const char*> gi = giMethods();
    return gi[std::clamp(giMethod, 0, (int)gi.size() - 1)];
}

Params readParams(const Instance& in, OfxTime t) {
    Params p;
    const OutputOption& o = kOutputOptions[choiceAt(in.output_, t, kOutputCount)];
    p.output = o.kind;
    p.strength = std::clamp(doubleAt(in.strength, t), 0.0, 1.0);
    Settings& s = p.settings;
    s.method = methodFor(o, intAt(in.method, t), intAt(in.giMethod, t));
    s.bounce = o.bounce;
    s.ssdoSamples = intAt(in.ssdoSamples, t);
    s.interleave = intAt(in.interleave, t);
    rgbAt(in.skyColour, t, s.skyRadiance);
    for (float& c : s.skyRadiance) c = std::clamp(c, 0.0f, kMaxLight);  // a colour picker allows any
    s.envRotationDeg = (float)doubleAt(in.envRotation, t);
    s.envIntensity = (float)doubleAt(in.envIntensity, t);
    s.zUp = choiceAt(in.upAxis, t, (int)std::size(kUpAxes)) == 1;
    p.envPath = stringAt(in.envMap, t);
    p.timesAlbedo = intAt(in.timesAlbedo, t) != 0;
    s.radius = (float)doubleAt(in.radius, t);
    s.directions = intAt(in.directions, t);
    s.steps = intAt(in.steps, t);
    s.weighting = choiceAt(in.weighting, t, 2) == 0 ? Weighting::Uniform : Weighting::Cosine;
    s.falloff = choiceAt(in.falloff, t, 2) == 0 ? Falloff::Linear : Falloff::None;
    s.blur = intAt(in.blur, t);
    s.skyDepth = (float)doubleAt(in.skyDepth, t);
    s.threads = intAt(in.threads, t);
    readMethodParams(in, t, s);
    s.device = resolveDevice(deviceNames()[choiceAt(in.device, t, (int)deviceNames().size())].name);
    readCamera(in, t, p);
    return p;
}

} // namespace obscura::ofx
