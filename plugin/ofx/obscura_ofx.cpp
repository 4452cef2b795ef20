// obscura as an OpenFX image effect (General context): an adapter from OFX clips,
// parameters and render windows to the operator (core/operator.h).
//
// Coordinates. OFX images live in pixel coordinates, y up, origin bottom-left, rows
// possibly stored bottom-up or top-down (rowBytes < 0); the operator's planes are
// display-window coordinates, y down. The one conversion between them is FrameMap.
//
// Tiles. A render window is computed from the depth/normal data over the window plus
// an apron of the largest projected radius (+ texel snapping + blur), clipped to the
// Depth clip's region of definition, with the radius cap pinned (Settings::
// maxRadiusPixels) so every tile runs the kernel exactly as the whole frame does.
//
// SSDO outputs (DO, GI, relit) run the operator's "ssdo" method with the Source clip
// (the beauty) as the bounce source, as the CLI's --bounce-source beauty: the beauty
// already carries the senders' albedo, so the Albedo clip is not a sender albedo; it only
// forms relit (albedo (DO + GI) / pi) and the "times albedo" radiance (albedo E / pi).
#include "ofx_api.h"

#include "core/camera.h"
#include "core/devices.h"
#include "base/error.h"
#include "core/methods.h"
#include "core/operator.h"
#include "core/settings.h"
#include "core/settings_schema.h"
#include "io/environment_map.h"
#include "io/exr_file.h"


#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <sstream>
#include <string>
#include <vector>

#define OBSCURA_OFX_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

using namespace obscura;

// ---------------------------------------------------------------------------
// Host suites: fetched once at load, read-only afterwards.
// ---------------------------------------------------------------------------

OfxHost* gHost = nullptr;
const OfxPropertySuiteV1* gProp = nullptr;
const OfxImageEffectSuiteV1* gEffect = nullptr;
const OfxParameterSuiteV1* gParam = nullptr;
const OfxMessageSuiteV1* gMessage = nullptr;  // optional

constexpr const char* kPluginId = "io.github.obscura.AmbientOcclusion";
constexpr unsigned kVersionMajor = OBSCURA_OFX_VERSION_MAJOR;
constexpr unsigned kVersionMinor = OBSCURA_OFX_VERSION_MINOR;

// Clips.
constexpr const char* kClipSource = kOfxImageEffectSimpleSourceClipName;
constexpr const char* kClipDepth = "Depth";
constexpr const char* kClipNormal = "Normal";
constexpr const char* kClipPosition = "Position";
constexpr const char* kClipAlbedo = "Albedo";
constexpr const char* kClipOutput = kOfxImageEffectOutputClipName;

// Parameters (names are also script names).
constexpr const char* kParamOutput = "output";
constexpr const char* kParamStrength = "strength";
constexpr const char* kParamMethod = "method";
constexpr const char* kParamRadius = "radius";
constexpr const char* kParamDirections = "directions";
constexpr const char* kParamSteps = "steps";
constexpr const char* kParamWeighting = "weighting";
constexpr const char* kParamFalloff = "falloff";
constexpr const char* kParamBlur = "blur";
constexpr const char* kParamProjection = "projection";
constexpr const char* kParamFov = "fovDeg";
constexpr const char* kParamOrthoWidth = "orthoWidth";
constexpr const char* kParamCameraToWorld = "cameraToWorld";
constexpr const char* kParamDepthKind = "depthKind";
constexpr const char* kParamNormalSpace = "normalSpace";
constexpr const char* kParamSkyDepth = "skyDepth";
constexpr const char* kParamMaxScreenRadius = "maxScreenRadius";
constexpr const char* kParamDevice = "device";
constexpr const char* kParamThreads = "threads";
constexpr const char* kParamSsdoSamples = "samples";
constexpr const char* kParamInterleave = "interleave";
constexpr const char* kParamSkyColour = "skyColour";
constexpr const char* kParamEnvMap = "envMap";
constexpr const char* kParamEnvRotation = "envRotation";
constexpr const char* kParamEnvIntensity = "envIntensity";
constexpr const char* kParamUpAxis = "upAxis";
constexpr const char* kParamTimesAlbedo = "timesAlbedo";
constexpr const char* kGroupSsdo = "ssdoGroup";
constexpr const char* kGroupCamera = "cameraGroup";
constexpr const char* kGroupAdvanced = "advancedGroup";
constexpr const char* kPage = "controls";

// What the Output clip carries. Hosts store a choice as its index, so new outputs (DO,
// GI, relit...) are appended to this table, never inserted: saved projects keep meaning.
enum class OutputKind { Ao, BeautyTimesAo, Directional, Indirect, Relit };
struct OutputOption {
    OutputKind kind;
    const char* label;
    bool needsSource;  // reads the Source (beauty) clip
    bool ssdo;         // an SSDO quantity: the method is ssdo whatever the Method parameter says
    bool bounce;       // runs the bounce, reading Source over the window + apron (the senders)
};
const OutputOption kOutputOptions[] = {
    {OutputKind::Ao, "AO", false, false, false},
    {OutputKind::BeautyTimesAo, "Beauty x AO", true, false, false},
    {OutputKind::Directional, "Directional occlusion (DO)", false, true, false},
    {OutputKind::Indirect, "Indirect (GI)", true, true, true},
    {OutputKind::Relit, "Relit", true, true, true},
};
constexpr int kOutputCount = int(sizeof(kOutputOptions) / sizeof(kOutputOptions[0]));

const char* const kUpAxes[] = {"y", "z"};
const char* const kWeightings[] = {"uniform", "cosine"};
const char* const kFalloffs[] = {"linear", "none"};
const char* const kProjections[] = {"perspective", "orthographic"};
const char* const kDepthKinds[] = {"planar", "radial"};
const char* const kNormalSpaces[] = {"world", "camera", "depth"};

template <class T, size_t N>
constexpr int countOf(const T (&)[N]) {
    return int(N);
}

// ---------------------------------------------------------------------------
// Small helpers over the property suite
// ---------------------------------------------------------------------------

struct OfxFailure {
    OfxStatus status;
};

void check(OfxStatus st) {
    if (st != kOfxStatOK) throw OfxFailure{st};
}

std::string getString(OfxPropertySetHandle p, const char* name, int index = 0) {
    char* v = nullptr;
    if (gProp->propGetString(p, name, index, &v) != kOfxStatOK || !v) return {};
    return v;
}

int getInt(OfxPropertySetHandle p, const char* name, int fallback, int index = 0) {
    int v = fallback;
    if (gProp->propGetInt(p, name, index, &v) != kOfxStatOK) return fallback;
    return v;
}

