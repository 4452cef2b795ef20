// The frame of a render and the regions it reads (ofx_coords.h), and the region actions: the
// output's region of definition (the Depth clip's; with Source's for Beauty x AO) and each clip's
// region of interest for a render window (the window and its apron, or nothing for a clip the
// chosen output does not read).
#include "ofx_coords.h"

#include "ofx_actions.h"
#include "ofx_camera.h"
#include "ofx_names.h"
#include "ofx_suites.h"

#include "base/error.h"
#include "core/methods.h"

#include <algorithm>
#include <string>

namespace obscura::ofx {

// A clip's region of definition as the plugin reads it: a side the host flags infinite
// (kOfxFlagInfiniteMin / Max, a generator's; anything past 2^30 pixels alike) is the project's
// frame, the display window the camera's field of view spans.
static OfxRectD finiteRegion(const Instance& in, OfxImageClipHandle clip, OfxTime t) {
    OfxRectD r{0, 0, 0, 0};
    check(gEffect->clipGetRegionOfDefinition(clip, t, &r));
    OfxPropertySetHandle props = effectProps(in.effect);
    double offset[2] = {0, 0}, extent[2] = {0, 0};
    gProp->propGetDoubleN(props, kOfxImageEffectPropProjectOffset, 2, offset);  // optional: 0, 0
    gProp->propGetDoubleN(props, kOfxImageEffectPropProjectExtent, 2, extent);
    const double infinite = double(1 << 30);
    if (!(r.x1 > -infinite)) r.x1 = offset[0];
    if (!(r.y1 > -infinite)) r.y1 = offset[1];
    if (!(r.x2 < infinite)) r.x2 = offset[0] + extent[0];
    if (!(r.y2 < infinite)) r.y2 = offset[1] + extent[1];
    return r;
}

static OfxRectD depthRegion(const Instance& in, OfxTime t) { return finiteRegion(in, in.depth, t); }

FrameMap frameMap(const Instance& in, OfxTime t, OfxPropertySetHandle actionArgs) {
    FrameMap f;
    OfxPropertySetHandle props = effectProps(in.effect);
    // The images' pixel aspect ratio maps canonical to pixel coordinates: the clips', which the host
    // made one (the plugin takes no mixed PARs) and which need not be the project's.
    const double projectPar = getDouble(props, kOfxImageEffectPropProjectPixelAspectRatio, 1.0);
    f.par = getDouble(clipProps(in.output), kOfxImagePropPixelAspectRatio,
                      getDouble(clipProps(in.depth), kOfxImagePropPixelAspectRatio, projectPar));
    if (!(f.par > 0)) f.par = projectPar > 0 ? projectPar : 1;
    f.sx = getDouble(actionArgs, kOfxImageEffectPropRenderScale, 1.0, 0);
    f.sy = getDouble(actionArgs, kOfxImageEffectPropRenderScale, 1.0, 1);
    if (!(f.sx > 0 && f.sy > 0)) throw Error("the host gives an invalid render scale");
    double extent[2] = {0, 0};
    if (gProp->propGetDoubleN(props, kOfxImageEffectPropProjectExtent, 2, extent) != kOfxStatOK)
        throw Error("the host gives no project extent (the display window the camera's field of view spans)");
    f.displayW = (int)std::lround(extent[0] * f.sx / f.par);
    f.displayH = (int)std::lround(extent[1] * f.sy);
    f.rod = f.toPixels(depthRegion(in, t));
    return f;
}

Params paramsAt(const Instance& in, OfxTime t, const FrameMap& f) {
    Params p = readParams(in, t);
    if (p.settings.blur > 0) p.settings.blur = std::max(1, (int)std::lround(p.settings.blur * f.sx));
    p.maxScreenRadius *= f.sx;
    return p;
}

float radiusCap(const Params& p, const FrameMap& f) {
    if (p.maxScreenRadius > 0) return (float)p.maxScreenRadius;
    return (float)std::max(f.rod.width(), f.rod.height()) + 2.0f;
}

// The apron: the projected radius (bounded by the cap; for an orthographic camera R *
// pixels-per-unit), the texel snapping of the samples, then the two blur passes.
//
// SSDO places its samples in world space within r_max and does not bound their projection
// by the cap: orthographic, that reach is exactly R * pixels-per-unit; in perspective the cap
// stands for it, which holds wherever r_max projects within the cap (surfaces farther from
// the eye than about fx r_max / cap + r_max). Its blur gathers the interleaving block (the
// interleave width, or Blur when set: resolvedBlur; the bounce's wider blur is the method's
// extraApron), and the bounce reads Source under the same apron.
int apronPixels(const Params& p, const Camera& cam, float cap) {
    const bool ssdo = p.settings.method == "ssdo";
    double reach = cap;
    // R across the larger focal length: with non-square pixels it reaches farther in rows.
    const double f = std::max(cam.fx, cam.fy);
    if (cam.projection == Projection::Orthographic)
        reach = ssdo ? std::min<double>((double)p.settings.radius * f, 1e7) : std::min<double>(p.settings.radius * f, cap);
    const int blur = resolvedBlur(p.settings);
    const MethodInfo* m = findMethod(p.settings.method);
    const int extra = m && m->extraApron ? m->extraApron(p.settings) : 0;
    // Normals from the depth read two texels each way: the apron's texels get theirs as the whole frame's.
    const int normals = p.normalSpace == NormalSpace::Depth ? 2 : 0;
    return (int)std::ceil(reach) + 2 + std::max(blur, 0) + extra + normals;
}

PixRect dataRegion(const PixRect& window, int apron, const FrameMap& f) { return intersect(grow(window, apron), f.rod); }

PixRect dataRegionFor(const PixRect& window, const Params& p, const FrameMap& f) {
    if (!computes(p)) return {};
    const MethodInfo* m = findMethod(p.settings.method);
    if (m && m->readsWholeFrame) return f.rod;
    return dataRegion(window, apronPixels(p, makeCamera(p, f), radiusCap(p, f)), f);
}

// ---------------------------------------------------------------------------
// The region actions
// ---------------------------------------------------------------------------

OfxStatus onGetRegionOfDefinition(OfxImageEffectHandle effect, OfxPropertySetHandle inArgs,
                                  OfxPropertySetHandle outArgs) {
    const Instance& in = *instanceOf(effect);
    if (!connected(in.depth)) return kOfxStatReplyDefault;
    const OfxTime t = getDouble(inArgs, kOfxPropTime, 0);
    // The AO and the light exist where the depth does (the data window, overscan included).
    OfxRectD rod = depthRegion(in, t);
    // Beauty x AO passes the beauty where there is no depth: all of a larger Source is kept.
    if (readParams(in, t).output == OutputKind::BeautyTimesAo && connected(in.source)) {
        const OfxRectD source = finiteRegion(in, in.source, t);
        rod = {std::min(rod.x1, source.x1), std::min(rod.y1, source.y1), std::max(rod.x2, source.x2),
               std::max(rod.y2, source.y2)};
    }
    check(gProp->propSetDoubleN(outArgs, kOfxImageEffectPropRegionOfDefinition, 4, &rod.x1));
    return kOfxStatOK;
}

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
        dataRoi = f.toCanonical(dataRegionFor(f.toPixels(region), paramsAt(in, t, f), f));
        setRoi(kClipDepth, dataRoi);
        setRoi(kClipNormal, p.normalSpace == NormalSpace::Depth ? none : dataRoi);
    }
    // Inputs the chosen output does not read are not requested at all. The bounce reads
    // Source (its senders) wherever the depth is read; Albedo is read under the window.
    setRoi(kClipSource, o.bounce ? dataRoi : o.needsSource ? region : none);
    setRoi(kClipPosition, none);
    setRoi(kClipAlbedo, needsAlbedo(p) ? region : none);
    return kOfxStatOK;
}

} // namespace obscura::ofx
