// The Output image, pixel by pixel (ofx_output.h). Outside the Depth clip's region of
// definition the AO outputs are 0 (Beauty x AO passes the beauty), and the SSDO outputs are 0
// wherever the operator did not compute.
#include "ofx_output.h"

#include <algorithm>
#include <cmath>

namespace obscura::ofx {

namespace {

constexpr float kInvPi = (float)(1.0 / M_PI);

// What every pixel of one render shares.
struct Composite {
    const OutputOption& option;
    bool withAlbedo;
    float strength;
    const Occlusion& occ;
    const ClipImage& out;
    const ClipImage& source;
    const ClipImage& albedo;
};

// The alpha a Source pixel carries: its A, the lone channel of an Alpha clip, or 1 for RGB.
float alphaOf(const float* s, int sc) { return sc == 1 ? s[0] : sc == 4 ? s[3] : 1.0f; }

// RGB and alpha into an Output pixel of `oc` channels (an Alpha clip gets the alpha).
void store(float* o, int oc, const float rgb[3], float alpha) {
    if (oc == 1) {
        o[0] = alpha;
    } else {
        o[0] = rgb[0], o[1] = rgb[1], o[2] = rgb[2];
        if (oc == 4) o[3] = alpha;
    }
}

// DO / GI irradiance (or albedo E / pi), or relit = albedo (DO + GI) / pi; (dx, dy) is the
// pixel in the operator's planes, `inside` whether it lies in the frame and the data.
void ssdoPixel(const Composite& c, float* o, int x, int y, bool inside, int dx, int dy) {
    const int oc = c.out.components();
    const float* s = c.option.needsSource ? c.source.pixel(x, y) : nullptr;
    if (!inside || (c.option.needsSource && !s)) {
        std::fill(o, o + oc, 0.0f);
        return;
    }
    const OutputKind kind = c.option.kind;
    const int ac = c.albedo.components();
    const float* a = c.withAlbedo ? c.albedo.pixel(x, y) : nullptr;
    // hbao's bounce has no DO: its relit is albedo GI / pi.
    static constexpr float kNoLight[3] = {0.0f, 0.0f, 0.0f};
    const Image& light = kind == OutputKind::Indirect ? c.occ.result.indirect : c.occ.result.directional;
    const float* e = light.empty() ? kNoLight : light.at(dx, dy);
    const float* gi = kind == OutputKind::Relit ? c.occ.result.indirect.at(dx, dy) : nullptr;
    float rgb[3];
    for (int ch = 0; ch < 3; ++ch) {
        const float alb = c.withAlbedo ? (a ? a[ac >= 3 ? ch : 0] : 0.0f) : 1.0f;
        if (kind == OutputKind::Relit)
            rgb[ch] = alb * (e[ch] + gi[ch]) * kInvPi;
        else
            rgb[ch] = c.withAlbedo ? e[ch] * (alb * kInvPi) : e[ch];
    }
    store(o, oc, rgb, kind == OutputKind::Relit ? alphaOf(s, c.source.components()) : 1.0f);
}

// The AO at a pixel (1 outside the data), blended towards 1 by Strength.
float aoAt(const Composite& c, bool inData, int dx, int dy) {
    float a = 1.0f;
    if (inData) a = *c.occ.result.ao.at(dx, dy);
    if (c.strength < 1.0f) a = 1.0f - c.strength * (1.0f - a);
    return a;
}

// AO: RGB = AO, A = 1 (an Alpha clip gets the AO alone); 0 outside the frame.
void aoPixel(float* o, int oc, bool inFrame, float a) {
    if (!inFrame) {
        std::fill(o, o + oc, 0.0f);
    } else if (oc == 1) {
        o[0] = a;
    } else {
        o[0] = o[1] = o[2] = a;
        if (oc == 4) o[3] = 1.0f;
    }
}

// Beauty x AO: Source RGB times the AO inside the frame, Source alpha; 0 where Source has none.
void beautyTimesAoPixel(float* o, int oc, const float* s, int sc, bool inFrame, float a) {
    if (!s) {
        std::fill(o, o + oc, 0.0f);
        return;
    }
    const float m = inFrame ? a : 1.0f;
    const float rgb[3] = {(sc >= 3 ? s[0] : 0.0f) * m, (sc >= 3 ? s[1] : 0.0f) * m, (sc >= 3 ? s[2] : 0.0f) * m};
    store(o, oc, rgb, alphaOf(s, sc));
}

} // namespace

void writeOutput(const Params& p, const FrameMap& f, const Occlusion& occ, const ClipImage& out,
                 const ClipImage& source, const ClipImage& albedo, const PixRect& window) {
    const Composite c{optionOf(p), needsAlbedo(p), (float)p.strength, occ, out, source, albedo};
    const int oc = out.components();
    const PixRect target = intersect(window, out.bounds());
    for (int y = target.y1; y < target.y2; ++y) {
        for (int x = target.x1; x < target.x2; ++x) {
            float* o = out.pixel(x, y);
            const bool inFrame = f.rod.contains(x, y);
            const bool inData = occ.computed && occ.data.contains(x, y);
            const int dx = x - occ.data.x1, dy = occ.data.y2 - 1 - y;  // FrameMap::ofxRow, inverted
            if (c.option.light)
                ssdoPixel(c, o, x, y, inFrame && inData, dx, dy);
            else if (!c.option.needsSource)
                aoPixel(o, oc, inFrame, aoAt(c, inData, dx, dy));
            else
                beautyTimesAoPixel(o, oc, source.pixel(x, y), source.components(), inFrame, aoAt(c, inData, dx, dy));
        }
    }
}

} // namespace obscura::ofx