double getDouble(OfxPropertySetHandle p, const char* name, double fallback, int index = 0) {
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
    if (gMessage) gMessage->message(effect, type, nullptr, "%s", text.c_str());
}

// ---------------------------------------------------------------------------
// Per-instance data: clip and parameter handles, and the instance's own environment map
// cache (the only mutable state, behind its mutex; never shared between instances).
// ---------------------------------------------------------------------------

struct EnvironmentCache {
    std::mutex mutex;
    std::string path;
    long long mtimeNs = 0, size = -1;
    std::shared_ptr<const Image> image;
};

struct Instance {
    OfxImageEffectHandle effect = nullptr;
    OfxImageClipHandle source = nullptr, depth = nullptr, normal = nullptr, position = nullptr, albedo = nullptr,
                       output = nullptr;
    OfxParamHandle output_ = nullptr, strength = nullptr, method = nullptr, radius = nullptr, directions = nullptr,
                   steps = nullptr, weighting = nullptr, falloff = nullptr, blur = nullptr, projection = nullptr,
                   fov = nullptr, orthoWidth = nullptr, cameraToWorld = nullptr, depthKind = nullptr,
                   normalSpace = nullptr, skyDepth = nullptr, maxScreenRadius = nullptr, device = nullptr,
                   threads = nullptr;
    OfxParamHandle ssdoSamples = nullptr, interleave = nullptr, skyColour = nullptr, envMap = nullptr,
                   envRotation = nullptr, envIntensity = nullptr, upAxis = nullptr, timesAlbedo = nullptr;
    std::vector<OfxParamHandle> methodParams;  // one per allMethodParams(), in its order
    mutable EnvironmentCache environment;
};

Instance* instanceOf(OfxImageEffectHandle effect) {
    void* p = nullptr;
    check(gProp->propGetPointer(effectProps(effect), kOfxPropInstanceData, 0, &p));
    if (!p) throw OfxFailure{kOfxStatErrBadHandle};
    return static_cast<Instance*>(p);
}

// The parameter values at one time, as the operator wants them.
struct Params {
    OutputKind output = OutputKind::Ao;
    double strength = 1;
    Settings settings;
    Projection projection = Projection::Perspective;
    double fovDeg = 0, orthoWidth = 0;
    std::string cameraToWorld;
    DepthKind depthKind = DepthKind::Planar;
    NormalSpace normalSpace = NormalSpace::World;
    double maxScreenRadius = 0;  // 0 = automatic (frame extent)
    std::string envPath;         // lat-long environment map ("" = the sky colour)
    bool timesAlbedo = false;    // DO / GI as albedo E / pi
};

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

Params readParams(const Instance& in, OfxTime t) {
    Params p;
    const OutputOption& o = kOutputOptions[choiceAt(in.output_, t, kOutputCount)];
    p.output = o.kind;
    p.strength = std::clamp(doubleAt(in.strength, t), 0.0, 1.0);
    Settings& s = p.settings;
    s.method = o.ssdo ? "ssdo" : methods()[choiceAt(in.method, t, (int)methods().size())].name;
    s.bounce = o.bounce;
    s.ssdoSamples = intAt(in.ssdoSamples, t);
    s.interleave = intAt(in.interleave, t);
    rgbAt(in.skyColour, t, s.skyRadiance);
    s.envRotationDeg = (float)doubleAt(in.envRotation, t);
    s.envIntensity = (float)doubleAt(in.envIntensity, t);
    s.zUp = choiceAt(in.upAxis, t, countOf(kUpAxes)) == 1;
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
    const std::vector<const MethodParam*> own = allMethodParams();
    for (size_t i = 0; i < own.size(); ++i) {
        if (!own[i]->ofx) continue;  // not offered: the Settings default stands
        if (own[i]->boolField) s.*(own[i]->boolField) = intAt(in.methodParams[i], t) != 0;
        else if (own[i]->intField) s.*(own[i]->intField) = intAt(in.methodParams[i], t);
        else s.*(own[i]->floatField) = (float)fromHostValue(*own[i], doubleAt(in.methodParams[i], t));
    }
    s.device = resolveDevice(deviceNames()[choiceAt(in.device, t, (int)deviceNames().size())].name);
    p.projection = choiceAt(in.projection, t, 2) == 0 ? Projection::Perspective : Projection::Orthographic;
    p.fovDeg = doubleAt(in.fov, t);
    p.orthoWidth = doubleAt(in.orthoWidth, t);
    p.cameraToWorld = stringAt(in.cameraToWorld, t);
    p.depthKind = choiceAt(in.depthKind, t, 2) == 0 ? DepthKind::Planar : DepthKind::Radial;
    // Without a Normal clip the normals come from the depth, as the CLI's for a file without a normal layer.
    const NormalSpace spaces[] = {NormalSpace::World, NormalSpace::Camera, NormalSpace::Depth};
    p.normalSpace = connected(in.normal) ? spaces[choiceAt(in.normalSpace, t, 3)] : NormalSpace::Depth;
    p.maxScreenRadius = std::max(0.0, doubleAt(in.maxScreenRadius, t));
    return p;
}

// 16 numbers, row-major, OpenGL convention: the same as the CLI's --camera-to-world.
glm::dmat4 parseCameraToWorld(const std::string& text) {
    std::vector<double> v;
    std::string item;
    std::stringstream ss(text);
    while (std::getline(ss, item, ',')) {
        const size_t a = item.find_first_not_of(" \t\r\n"), b = item.find_last_not_of(" \t\r\n");
        if (a == std::string::npos) throw Error("camera-to-world: empty number in '" + text + "'");
        item = item.substr(a, b - a + 1);
        char* end = nullptr;
        const double x = std::strtod(item.c_str(), &end);
        if (end == item.c_str() || *end != '\0' || !std::isfinite(x))
            throw Error("camera-to-world: '" + item + "' is not a number");
        v.push_back(x);
    }
    if (v.size() != 16) throw Error("camera-to-world expects 16 comma-separated numbers, got " + std::to_string(v.size()));
    glm::dmat4 m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m[c][r] = v[r * 4 + c];
    if (std::fabs(v[12]) > 1e-6 || std::fabs(v[13]) > 1e-6 || std::fabs(v[14]) > 1e-6 || std::fabs(v[15] - 1) > 1e-6 ||
        std::fabs(glm::determinant(glm::dmat3(m))) < 1e-12)
        throw Error("camera-to-world must be an invertible affine 4x4 (rows, last row 0 0 0 1)");
    return m;
}

// ---------------------------------------------------------------------------
// Geometry: OFX pixel coordinates (y up) <-> the operator's display coordinates (y down)
// ---------------------------------------------------------------------------

