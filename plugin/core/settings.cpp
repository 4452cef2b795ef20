#include "settings.h"

#include "methods.h"
#include <cstdio>

namespace obscura {


const std::vector<QualityPreset>& qualityPresets() {
    // Each level roughly quadruples the samples; the blur hides the noise of the sparse ones.
    static const std::vector<QualityPreset> presets = {
        {"low", 4, 4, 2},
        {"medium", 8, 8, 1},   // the defaults (Settings' kBlurAuto is this blur)
        {"high", 16, 12, 0},
        {"ultra", 32, 24, 0},
    };
    return presets;
}

bool applyQualityPreset(const std::string& name, Settings& s) { return applyMethodPresets(name, s); }

int resolvedBlur(const Settings& s) {
    if (methodOutputs(s.method, "do")) return s.blur > 0 ? s.blur : (s.interleave > 1 ? s.interleave : 0);
    if (s.blur != kBlurAuto) return s.blur;
    if (s.presetBlur != kBlurAuto) return s.presetBlur;
    for (const QualityPreset& q : qualityPresets())
        if (std::string(q.name) == "medium") return q.blur;
    return 0;
}

// auto: docs/hbao.md gives the reference scenes the share of R was chosen on (and hbao's
// per-occluder rule, whose cap it is).
float resolvedThickness(const Settings& s) {
    return s.thickness == kThicknessAuto ? kAutoThicknessPerRadius * s.radius : s.thickness;
}

const char* toString(Weighting w) { return w == Weighting::Uniform ? "uniform" : "cosine"; }
const char* toString(Falloff f) { return f == Falloff::Linear ? "linear" : "none"; }
const char* toString(DepthKind d) { return d == DepthKind::Planar ? "planar" : "radial"; }

namespace {
const char* const kDepthEncodings[] = {"planar", "radial", "inverse", "normalized"};
} // namespace

const char* toString(DepthEncoding e) { return kDepthEncodings[(int)e]; }

bool parse(const std::string& s, DepthEncoding& e) {
    for (int i = 0; i < 4; ++i)
        if (s == kDepthEncodings[i]) {
            e = (DepthEncoding)i;
            return true;
        }
    return false;
}

DepthKind decodedKind(DepthEncoding e) { return e == DepthEncoding::Radial ? DepthKind::Radial : DepthKind::Planar; }
const char* toString(NormalSpace n) {
    return n == NormalSpace::World ? "world" : n == NormalSpace::Camera ? "camera" : "depth";
}

namespace {
template <class E>
bool parseEnum(const std::string& s, E& out, const char* a, E ea, const char* b, E eb) {
    if (s == a) { out = ea; return true; }
    if (s == b) { out = eb; return true; }
    return false;
}
} // namespace

bool parse(const std::string& s, Weighting& w) { return parseEnum(s, w, "uniform", Weighting::Uniform, "cosine", Weighting::Cosine); }
bool parse(const std::string& s, Falloff& f) { return parseEnum(s, f, "linear", Falloff::Linear, "none", Falloff::None); }
bool parse(const std::string& s, DepthKind& d) { return parseEnum(s, d, "planar", DepthKind::Planar, "radial", DepthKind::Radial); }
bool parse(const std::string& s, NormalSpace& n) {
    if (s == "depth") {
        n = NormalSpace::Depth;
        return true;
    }
    return parseEnum(s, n, "world", NormalSpace::World, "camera", NormalSpace::Camera);
}

} // namespace obscura
