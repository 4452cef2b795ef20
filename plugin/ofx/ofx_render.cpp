// The render action: one render window of the Output clip. The node checks its inputs, runs
// the operator (core/operator.h) over the window's data region, and writes the chosen output.
//
// The light outputs (DO, GI, relit) run "ssdo" (DO) or the GI Method's method (GI, relit) with the
// Source clip (the beauty) as the bounce source, as the CLI's --bounce-source beauty: the beauty
// already carries the senders' albedo, so the Albedo clip is not a sender albedo; it only
// forms relit (albedo (DO + GI) / pi) and the "times albedo" radiance (albedo E / pi).
#include "ofx_actions.h"
#include "ofx_camera.h"
#include "ofx_coords.h"
#include "ofx_images.h"
#include "ofx_names.h"
#include "ofx_output.h"
#include "ofx_params.h"
#include "ofx_suites.h"

#include "base/cancel.h"
#include "base/error.h"
#include "core/operator.h"
#include "core/settings_schema.h"
#include "io/depth_encoding.h"

#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

namespace obscura::ofx {

namespace {

PixRect renderWindow(OfxPropertySetHandle inArgs) {
    int w[4] = {0, 0, 0, 0};
    check(gProp->propGetIntN(inArgs, kOfxImageEffectPropRenderWindow, 4, w));
    return PixRect{w[0], w[1], w[2], w[3]};
}

// Required inputs first: without them a render would be black, not an answer. The Normal clip is
// optional: without it the normals are reconstructed from the depth (readParams).
void requireGeometry(const Instance& in) {
    if (!connected(in.depth)) throw Error(std::string("the ") + kClipDepth + " clip is not connected; it is required");
}

// The clips the chosen output reads besides the geometry, so a missing one is reported
// before any work.
void requireOutputInputs(const Instance& in, const Params& p) {
    const OutputOption& option = optionOf(p);
    if (option.needsSource && !connected(in.source))
        throw Error(std::string("the ") + option.label + " output needs the Source clip" +
                    (option.bounce ? " (the beauty: the bounce source)" : ""));
    if (needsAlbedo(p) && !connected(in.albedo))
        throw Error(std::string("the ") + option.label + " output" +
                    (p.output == OutputKind::Relit ? "" : " times albedo") + " needs the Albedo clip");
}

// The lat-long map SSDO is lit by, or none (the sky colour).
std::shared_ptr<const Image> environmentOf(const Instance& in, const Params& p) {
    const bool ssdo = p.settings.method == "ssdo";
    if (ssdo && p.envPath.find_first_not_of(" \t\r\n") != std::string::npos)
        return environmentFor(in.environment, p.envPath);
    return nullptr;
}

// The Depth clip's values as the operator reads them (planar or radial, sky +inf), as the CLI's
// --depth and --depth-range decode a file's.
void decodeClipDepth(const Params& p, Image& depth) {
    DepthDecoding d;
    d.encoding = p.depthEncoding;
    if (d.encoding == DepthEncoding::Normalized) {
        const std::string problem = depthRangeProblem(p.depthRange[0], p.depthRange[1], Spelling::Key);
        if (!problem.empty())
            throw Error("normalized depth needs Depth Near and Depth Far, two different distances (" + problem + ")");
        d.range = std::array<double, 2>{p.depthRange[0], p.depthRange[1]};
    }
    decodeDepth(depth, d);
}

// The operator's inputs: the planes over `data` within the display window, seen by the camera.
OperatorInputs operatorInputs(const Params& p, const FrameMap& f, const PixRect& data, const Image& depth,
                              const Image& normal, const Image& radiance, const Image* environment) {
    OperatorInputs oi;
    oi.displayWindow = Box2i{0, 0, f.displayW, f.displayH};
    oi.dataWindow = f.toDisplay(data);
    oi.depth = depth.view();
    if (p.normalSpace != NormalSpace::Depth) oi.normal = normal.view();
    oi.depthKind = p.depthKind;
    oi.normalSpace = p.normalSpace;
    oi.camera = makeCamera(p, f);
    if (!radiance.empty()) oi.radiance = radiance.view();
    oi.environment = environment;
    return oi;
}

// Reads Depth, Normal unless the normals come from the depth (and for the bounce Source) over `occ.data` and runs the operator on
// them, with the frame's radius cap so every tile computes what the whole frame does.
void readAndOcclude(const Instance& in, OfxTime t, const Params& p, const FrameMap& f, Occlusion& occ) {
    const OfxRectD region = f.toCanonical(occ.data);
    ClipImage depth, normal, radiance;
    fetchInput(depth, in.depth, t, region, "Depth");
    const bool normals = p.normalSpace != NormalSpace::Depth;  // else reconstructed from the depth
    if (normals) {
        fetchInput(normal, in.normal, t, region, "Normal");
        if (!normal.empty() && normal.components() < 3)
            throw Error("the Normal clip must be RGB(A): normals are three channels");
    }
    // Holes outside what the host delivered read as sky (+inf in every encoding) and missing normals.
    Image depthPlane = toDisplayPlane(depth, occ.data, f, 1, std::numeric_limits<float>::infinity());
    decodeClipDepth(p, depthPlane);
    const Image normalPlane = normals ? toDisplayPlane(normal, occ.data, f, 3, 0.0f) : Image();
    Image radiancePlane;
    if (optionOf(p).bounce) {
        fetchInput(radiance, in.source, t, region, "Source");
        if (!radiance.empty() && radiance.components() < 3) throw Error("the bounce needs an RGB(A) Source clip");
        radiancePlane = toDisplayPlane(radiance, occ.data, f, 3, 0.0f);
    }
    const std::shared_ptr<const Image> environment = environmentOf(in, p);
    throwIfCancelled();

    Settings s = p.settings;
    s.maxRadiusPixels = radiusCap(p, f);  // the same for every tile
    occ.result = runOperator(operatorInputs(p, f, occ.data, depthPlane, normalPlane, radiancePlane, environment.get()), s);
}

// readAndOcclude, asking the host's abort after the inputs are read and between the operator's
// tiles (at most every 10 ms: the specification's guide says a host's abort may be costly), so a
// long frame stops when the user moves on. False when the host aborted.
bool occlude(OfxImageEffectHandle effect, const Instance& in, OfxTime t, const Params& p, const FrameMap& f,
             Occlusion& occ) {
    const CancelScope hostAbort(
        askedAtMostEvery(std::chrono::milliseconds(10), [effect] { return gEffect->abort(effect) != 0; }));
    try {
        readAndOcclude(in, t, p, f, occ);
    } catch (const Cancelled&) {
        return false;
    }
    return true;
}

// What the node shows after a render whose light inputs held NaN, infinite or huge values (the
// operator took them as 0): the inputs by their names on the node, without the CLI's counts, which
// would be one tile's.
std::string lightWarning(const OperatorStats& st) {
    std::string inputs;
    for (size_t i = 0; i < st.unphysicalLight.size(); ++i) {
        const std::string& what = st.unphysicalLight[i];
        inputs += (i == 0 ? "" : i + 1 == st.unphysicalLight.size() ? " and " : ", ") +
                  (what == "the bounce source" ? std::string("the ") + kClipSource + " clip" : what);
    }
    if (inputs.empty()) return "";
    return "obscura: " + inputs + " held NaN, infinite or huge (above 1e9) values; the light takes them as 0 (black)";
}

} // namespace

OfxStatus onRender(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs, std::optional<std::string>& warning) {
    const Instance& in = *instanceOf(effect);
    const OfxTime t = getDouble(inArgs, kOfxPropTime, 0);
    const PixRect window = renderWindow(inArgs);
    requireGeometry(in);
    const FrameMap f = frameMap(in, t, inArgs);
    const Params p = paramsAt(in, t, f);

    ClipImage out;
    if (!out.fetch(in.output, t, nullptr, "Output")) throw Error("the host gave no Output image");
    if (optionOf(p).kind != OutputKind::Ao && out.components() == 1)
        throw Error(std::string("the ") + optionOf(p).label + " output is colour, and the host gave an Alpha Output "
                    "image: set the node's output to RGBA");
    requireOutputInputs(in, p);

    // The occlusion over the window's data region, or nothing when the AO is off.
    Occlusion occ;
    occ.data = dataRegionFor(window, p, f);
    occ.computed = computes(p) && !occ.data.empty();
    if (occ.computed && !occlude(effect, in, t, p, f, occ)) return kOfxStatOK;  // aborted: nothing to say

    // What the output composites with, under the window.
    ClipImage source, albedo;
    const OfxRectD underWindow = f.toCanonical(window);
    if (optionOf(p).needsSource) fetchInput(source, in.source, t, underWindow, "Source");
    if (needsAlbedo(p)) fetchInput(albedo, in.albedo, t, underWindow, "Albedo");

    writeOutput(p, f, occ, out, source, albedo, window);
    warning = lightWarning(occ.result.stats);
    return kOfxStatOK;
}

} // namespace obscura::ofx