// Half-open pixel rectangle in OFX pixel coordinates (y up).
struct PixRect {
    int x1 = 0, y1 = 0, x2 = 0, y2 = 0;
    bool empty() const { return x2 <= x1 || y2 <= y1; }
    int width() const { return x2 - x1; }
    int height() const { return y2 - y1; }
};

PixRect intersect(const PixRect& a, const PixRect& b) {
    PixRect r{std::max(a.x1, b.x1), std::max(a.y1, b.y1), std::min(a.x2, b.x2), std::min(a.y2, b.y2)};
    return r.empty() ? PixRect{} : r;
}
PixRect grow(const PixRect& a, int by) { return {a.x1 - by, a.y1 - by, a.x2 + by, a.y2 + by}; }

// The frame of one render: the project's pixel aspect ratio, the render scale, the display
// window (the project extent) and the region of definition of the depth pass (the data
// window), the last two in pixels at the render scale. Regions of interest, regions of
// definition and fetch regions are canonical; render windows and image bounds are pixels.
struct FrameMap {
    double par = 1;
    double sx = 1, sy = 1;            // render scale (proxy renders: 0.5, ...)
    int displayW = 0, displayH = 0;  // display window: OFX pixels [0, W) x [0, H)
    PixRect rod;                      // Depth clip's region of definition, OFX pixels

    // Canonical -> pixel: x * scale / PAR, y * scale.
    PixRect toPixels(const OfxRectD& r) const {
        const double kx = sx / par;
        return {(int)std::floor(r.x1 * kx + 1e-6), (int)std::floor(r.y1 * sy + 1e-6), (int)std::ceil(r.x2 * kx - 1e-6),
                (int)std::ceil(r.y2 * sy - 1e-6)};
    }
    OfxRectD toCanonical(const PixRect& r) const {
        if (r.empty()) return {0, 0, 0, 0};
        const double kx = par / sx;
        return {r.x1 * kx, r.y1 / sy, r.x2 * kx, r.y2 / sy};
    }
    // The width / height of one pixel at this render scale, which is what the camera sees.
    double pixelAspect() const { return par * sy / sx; }
    // The single flip: an OFX pixel rectangle as a display-window box (y down).
    Box2i toDisplay(const PixRect& r) const { return Box2i{r.x1, displayH - r.y2, r.x2, displayH - r.y1}; }
    // Row `row` (y down) of the display box of `r` is OFX row:
    int ofxRow(const PixRect& r, int row) const { return r.y2 - 1 - row; }
};

// `actionArgs`: the RoI or render action's in-args, which carry the render scale.
FrameMap frameMap(const Instance& in, OfxTime t, OfxPropertySetHandle actionArgs) {
    FrameMap f;
    OfxPropertySetHandle props = effectProps(in.effect);
    f.par = getDouble(props, kOfxImageEffectPropProjectPixelAspectRatio, 1.0);
    if (!(f.par > 0)) f.par = 1;
    f.sx = getDouble(actionArgs, kOfxImageEffectPropRenderScale, 1.0, 0);
    f.sy = getDouble(actionArgs, kOfxImageEffectPropRenderScale, 1.0, 1);
    if (!(f.sx > 0 && f.sy > 0)) throw Error("the host gives an invalid render scale");
    double extent[2] = {0, 0};
    if (gProp->propGetDoubleN(props, kOfxImageEffectPropProjectExtent, 2, extent) != kOfxStatOK)
        throw Error("the host gives no project extent (the display window the camera's field of view spans)");
    f.displayW = (int)std::lround(extent[0] * f.sx / f.par);
    f.displayH = (int)std::lround(extent[1] * f.sy);
    OfxRectD rod{0, 0, 0, 0};
    check(gEffect->clipGetRegionOfDefinition(in.depth, t, &rod));
    f.rod = f.toPixels(rod);
    return f;
}

// The parameters for a render at the frame's scale. Blur and Max Screen Radius are in
// full-resolution pixels, so a proxy render scales them; the radius is in world units and
// scales through the camera (whose display window is at the render scale).
Params paramsAt(const Instance& in, OfxTime t, const FrameMap& f) {
    Params p = readParams(in, t);
    if (p.settings.blur > 0) p.settings.blur = std::max(1, (int)std::lround(p.settings.blur * f.sx));
    p.maxScreenRadius *= f.sx;
    return p;
}

Camera makeCamera(const Params& p, const FrameMap& f) {
    Camera cam;
    if (p.projection == Projection::Perspective) {
        if (!(p.fovDeg > 0 && p.fovDeg < 180)) throw Error("the field of view must be between 0 and 180 degrees");
        cam = Camera::perspectiveFromFov(p.fovDeg * 3.14159265358979323846 / 180, f.displayW, f.displayH,
                                         f.pixelAspect());
    } else {
        if (!(p.orthoWidth > 0)) throw Error("the orthographic width must be positive");
        cam = Camera::orthographic(p.orthoWidth, f.displayW, f.displayH, f.pixelAspect());
    }
    const bool hasText = p.cameraToWorld.find_first_not_of(" \t\r\n") != std::string::npos;
    if (hasText) {
        cam.cameraToWorld = parseCameraToWorld(p.cameraToWorld);
        cam.hasPose = true;
    }
    cam.source = "OFX parameters";
    return cam;
}

// The cap on the projected radius, the same for every tile of the frame: the parameter,
// or with 0 (automatic) the CLI's rule over the whole frame (its extent + 2 pixels).
float radiusCap(const Params& p, const FrameMap& f) {
    if (p.maxScreenRadius > 0) return (float)p.maxScreenRadius;
    return (float)std::max(f.rod.width(), f.rod.height()) + 2.0f;
}

// How far from a pixel its AO reads, in pixels: the projected radius (bounded by the cap;
// for an orthographic camera R * pixels-per-unit), the texel snapping of the samples, then
// the two blur passes. Known before any depth is fetched, so it can answer the RoI action.
//
// SSDO places its samples in world space within r_max and does not bound their projection
// by the cap: orthographic, that reach is exactly R * pixels-per-unit; in perspective the cap
// stands for it, which holds wherever r_max projects within the cap (surfaces farther from
// the eye than about fx r_max / cap + r_max). Its blur gathers the interleaving block (the
// interleave width, or Blur when set: resolvedBlur), and the bounce reads Source under the same apron.

