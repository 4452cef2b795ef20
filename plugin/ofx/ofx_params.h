// The node's parameters as the operator wants them: what each Output option computes, and
// the values at one time read into Settings (the ranges, device names and method rules are
// plugin/core's: core/settings_schema.h, core/devices.h, core/methods.h).
#pragma once
#include "ofx_api.h"
#include "ofx_instance.h"

#include "core/camera.h"
#include "core/settings.h"

#include <algorithm>
#include <string>

namespace obscura::ofx {

// What the Output clip carries. Hosts store a choice as its index, so new outputs (DO,
// GI, relit...) are appended to this table, never inserted: saved projects keep meaning.
enum class OutputKind { Ao, BeautyTimesAo, Directional, Indirect, Relit };
struct OutputOption {
    OutputKind kind;
    const char* label;
    bool needsSource;  // reads the Source (beauty) clip
    bool light;        // DO, GI or relit: run by ssdo (DO) or the GI Method parameter's method, not Method
    bool bounce;       // runs the bounce, reading Source over the window + apron (the senders)
};
inline constexpr OutputOption kOutputOptions[] = {
    {OutputKind::Ao, "AO", false, false, false},
    {OutputKind::BeautyTimesAo, "Beauty x AO", true, false, false},
    {OutputKind::Directional, "Directional occlusion (DO)", false, true, false},
    {OutputKind::Indirect, "Indirect (GI)", true, true, true},
    {OutputKind::Relit, "Relit", true, true, true},
};
inline constexpr int kOutputCount = int(sizeof(kOutputOptions) / sizeof(kOutputOptions[0]));

// The option a stored choice index names (out-of-range indices clamp to the table).
inline const OutputOption& outputAt(int index) { return kOutputOptions[std::clamp(index, 0, kOutputCount - 1)]; }

// The methods that write GI (the GI Method choice), in the method table's order, and the index of
// ssdo among them: the default, so projects saved before the choice existed keep SSDO's GI.
std::vector<const char*> giMethods();
int ssdoGiMethodIndex();

// The choices' words, in their stored order.
inline constexpr const char* kUpAxes[] = {"y", "z"};
inline constexpr const char* kWeightings[] = {"uniform", "cosine"};
inline constexpr const char* kFalloffs[] = {"linear", "none"};
// Appended only (stored as indices): the film back came after the field of view.
inline constexpr const char* kProjections[] = {"perspective", "orthographic", "perspective (focal length)"};
inline constexpr const char* kDepthKinds[] = {"planar", "radial", "inverse", "normalized"};
inline constexpr const char* kNormalSpaces[] = {"world", "camera", "depth"};

// The parameter values at one time, as the operator wants them.
struct Params {
    OutputKind output = OutputKind::Ao;
    double strength = 1;
    Settings settings;
    Projection projection = Projection::Perspective;
    bool filmBack = false;  // perspective from the focal length and horizontal aperture, not the fov
    double fovDeg = 0, orthoWidth = 0, focalMm = 0, apertureMm = 0;
    std::string cameraToWorld;
    DepthEncoding depthEncoding = DepthEncoding::Planar;  // as the Depth clip stores it (--depth)
    double depthRange[2] = {0, 0};                        // normalized's 0 and 1 (--depth-range)
    DepthKind depthKind = DepthKind::Planar;              // what the operator reads once decoded
    NormalSpace normalSpace = NormalSpace::World;
    double maxScreenRadius = 0;  // 0 = automatic (frame extent)
    std::string envPath;         // lat-long environment map ("" = the sky colour)
    bool timesAlbedo = false;    // DO / GI as albedo E / pi
};

// The values at time `t`, at full resolution (paramsAt in ofx_coords.h scales them to a render).
Params readParams(const Instance& in, OfxTime t);
// The method output `o` runs: Method (stored index `method`) for the AO outputs, ssdo for DO, GI
// Method (index `giMethod`) for GI and Relit. Indices out of range clamp to the choices.
std::string methodFor(const OutputOption& o, int method, int giMethod);

// What an output reads and computes (regions of interest and render agree through these).
inline const OutputOption& optionOf(const Params& p) { return kOutputOptions[(int)p.output]; }
// AO outputs with strength 0 compute nothing; the SSDO quantities ignore Strength.
inline bool computes(const Params& p) { return optionOf(p).light || p.strength > 0; }
inline bool needsAlbedo(const Params& p) {
    return p.output == OutputKind::Relit ||
           (p.timesAlbedo && (p.output == OutputKind::Directional || p.output == OutputKind::Indirect));
}
// Beauty x AO and Relit keep the Source's alpha (and premultiplication); the rest are opaque.
inline bool keepsSourceAlpha(OutputKind k) { return k == OutputKind::BeautyTimesAo || k == OutputKind::Relit; }

} // namespace obscura::ofx