int apronPixels(const Params& p, const Camera& cam, float cap) {
    const bool ssdo = p.settings.method == "ssdo";
    double reach = cap;
    if (cam.projection == Projection::Orthographic)
        reach = ssdo ? std::min<double>((double)p.settings.radius * cam.fx, 1e7)
                     : std::min<double>(p.settings.radius * cam.fx, cap);
    const int blur = resolvedBlur(p.settings);
    const MethodInfo* m = findMethod(p.settings.method);
    const int extra = m && m->extraApron ? m->extraApron(p.settings) : 0;
    // Normals from the depth read two texels each way: the apron's texels get theirs as the whole frame's.
    const int normals = p.normalSpace == NormalSpace::Depth ? 2 : 0;
    return (int)std::ceil(reach) + 2 + std::max(blur, 0) + extra + normals;
}

// The depth/normal pixels a render window reads.
PixRect dataRegion(const PixRect& window, int apron, const FrameMap& f) { return intersect(grow(window, apron), f.rod); }

// ---------------------------------------------------------------------------
// Images fetched from clips
// ---------------------------------------------------------------------------

class ClipImage {
public:
    ClipImage() = default;
    ClipImage(const ClipImage&) = delete;
    ClipImage& operator=(const ClipImage&) = delete;
    ~ClipImage() {
        if (handle_) gEffect->clipReleaseImage(handle_);
    }

    // region = nullptr: the whole image the host offers (the render window for Output).
    bool fetch(OfxImageClipHandle clip, OfxTime t, const OfxRectD* region, const char* what) {
        if (gEffect->clipGetImage(clip, t, region, &handle_) != kOfxStatOK || !handle_) {
            handle_ = nullptr;
            return false;
        }
        const std::string depth = getString(handle_, kOfxImageEffectPropPixelDepth);
        if (depth != kOfxBitDepthFloat)
            throw Error(std::string("the ") + what + " image is " + depth + "; only 32-bit float is supported");
        const std::string comps = getString(handle_, kOfxImageEffectPropComponents);
        comps_ = comps == kOfxImageComponentRGBA ? 4 : comps == kOfxImageComponentRGB ? 3 : comps == kOfxImageComponentAlpha ? 1 : 0;
        if (comps_ == 0) throw Error(std::string("the ") + what + " image has unsupported components " + comps);
        void* data = nullptr;
        check(gProp->propGetPointer(handle_, kOfxImagePropData, 0, &data));
        data_ = static_cast<char*>(data);
        int b[4] = {0, 0, 0, 0};
        check(gProp->propGetIntN(handle_, kOfxImagePropBounds, 4, b));
        bounds_ = {b[0], b[1], b[2], b[3]};
        rowBytes_ = getInt(handle_, kOfxImagePropRowBytes, 0);
        if (!data_ && !bounds_.empty()) throw Error(std::string("the ") + what + " image has no pixels");
        return true;
    }

    int components() const { return comps_; }
    const PixRect& bounds() const { return bounds_; }
    // The pixel at OFX pixel (x, y), or nullptr outside the image's bounds.
    float* pixel(int x, int y) const {
        if (x < bounds_.x1 || x >= bounds_.x2 || y < bounds_.y1 || y >= bounds_.y2) return nullptr;
        return reinterpret_cast<float*>(data_ + (std::ptrdiff_t)(y - bounds_.y1) * rowBytes_) + (size_t)(x - bounds_.x1) * comps_;
    }

private:
    OfxPropertySetHandle handle_ = nullptr;
    char* data_ = nullptr;
    PixRect bounds_;
    int rowBytes_ = 0;
    int comps_ = 0;
};

// Copies `channels` channels of `img` over OFX region `r` into a packed display-ordered
// (y down) plane; pixels the image does not cover read `fill`.
Image toDisplayPlane(const ClipImage& img, const PixRect& r, const FrameMap& f, int channels, float fill) {
    Image out(r.width(), r.height(), channels, fill);
    for (int row = 0; row < r.height(); ++row) {
        const int y = f.ofxRow(r, row);
        for (int col = 0; col < r.width(); ++col) {
            const float* p = img.pixel(r.x1 + col, y);
            if (!p) continue;
            float* o = out.at(col, row);
            for (int c = 0; c < channels; ++c) o[c] = c < img.components() ? p[c] : fill;
        }
    }
    return out;
}

// ---------------------------------------------------------------------------
// The environment map: plugin/io's reader (the CLI's and Python's), converted to the working
// space, cached per instance by path, modification time and size.
// ---------------------------------------------------------------------------

std::shared_ptr<const Image> environmentFor(const Instance& in, const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0) throw FileError(path, "the environment map does not exist");
    const long long mtime = (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec;
    EnvironmentCache& cache = in.environment;
    std::lock_guard<std::mutex> lock(cache.mutex);
    if (!cache.image || cache.path != path || cache.mtimeNs != mtime || cache.size != (long long)st.st_size) {
        cache.image.reset();
        // The CLI's default --max-pixels: the header's size is checked before allocating.
        cache.image = std::make_shared<const Image>(readEnvironmentMap(path, "", kDefaultMaxPixels).rgb);
        cache.path = path;
        cache.mtimeNs = mtime;
        cache.size = (long long)st.st_size;
    }
    return cache.image;
}

// ---------------------------------------------------------------------------
// Actions
// ---------------------------------------------------------------------------

OfxStatus onLoad() {
    if (!gHost) return kOfxStatErrMissingHostFeature;
    gProp = static_cast<const OfxPropertySuiteV1*>(gHost->fetchSuite(gHost->host, kOfxPropertySuite, 1));
    gEffect = static_cast<const OfxImageEffectSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxImageEffectSuite, 1));
    gParam = static_cast<const OfxParameterSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxParameterSuite, 1));
    gMessage = static_cast<const OfxMessageSuiteV1*>(gHost->fetchSuite(gHost->host, kOfxMessageSuite, 1));
    if (!gProp || !gEffect || !gParam) return kOfxStatErrMissingHostFeature;
    return kOfxStatOK;
}

// OFX 1.5 colour management: the host offers a style on its own properties, the plugin
// declares the one it supports at describe (Basic: it only names basic spaces, ofx_raw and
// clip cross-references), and the host puts the negotiated style on each instance. A
// pre-1.5 host sets nothing, which means none.
bool colourManaged(OfxPropertySetHandle p) {
    const std::string style = getString(p, kOfxImageEffectPropColourManagementStyle);
    return !style.empty() && style != kOfxImageEffectColourManagementNone;
}

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

struct ParamDef {
    OfxParamSetHandle set;
    std::vector<std::string> topLevel;
    std::vector<std::string> defined;  // every name, to add the method table's remaining parameters

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
        if (parent)
            gProp->propSetString(p, kOfxParamPropParent, 0, parent);
        else
            topLevel.push_back(name);
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
    void group(const char* name, const char* label) {
        OfxPropertySetHandle p = define(kOfxParamTypeGroup, name, label, nullptr);
        gProp->propSetInt(p, kOfxParamPropGroupOpen, 0, 1);
    }
};

OfxStatus onDescribeInContext(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs) {
    // A context the plugin did not declare is a feature it lacks (the specification's status).
    if (getString(inArgs, kOfxImageEffectPropContext) != kOfxImageEffectContextGeneral)
        return kOfxStatErrMissingHostFeature;
    defineClip(effect, kClipSource, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, true, nullptr);
    defineClip(effect, kClipDepth, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, false, nullptr);
    defineClip(effect, kClipNormal, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipPosition, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipAlbedo, {kOfxImageComponentRGBA}, true, nullptr);
    defineClip(effect, kClipOutput, {kOfxImageComponentRGBA, kOfxImageComponentAlpha}, false, nullptr);

    ParamDef d;
    check(gEffect->getParamSet(effect, &d.set));
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
    d.choice(kParamMethod, "Method", "Occlusion method for the AO outputs (--method); DO, GI and Relit always use ssdo",
             methodChoices, 0);
    d.real(kParamRadius, "Radius", "Radius in world units (--radius)", 1.0, lo(kParamRadius), hi(kParamRadius), 0.01, 10.0);
    d.integer(kParamDirections, "Directions", "Slices per pixel (--directions)", 8, 1, 256, 1, 32);
    d.integer(kParamSteps, "Steps", "Samples per slice (--steps)", 8, 1, 256, 1, 32);
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

    d.group(kGroupCamera, "Camera");
    d.choice(kParamProjection, "Projection", "Perspective (field of view) or orthographic (width) camera",
             {kProjections[0], kProjections[1]}, 0, kGroupCamera);
    d.real(kParamFov, "Field of View", "Horizontal field of view across the project format, degrees (--fov-deg)",
           39.5977, lo(kParamFov), hi(kParamFov), 1.0, 120.0, kGroupCamera, kOfxParamDoubleTypeAngle);
    d.real(kParamOrthoWidth, "Ortho Width", "World units across the project format (--ortho-width)", 10.0, lo(kParamOrthoWidth), hi(kParamOrthoWidth),
           0.1, 100.0, kGroupCamera);
    {
        OfxPropertySetHandle p = d.define(kOfxParamTypeString, kParamCameraToWorld, "Camera to World",
                                          "16 numbers m00,...,m33, row-major, OpenGL convention (camera looks down -Z); "
                                          "needed for world-space normals (--camera-to-world)",
                                          kGroupCamera);
        gProp->propSetString(p, kOfxParamPropDefault, 0, "");
        gProp->propSetString(p, kOfxParamPropStringMode, 0, kOfxParamStringIsSingleLine);
        gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    }
    d.choice(kParamDepthKind, "Depth", "planar: camera-space Z; radial: distance to the eye (--depth)",
             {kDepthKinds[0], kDepthKinds[1]}, 0, kGroupCamera);
    d.choice(kParamNormalSpace, "Normals",
             "Space of the Normal clip's RGB, or depth: reconstructed from the Depth clip, as they are without "
             "a Normal clip (--normals)",
             {kNormalSpaces[0], kNormalSpaces[1], kNormalSpaces[2]}, 0, kGroupCamera);

    d.group(kGroupAdvanced, "Advanced");
    d.real(kParamSkyDepth, "Sky Depth", "Depth at or beyond which a pixel is sky (--sky-depth)", 1e9, lo(kParamSkyDepth), hi(kParamSkyDepth), 1.0,
           1e10, kGroupAdvanced);
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

    d.group(kGroupSsdo, "SSDO");
    d.integer(kParamSsdoSamples, "Samples", "Sample set N shared by an interleaving block (--samples)", 64, 1, 4096, 1,
              256, kGroupSsdo);
    d.integer(kParamInterleave, "Interleave",
              "M: an M x M block of pixels splits the sample set, N / M^2 each, gathered back by a blur (--interleave)",
              2, 1, 8, 1, 8, kGroupSsdo);
    {
        OfxPropertySetHandle p = d.define(kOfxParamTypeRGB, kParamSkyColour, "Sky Colour",
                                          "Constant sky radiance when there is no environment map (--sky)", kGroupSsdo);
        for (int c = 0; c < 3; ++c) gProp->propSetDouble(p, kOfxParamPropDefault, c, 1.0);
    }
    {
        OfxPropertySetHandle p = d.define(kOfxParamTypeString, kParamEnvMap, "Environment Map",
                                          "Lat-long radiance map, any format OpenImageIO reads, converted from its colour space to the working space as the CLI does "
                                          "(--env); empty = the sky colour",
                                          kGroupSsdo);
        gProp->propSetString(p, kOfxParamPropDefault, 0, "");
        gProp->propSetString(p, kOfxParamPropStringMode, 0, kOfxParamStringIsFilePath);
        gProp->propSetInt(p, kOfxParamPropStringFilePathExists, 0, 1);
        gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    }
    d.real(kParamEnvRotation, "Env Rotation", "Turns the environment about the up axis, degrees (--env-rotate)", 0.0,
           lo(kParamEnvRotation), hi(kParamEnvRotation), -180.0, 180.0, kGroupSsdo, kOfxParamDoubleTypeAngle);
    d.real(kParamEnvIntensity, "Env Intensity", "Multiplies the environment map (--env-intensity)", 1.0, lo(kParamEnvIntensity), hi(kParamEnvIntensity), 0.0,
           4.0, kGroupSsdo);
    d.choice(kParamUpAxis, "Up Axis", "World up axis for the environment: y, or z for Blender renders (--up)",
             {kUpAxes[0], kUpAxes[1]}, 0, kGroupSsdo);
    {
        OfxPropertySetHandle p = d.define(kOfxParamTypeBoolean, kParamTimesAlbedo, "Times Albedo",
                                          "DO and GI as albedo x E / pi (needs the Albedo clip), the outgoing radiance "
                                          "of the diffuse receiver, instead of irradiance E (--times-albedo)",
                                          kGroupSsdo);
        gProp->propSetInt(p, kOfxParamPropDefault, 0, 0);
        gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
    }

    // The methods' own parameters that have no control above (ssao's, rtao's), from the method
    // table, with its ranges and the Settings defaults, in a group per method.
    const Settings defaults;
    for (const MethodInfo& m : methods()) {
        bool grouped = false;
        for (const MethodParam& mp : m.params) {
            if (!mp.ofx || std::find(d.defined.begin(), d.defined.end(), mp.key) != d.defined.end()) continue;
            if (!grouped) d.group(m.name, m.name);
            grouped = true;
            if (mp.boolField) {
                OfxPropertySetHandle p = d.define(kOfxParamTypeBoolean, mp.key, mp.key, mp.help, m.name);
                gProp->propSetInt(p, kOfxParamPropDefault, 0, defaults.*(mp.boolField) ? 1 : 0);
                gProp->propSetInt(p, kOfxParamPropAnimates, 0, 0);
            } else if (mp.intField) {
                d.integer(mp.key, mp.key, mp.help, defaults.*(mp.intField), (int)mp.min, (int)mp.max, (int)mp.min,
                          (int)std::min(mp.max, 256.0), m.name);
            } else {
                // Named values (auto, inf) are plain numbers here: their hostValue, inside the range.
                double def = defaults.*(mp.floatField), lo = mp.min, hi = std::min(mp.max, 1e9);
                for (const NamedValue& n : mp.named) {
                    if (def == n.value) def = n.hostValue;
                    lo = std::min(lo, n.hostValue);
                    hi = std::max(hi, n.hostValue);
                }
                d.real(mp.key, mp.key, mp.help, def, lo, hi, mp.min, std::min(mp.max, 10.0), m.name);
            }
        }
    }

    OfxPropertySetHandle page = d.define(kOfxParamTypePage, kPage, "Controls", nullptr);
    d.topLevel.pop_back();  // the page itself
    for (int i = 0; i < (int)d.topLevel.size(); ++i)
        gProp->propSetString(page, kOfxParamPropPageChild, i, d.topLevel[i].c_str());
    return kOfxStatOK;
}

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

void updateEnabled(const Instance& in) {
    int projection = 0, normals = 0, output = 0;
    gParam->paramGetValue(in.projection, &projection);
    gParam->paramGetValue(in.normalSpace, &normals);
    gParam->paramGetValue(in.output_, &output);
    const OutputKind kind = kOutputOptions[std::clamp(output, 0, kOutputCount - 1)].kind;
    auto enable = [](OfxParamHandle h, bool on) {
        OfxPropertySetHandle p = nullptr;
        if (gParam->paramGetPropertySet(h, &p) == kOfxStatOK) gProp->propSetInt(p, kOfxParamPropEnabled, 0, on ? 1 : 0);
    };
    enable(in.fov, projection == 0);
    enable(in.orthoWidth, projection == 1);
    enable(in.cameraToWorld, normals == 0);
    // DO, GI and Relit are SSDO whatever the method; Times Albedo concerns DO and GI only.
    const bool ao = kind == OutputKind::Ao || kind == OutputKind::BeautyTimesAo;
    enable(in.method, ao);
    // What the method does not read is greyed out, from the same table the CLI and Python refuse by.
    int methodIndex = 0;
    gParam->paramGetValue(in.method, &methodIndex);
    const std::string method = ao ? methods()[std::clamp(methodIndex, 0, (int)methods().size() - 1)].name : "ssdo";
    const std::vector<const MethodParam*> own = allMethodParams();
    for (size_t i = 0; i < own.size(); ++i)
        if (in.methodParams[i]) enable(in.methodParams[i], settingRefusal(method, own[i]->key, Spelling::Key).empty());
    OfxParamSetHandle set = nullptr;
    gEffect->getParamSet(in.effect, &set);
    for (const MethodOption& o : methodOptions())
        if (o.ofx) enable(param(set, o.ofx), settingRefusal(method, o.ofx, Spelling::Key).empty());
    enable(in.timesAlbedo, kind == OutputKind::Directional || kind == OutputKind::Indirect);
}

OfxStatus onCreateInstance(OfxImageEffectHandle effect) {
    auto in = std::make_unique<Instance>();
    in->effect = effect;
    in->source = clip(effect, kClipSource);
    in->depth = clip(effect, kClipDepth);
    in->normal = clip(effect, kClipNormal);
    in->position = clip(effect, kClipPosition);
    in->albedo = clip(effect, kClipAlbedo);
    in->output = clip(effect, kClipOutput);
    OfxParamSetHandle set = nullptr;
    check(gEffect->getParamSet(effect, &set));
    in->output_ = param(set, kParamOutput);
    in->strength = param(set, kParamStrength);
    in->method = param(set, kParamMethod);
    in->radius = param(set, kParamRadius);
    in->directions = param(set, kParamDirections);
    in->steps = param(set, kParamSteps);
    in->weighting = param(set, kParamWeighting);
    in->falloff = param(set, kParamFalloff);
    in->blur = param(set, kParamBlur);
    in->projection = param(set, kParamProjection);
    in->fov = param(set, kParamFov);
    in->orthoWidth = param(set, kParamOrthoWidth);
    in->cameraToWorld = param(set, kParamCameraToWorld);
    in->depthKind = param(set, kParamDepthKind);
    in->normalSpace = param(set, kParamNormalSpace);
    in->skyDepth = param(set, kParamSkyDepth);
    in->maxScreenRadius = param(set, kParamMaxScreenRadius);
    in->device = param(set, kParamDevice);
    in->threads = param(set, kParamThreads);
    in->ssdoSamples = param(set, kParamSsdoSamples);
    in->interleave = param(set, kParamInterleave);
    in->skyColour = param(set, kParamSkyColour);
    in->envMap = param(set, kParamEnvMap);
    in->envRotation = param(set, kParamEnvRotation);
    in->envIntensity = param(set, kParamEnvIntensity);
    in->upAxis = param(set, kParamUpAxis);
    in->timesAlbedo = param(set, kParamTimesAlbedo);
    for (const MethodParam* mp : allMethodParams()) in->methodParams.push_back(mp->ofx ? param(set, mp->key) : nullptr);
    check(gProp->propSetPointer(effectProps(effect), kOfxPropInstanceData, 0, in.get()));
    updateEnabled(*in);
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

OfxStatus onGetRegionOfDefinition(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                                  OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    if (!connected(in.depth)) return kOfxStatReplyDefault;
    OfxRectD rod{0, 0, 0, 0};
    check(gEffect->clipGetRegionOfDefinition(in.depth, getDouble(inArgs, kOfxPropTime, 0), &rod));
    // The AO exists where the depth does (the data window, overscan included).
    check(gProp->propSetDoubleN(outArgs, kOfxImageEffectPropRegionOfDefinition, 4, &rod.x1));
    return kOfxStatOK;
}

// What an output reads and computes (regions of interest and render agree through these).
const OutputOption& optionOf(const Params& p) { return kOutputOptions[(int)p.output]; }
// AO outputs with strength 0 compute nothing; the SSDO quantities ignore Strength.
bool computes(const Params& p) { return optionOf(p).ssdo || p.strength > 0; }
bool needsAlbedo(const Params& p) {
    return p.output == OutputKind::Relit ||
           (p.timesAlbedo && (p.output == OutputKind::Directional || p.output == OutputKind::Indirect));
}
// Beauty x AO and Relit keep the Source's alpha (and premultiplication); the rest are opaque.
bool keepsSourceAlpha(OutputKind k) { return k == OutputKind::BeautyTimesAo || k == OutputKind::Relit; }

OfxStatus onGetRegionsOfInterest(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                                 OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    const OfxTime t = getDouble(inArgs, kOfxPropTime, 0);
    OfxRectD region{0, 0, 0, 0};
    check(gProp->propGetDoubleN(inArgs, kOfxImageEffectPropRegionOfInterest, 4, &region.x1));
    const Params p = readParams(in, t);
    const OutputOption& o = optionOf(p);
    const OfxRectD none{0, 0, 0, 0};
    auto setRoi = [&](const char* clipName, const OfxRectD& r) {
        gProp->propSetDoubleN(outArgs, (std::string(kOfxImageClipPropRoI) + clipName).c_str(), 4, &r.x1);
    };
    OfxRectD dataRoi = none;
    if (connected(in.depth)) {
        const FrameMap f = frameMap(in, t, inArgs);
        const Params ps = paramsAt(in, t, f);
        PixRect data;
        if (computes(ps)) {
            const int apron = apronPixels(ps, makeCamera(ps, f), radiusCap(ps, f));
            data = dataRegion(f.toPixels(region), apron, f);
        }
        dataRoi = f.toCanonical(data);
        setRoi(kClipDepth, dataRoi);
        setRoi(kClipNormal, ps.normalSpace == NormalSpace::Depth ? none : dataRoi);
    }
    // Inputs the chosen output does not read are not requested at all. The bounce reads
    // Source (its senders) wherever the depth is read; Albedo is read under the window.
    setRoi(kClipSource, o.bounce ? dataRoi : o.needsSource ? region : none);
    setRoi(kClipPosition, none);
    setRoi(kClipAlbedo, needsAlbedo(p) ? region : none);
    return kOfxStatOK;
}

OfxStatus onGetClipPreferences(OfxImageEffectHandle effect, OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    int outputIndex = 0;
    check(gParam->paramGetValue(in.output_, &outputIndex));
    const OutputOption& o = kOutputOptions[std::clamp(outputIndex, 0, kOutputCount - 1)];
    for (const char* name : {kClipSource, kClipDepth, kClipNormal, kClipPosition, kClipAlbedo, kClipOutput})
        gProp->propSetString(outArgs, (std::string(kOfxImageClipPropDepthPrefix) + name).c_str(), 0, kOfxBitDepthFloat);
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
    int outputIndex = 0;
    check(gParam->paramGetValue(in.output_, &outputIndex));
    const bool colour = kOutputOptions[std::clamp(outputIndex, 0, kOutputCount - 1)].kind != OutputKind::Ao;
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

OfxStatus onRender(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs) {
    const Instance& in = *instanceOf(effect);
    const OfxTime t = getDouble(inArgs, kOfxPropTime, 0);
    int w[4] = {0, 0, 0, 0};
    check(gProp->propGetIntN(inArgs, kOfxImageEffectPropRenderWindow, 4, w));
    const PixRect window{w[0], w[1], w[2], w[3]};
    // Required inputs first: without them a render would be black, not an answer.
    if (!connected(in.depth)) throw Error(std::string("the ") + kClipDepth + " clip is not connected; it is required");
    const FrameMap f = frameMap(in, t, inArgs);
    const Params p = paramsAt(in, t, f);
    const OutputOption& option = optionOf(p);
    const OutputKind kind = p.output;

    ClipImage out;
    if (!out.fetch(in.output, t, nullptr, "Output")) throw Error("the host gave no Output image");

    // Inputs first, so a missing clip is reported before any work.
    if (option.needsSource && !connected(in.source))
        throw Error(std::string("the ") + option.label + " output needs the Source clip" +
                    (option.bounce ? " (the beauty: the bounce source)" : ""));
    const bool withAlbedo = needsAlbedo(p);
    if (withAlbedo && !connected(in.albedo))
        throw Error(std::string("the ") + option.label + " output" + (kind == OutputKind::Relit ? "" : " times albedo") +
                    " needs the Albedo clip");

    // The operator over the render window's data region (display-ordered, y down), or
    // nothing when the AO is off.
    const PixRect data = computes(p) ? dataRegion(window, apronPixels(p, makeCamera(p, f), radiusCap(p, f)), f) : PixRect{};
    OperatorOutputs result;
    const bool computed = computes(p) && !data.empty();
    if (computed) {
        const OfxRectD region = f.toCanonical(data);
        ClipImage depth, normal, radiance;
        if (!depth.fetch(in.depth, t, &region, "Depth")) throw Error("the Depth clip gave no image");
        const bool normals = p.normalSpace != NormalSpace::Depth;
        if (normals && !normal.fetch(in.normal, t, &region, "Normal")) throw Error("the Normal clip gave no image");
        if (normals && normal.components() < 3) throw Error("the Normal clip must be RGB(A): normals are three channels");
        // Holes outside what the host delivered read as sky (depth 0) and missing normals.
        const Image depthPlane = toDisplayPlane(depth, data, f, 1, 0.0f);
        const Image normalPlane = normals ? toDisplayPlane(normal, data, f, 3, 0.0f) : Image();
        Image radiancePlane;
        if (option.bounce) {
            if (!radiance.fetch(in.source, t, &region, "Source")) throw Error("the Source clip gave no image");
            if (radiance.components() < 3) throw Error("the bounce needs an RGB(A) Source clip");
            radiancePlane = toDisplayPlane(radiance, data, f, 3, 0.0f);
        }
        std::shared_ptr<const Image> environment;
        const bool ssdo = p.settings.method == "ssdo";
        if (ssdo && p.envPath.find_first_not_of(" \t\r\n") != std::string::npos)
            environment = environmentFor(in, p.envPath);
        if (gEffect->abort(effect)) return kOfxStatOK;

        OperatorInputs oi;
        oi.displayWindow = Box2i{0, 0, f.displayW, f.displayH};
        oi.dataWindow = f.toDisplay(data);
        oi.depth = depthPlane.view();
        if (normals) oi.normal = normalPlane.view();
        oi.depthKind = p.depthKind;
        oi.normalSpace = p.normalSpace;
        oi.camera = makeCamera(p, f);
        if (!radiancePlane.empty()) oi.radiance = radiancePlane.view();
        oi.environment = environment.get();
        Settings s = p.settings;
        s.maxRadiusPixels = radiusCap(p, f);  // the same for every tile
        result = runOperator(oi, s);
    }

    ClipImage source, albedo;
    if (option.needsSource) {
        const OfxRectD region = f.toCanonical(window);
        if (!source.fetch(in.source, t, &region, "Source")) throw Error("the Source clip gave no image");
    }
    if (withAlbedo) {
        const OfxRectD region = f.toCanonical(window);
        if (!albedo.fetch(in.albedo, t, &region, "Albedo")) throw Error("the Albedo clip gave no image");
    }

    const float strength = (float)p.strength;
    const int oc = out.components();
    const int sc = source.components(), ac = albedo.components();
    const float invPi = (float)(1.0 / M_PI);
    const PixRect target = intersect(window, out.bounds());
    for (int y = target.y1; y < target.y2; ++y) {
        for (int x = target.x1; x < target.x2; ++x) {
            float* o = out.pixel(x, y);
            const bool inFrame = x >= f.rod.x1 && x < f.rod.x2 && y >= f.rod.y1 && y < f.rod.y2;
            const bool inData = computed && x >= data.x1 && x < data.x2 && y >= data.y1 && y < data.y2;
            const int dx = x - data.x1, dy = data.y2 - 1 - y;  // FrameMap::ofxRow, inverted
            if (option.ssdo) {
                // DO / GI irradiance (or albedo E / pi), or relit = albedo (DO + GI) / pi.
                const float* s = option.needsSource ? source.pixel(x, y) : nullptr;
                if (!inFrame || !inData || (option.needsSource && !s)) {
                    std::fill(o, o + oc, 0.0f);
                    continue;
                }
                const float* a = withAlbedo ? albedo.pixel(x, y) : nullptr;
                const float* e = (kind == OutputKind::Indirect ? result.indirect : result.directional).at(dx, dy);
                const float* gi = kind == OutputKind::Relit ? result.indirect.at(dx, dy) : nullptr;
                float rgb[3];
                for (int c = 0; c < 3; ++c) {
                    const float alb = withAlbedo ? (a ? a[ac >= 3 ? c : 0] : 0.0f) : 1.0f;
                    if (kind == OutputKind::Relit)
                        rgb[c] = alb * (e[c] + gi[c]) * invPi;
                    else
                        rgb[c] = withAlbedo ? e[c] * (alb * invPi) : e[c];
                }
                const float alpha = kind == OutputKind::Relit ? (sc == 1 ? s[0] : sc == 4 ? s[3] : 1.0f) : 1.0f;
                if (oc == 1) {
                    o[0] = alpha;
                } else {
                    o[0] = rgb[0], o[1] = rgb[1], o[2] = rgb[2];
                    if (oc == 4) o[3] = alpha;
                }
                continue;
            }
            float a = 1.0f;
            if (inData) a = *result.ao.at(dx, dy);
            if (strength < 1.0f) a = 1.0f - strength * (1.0f - a);
            if (!option.needsSource) {
                if (!inFrame) {
                    std::fill(o, o + oc, 0.0f);
                } else if (oc == 1) {
                    o[0] = a;
                } else {
                    o[0] = o[1] = o[2] = a;
                    if (oc == 4) o[3] = 1.0f;
                }
                continue;
            }
            const float* s = source.pixel(x, y);
            if (!s) {
                std::fill(o, o + oc, 0.0f);
                continue;
            }
            const float alpha = sc == 1 ? s[0] : sc == 4 ? s[3] : 1.0f;
            const float m = inFrame ? a : 1.0f;
            if (oc == 1) {
                o[0] = alpha;
            } else {
                for (int c = 0; c < 3; ++c) o[c] = (sc >= 3 ? s[c] : 0.0f) * m;
                if (oc == 4) o[3] = alpha;
            }
        }
    }
    return kOfxStatOK;
}

OfxStatus mainEntry(const char* action, const void* handle, OfxPropertySetHandle inArgs, OfxPropertySetHandle outArgs) {
    OfxImageEffectHandle effect = (OfxImageEffectHandle)handle;
    try {
        if (!std::strcmp(action, kOfxActionLoad)) return onLoad();
        if (!gProp || !gEffect || !gParam) return kOfxStatErrMissingHostFeature;
        if (!std::strcmp(action, kOfxActionUnload)) return kOfxStatOK;
        if (!std::strcmp(action, kOfxActionDescribe)) return onDescribe(effect);
        if (!std::strcmp(action, kOfxImageEffectActionDescribeInContext)) return onDescribeInContext(effect, inArgs);
        if (!std::strcmp(action, kOfxActionCreateInstance)) return onCreateInstance(effect);
        if (!std::strcmp(action, kOfxActionDestroyInstance)) return onDestroyInstance(effect);
        if (!std::strcmp(action, kOfxActionInstanceChanged)) return onInstanceChanged(effect);
        if (!std::strcmp(action, kOfxImageEffectActionGetRegionOfDefinition))
            return onGetRegionOfDefinition(effect, inArgs, outArgs);
        if (!std::strcmp(action, kOfxImageEffectActionGetRegionsOfInterest))
            return onGetRegionsOfInterest(effect, inArgs, outArgs);
        if (!std::strcmp(action, kOfxImageEffectActionGetClipPreferences)) return onGetClipPreferences(effect, outArgs);
        if (!std::strcmp(action, kOfxImageEffectActionGetOutputColourspace))
            return onGetOutputColourspace(effect, outArgs);
        if (!std::strcmp(action, kOfxImageEffectActionIsIdentity)) return onIsIdentity(effect, inArgs, outArgs);
        if (!std::strcmp(action, kOfxImageEffectActionRender)) return onRender(effect, inArgs);
        if (!std::strcmp(action, kOfxImageEffectActionBeginSequenceRender) ||
            !std::strcmp(action, kOfxImageEffectActionEndSequenceRender))
            return kOfxStatOK;
        return kOfxStatReplyDefault;
    } catch (const OfxFailure& e) {
        return e.status == kOfxStatOK ? kOfxStatFailed : e.status;
    } catch (const std::bad_alloc&) {
        return kOfxStatErrMemory;
    } catch (const std::exception& e) {
        if (effect && std::strcmp(action, kOfxActionDescribe) != 0)
            postMessage(effect, kOfxMessageError, std::string("obscura: ") + e.what());
        return kOfxStatFailed;
    } catch (...) {
        return kOfxStatFailed;
    }
}

void setHost(OfxHost* host) { gHost = host; }

OfxPlugin gPlugin = {kOfxImageEffectPluginApi, kOfxImageEffectPluginApiVersion, kPluginId, kVersionMajor,
                     kVersionMinor, setHost, mainEntry};

} // namespace

OBSCURA_OFX_EXPORT int OfxGetNumberOfPlugins(void) { return 1; }

OBSCURA_OFX_EXPORT OfxPlugin* OfxGetPlugin(int nth) { return nth == 0 ? &gPlugin : nullptr; }
