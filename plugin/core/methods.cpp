#include "methods.h"

#include "method_runs.h"
#include "base/kernel_params.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace obscura {

namespace {

// HBAO's levels carry the AO methods' blur (an explicit --blur wins, whatever the flags'
// order); directions x steps are HBAO's own.
void hbaoLevel(Settings& s, int level) {
    const QualityPreset& q = qualityPresets()[level];
    s.directions = q.directions;
    s.steps = q.steps;
    s.presetBlur = q.blur;
}

MethodParam intParam(const char* key, const char* flag, const char* help, int lo, int hi, int Settings::*field) {
    MethodParam p{key, flag, "N", help, (double)lo, (double)hi};
    p.intField = field;
    return p;
}
MethodParam floatParam(const char* key, const char* flag, const char* value, const char* help, double lo, double hi,
                       float Settings::*field) {
    MethodParam p{key, flag, value, help, lo, hi};
    p.floatField = field;
    return p;
}
MethodParam switchParam(const char* key, const char* flag, const char* help, bool Settings::*field) {
    MethodParam p{key, flag, nullptr, help, 0, 1};
    p.boolField = field;
    return p;
}

// hbao, rtao and discs: one thickness, the world-units depth of the solid behind each visible point.
MethodParam thicknessParam() {
    MethodParam p = floatParam("thickness", "--thickness", "T|auto|inf",
                               "hbao, rtao, discs: the solid behind each visible point is T world units deep; "
                               "auto: hbao takes each occluder as deep as it is wide across the slice, at most "
                               "0.85 R; rtao and discs 0.85 R; inf: the depth buffer is a height field (hbao's horizon) "
                               "(default auto)",
                               0.0, 1e30, &Settings::thickness);
    p.named = {{"auto", kThicknessAuto, -1.0}, {"inf", kThicknessInfinite, 1e9}};
    p.alsoFor = {"rtao", "discs"};
    return p;
}

// hbao: what a sample past the buffer's edge sees (overscan is used where the data window has it).
MethodParam borderParam() {
    MethodParam p = intParam("border", "--border",
                             "hbao: samples past the buffer's edge see open sky (open), the edge texel's depth "
                             "(clamp) or its tangent plane continued (tangent); discs: tangent continues the edge "
                             "nodes' planes, open and clamp leave nothing there (default tangent)",
                             kBorderOpen, kBorderTangent, &Settings::border);
    p.alsoFor = {"discs"};
    p.value = "open|clamp|tangent";
    p.named = {{"open", kBorderOpen, kBorderOpen}, {"clamp", kBorderClamp, kBorderClamp},
               {"tangent", kBorderTangent, kBorderTangent}};
    return p;
}

// hbao with deep input. OpenFX images are flat, so the node does not offer it.
MethodParam deepLayersParam() {
    MethodParam p = intParam("deep_layers", "--deep-layers",
                             "hbao with a deep EXR input: surfaces per pixel used as occluders, the visible one "
                             "included (default 4; docs/deep.md)",
                             1, 16, &Settings::deepLayers);
    p.ofx = false;
    return p;
}

std::vector<MethodInfo> makeTable() {
    std::vector<MethodInfo> t;
    t.push_back({"hbao", "horizon-based ambient occlusion (Bavoil et al. 2008): slices around the view vector",
                 "kernels/hbao.glsl", true, true,
                 {"depth", "normal", "deep", "beauty|direct-diffuse", "albedo"}, {"ao", "gi", "relit"},
                 {{"low", "4x4 + blur 2", [](Settings& s) { hbaoLevel(s, 0); }},
                  {"medium", "8x8 + blur 1", [](Settings& s) { hbaoLevel(s, 1); }},
                  {"high", "16x12", [](Settings& s) { hbaoLevel(s, 2); }},
                  {"ultra", "32x24", [](Settings& s) { hbaoLevel(s, 3); }}},
                 {intParam("directions", "--directions", "hbao: directions (slices) per pixel (default 8)", 1, 256,
                           &Settings::directions),
                  intParam("steps", "--steps", "hbao: samples per direction (default 8)", 1, 256, &Settings::steps),
                  thicknessParam(), borderParam(),
                  deepLayersParam()},
                 [](const Settings& s) { return s.directions * s.steps; }, nullptr, &runHbaoMethod,
                 /*blurWithinReach=*/true});
    t.push_back({"ssdo", "directional occlusion and one bounce (Ritschel et al. 2009): DO, AO and, with --bounce, GI",
                 "kernels/ssdo.glsl", true, true, {"depth", "normal", "beauty|direct-diffuse", "albedo"},
                 {"ao", "do", "gi", "relit"},
                 {{"low", "16 samples", [](Settings& s) { s.ssdoSamples = 16; }},
                  {"medium", "64 samples", [](Settings& s) { s.ssdoSamples = 64; }},
                  {"high", "256 samples", [](Settings& s) { s.ssdoSamples = 256; }},
                  {"ultra", "1024 samples", [](Settings& s) { s.ssdoSamples = 1024; }}},
                 {intParam("samples", "--samples", "ssdo: sample set per M x M block (default 64)", 1, 4096,
                           &Settings::ssdoSamples),
                  intParam("interleave", "--interleave",
                           "ssdo: interleaved sampling over M x M pixels, then a blur of M (default 2; 1 = off)", 1, 8,
                           &Settings::interleave)},
                 [](const Settings& s) { return std::max(1, s.ssdoSamples / (s.interleave * s.interleave)); },
                 // The bounce's blur is wider than DO's (kernel_params.glsl): a tile's apron covers it.
                 [](const Settings& s) {
                     return s.bounce ? (glsl::SSDO_GI_BLUR_SCALE - 1) * std::max(resolvedBlur(s), 0) : 0;
                 },
                 &runSsdoMethod, /*blurWithinReach=*/true});
    t.push_back({"ssao", "Crytek's screen-space AO (Mittring 2007): points around the pixel tested against the depth",
                 "kernels/ssao.glsl", true, true, {"depth", "normal"}, {"ao"},
                 {{"low", "8 points", [](Settings& s) { s.ssaoSamples = 8; }},
                  {"medium", "16 points", [](Settings& s) { s.ssaoSamples = 16; }},
                  {"high", "32 points", [](Settings& s) { s.ssaoSamples = 32; }},
                  {"ultra", "64 points", [](Settings& s) { s.ssaoSamples = 64; }}},
                 {intParam("ssao_samples", "--ssao-samples", "ssao: points per pixel (default 16)", 1, 1024,
                           &Settings::ssaoSamples),
                  switchParam("ssao_hemisphere", "--ssao-hemisphere",
                              "ssao: points in the normal-oriented hemisphere, not the sphere", &Settings::ssaoHemisphere)},
                 [](const Settings& s) { return s.ssaoSamples; }, nullptr, &runSsaoMethod});
    t.push_back({"rtao", "rays (Embree) against the mesh the depth pass describes, extruded by --thickness",
                 "cpu/rtao_*", true, false, {"depth", "normal"}, {"ao"},
                 {{"low", "4 rays", [](Settings& s) { s.rtaoRays = 4; }},
                  {"medium", "16 rays", [](Settings& s) { s.rtaoRays = 16; }},
                  {"high", "64 rays", [](Settings& s) { s.rtaoRays = 64; }},
                  {"ultra", "256 rays", [](Settings& s) { s.rtaoRays = 256; }}},
                 {intParam("rtao_rays", "--rtao-rays", "rtao: rays per traced point (default 16)", 1, 4096,
                           &Settings::rtaoRays),
                  intParam("rtao_grid", "--rtao-grid", "rtao: trace every N-th pixel, interpolate between (default 1)",
                           1, 64, &Settings::rtaoGrid)},
                 [](const Settings& s) { return s.rtaoRays; },
                 // The mesh joins texels by looking 2 beyond an edge; the grid interpolates across a cell.
                 [](const Settings& s) { return 1 + s.rtaoGrid; }, &runRtaoMethod});
    t.push_back({"discs", "hierarchical disc form factors (Bunnell 2005; Hoberock & Jia 2007): cosine-weighted, every pixel an element",
                 "kernels/discs.glsl, cpu/discs_cpu.cpp", true, true, {"depth", "normal"}, {"ao"},
                 {{"low", "k 1", [](Settings& s) { s.discsWindow = 1; }},
                  {"medium", "k 2", [](Settings& s) { s.discsWindow = 2; }},
                  {"high", "k 3", [](Settings& s) { s.discsWindow = 3; }},
                  {"ultra", "k 4", [](Settings& s) { s.discsWindow = 4; }}},
                 {intParam("disc_window", "--disc-window",
                           "discs: k, nodes open within k + 1/2 of their sizes: (4k+2)^2 per level (default 1)", 1, 4,
                           &Settings::discsWindow),
                  intParam("disc_passes", "--disc-passes",
                           "discs: 2 weights each element by its own first-pass AO (default 1)", 1, 2,
                           &Settings::discsPasses),
                  switchParam("disc_blend_levels", "--disc-blend-levels",
                              "discs: blend between levels (no seams even without --blur; slower, less accurate)",
                              &Settings::discsBlendLevels),
                  switchParam("disc_no_polygon", "--disc-no-polygon",
                              "discs: discs for the 8 nearest pixels too, not their exact polygons",
                              &Settings::discsNoPolygon),
                  switchParam("disc_sum", "--disc-sum",
                              "discs: sum the form factors (occluders behind occluders count twice), not their union per azimuth slice",
                              &Settings::discsSum)},
                 // Nodes visited per pass: about seven levels of (4k + 2)^2 for a typical reach.
                 [](const Settings& s) { return 7 * (4 * s.discsWindow + 2) * (4 * s.discsWindow + 2) * s.discsPasses; },
                 nullptr, &runDiscsMethod, /*blurWithinReach=*/false, /*readsWholeFrame=*/true});
    return t;
}

} // namespace

const std::vector<MethodInfo>& methods() {
    static const std::vector<MethodInfo> table = makeTable();
    return table;
}

const MethodInfo* findMethod(const std::string& name) {
    for (const MethodInfo& m : methods())
        if (name == m.name) return &m;
    return nullptr;
}

namespace {
bool listed(const std::vector<const char*>& list, const char* name) {
    for (const char* n : list)
        if (std::string(n) == name) return true;
    return false;
}
} // namespace

bool methodOutputs(const std::string& method, const char* output) {
    const MethodInfo* m = findMethod(method);
    return m && listed(m->outputs, output);
}

bool methodReads(const std::string& method, const char* pass) {
    const MethodInfo* m = findMethod(method);
    return m && listed(m->reads, pass);
}

std::string methodNames(const char* sep, const char* reading) {
    std::string names;
    for (const MethodInfo& m : methods())
        if (!reading || listed(m.reads, reading)) names += (names.empty() ? "" : sep) + std::string(m.name);
    return names;
}

std::vector<const MethodParam*> allMethodParams() {
    std::vector<const MethodParam*> all;
    for (const MethodInfo& m : methods())
        for (const MethodParam& p : m.params) all.push_back(&p);
    return all;
}

std::vector<const MethodParam*> paramsOf(const std::string& method) {
    std::vector<const MethodParam*> out;
    if (const MethodInfo* m = findMethod(method))
        for (const MethodParam& p : m->params) out.push_back(&p);
    for (const MethodParam* p : allMethodParams())
        for (const char* other : p->alsoFor)
            if (method == other) out.push_back(p);
    return out;
}

const NamedValue* findNamed(const MethodParam& p, const std::string& word) {
    for (const NamedValue& n : p.named)
        if (word == n.word) return &n;
    return nullptr;
}

double fromHostValue(const MethodParam& p, double hostValue) {
    for (const NamedValue& n : p.named)
        if (hostValue == n.hostValue) return n.value;
    if (hostValue >= p.min && hostValue <= p.max) return hostValue;
    // Outside the range (the host's takes in the words' stand-ins): the nearest word.
    const NamedValue* nearest = nullptr;
    for (const NamedValue& n : p.named)
        if (!nearest || std::abs(n.hostValue - hostValue) < std::abs(nearest->hostValue - hostValue)) nearest = &n;
    return nearest ? nearest->value : hostValue;
}

std::string checkParam(const MethodParam& p, double v, bool named) {
    if (p.boolField || (v >= p.min && v <= p.max)) return "";
    for (const NamedValue& n : p.named)
        if (named && v == n.value) return "";
    char range[96];
    std::snprintf(range, sizeof range, " must be between %g and %g", p.min, p.max);
    std::string words;
    for (const NamedValue& n : p.named) words += std::string(", or ") + n.word;
    return std::string(p.flag) + range + words;
}

namespace {
std::vector<MethodOption> makeOptions() {
    // The four AO integrals weigh and fade their samples; SSDO's DO has its own definition.
    // HBAO's --bounce reads the bounce source too (kernels/hbao_gi.glsl): no map, no lights.
    const std::vector<const char*> ao = {"hbao", "ssao", "rtao", "discs"}, ssdo = {"ssdo"}, bounce = {"ssdo", "hbao"};
    return {
        {"weighting", "--weighting", "weighting", ao},
        {"falloff", "--falloff", "falloff", ao},
        {"bounce", "--bounce", nullptr, bounce},
        {"bounce_source", "--bounce-source", nullptr, bounce},
        {"env", "--env", "envMap", ssdo},
        {"env_rotate", "--env-rotate", "envRotation", ssdo},
        {"env_intensity", "--env-intensity", "envIntensity", ssdo},
        {"env_colorspace", "--env-colorspace", nullptr, ssdo},
        {"sky", "--sky", "skyColour", ssdo},
        {"lights", "--light", nullptr, ssdo},
        {"up", "--up", "upAxis", ssdo},
        // Only SSDO and HBAO's bounce read colour passes (the bounce source, albedo, direct light).
        {"colorspace", "--colorspace", nullptr, bounce},
        {"times_albedo", "--times-albedo", "timesAlbedo", bounce},
        {"relit_direct", "--relit-direct", nullptr, bounce},
    };
}

bool named(const std::string& name, const char* key, const char* flag, const char* ofx) {
    return name == key || name == flag || (ofx && name == ofx);
}

std::string methodWord(const std::string& method, Spelling spelling) {
    return spelling == Spelling::Flag ? "--method " + method : "method='" + method + "'";
}

std::string refusal(const std::string& what, const char* verb, const std::vector<std::string>& readers,
                    const std::string& method, Spelling spelling) {
    std::string who;
    for (size_t i = 0; i < readers.size(); ++i)
        who += (i == 0 ? "" : i + 1 == readers.size() ? " or " : ", ") + methodWord(readers[i], spelling);
    return what + " is " + verb + " by " + who + " only, not by " + methodWord(method, spelling);
}
} // namespace

const std::vector<MethodOption>& methodOptions() {
    static const std::vector<MethodOption> table = makeOptions();
    return table;
}

std::vector<std::string> methodsReading(const std::string& name) {
    std::vector<std::string> readers;
    for (const MethodInfo& m : methods())
        for (const MethodParam& p : m.params)
            if (named(name, p.key, p.flag, p.ofx ? p.key : nullptr)) {
                readers.push_back(m.name);
                readers.insert(readers.end(), p.alsoFor.begin(), p.alsoFor.end());
            }
    for (const MethodOption& o : methodOptions())
        if (named(name, o.key, o.flag, o.ofx)) readers.assign(o.methods.begin(), o.methods.end());
    return readers;
}

std::string settingRefusal(const std::string& method, const std::string& name, Spelling spelling) {
    const std::vector<std::string> readers = methodsReading(name);
    if (readers.empty() || std::find(readers.begin(), readers.end(), method) != readers.end()) return "";
    return refusal(name, "read", readers, method, spelling);
}

std::string outputRefusal(const std::string& method, const std::string& output, Spelling spelling) {
    if (methodOutputs(method, output.c_str())) return "";
    std::vector<std::string> writers;
    for (const MethodInfo& m : methods())
        if (listed(m.outputs, output.c_str())) writers.push_back(m.name);
    if (writers.empty()) return "unknown output '" + output + "'";
    const std::string what = spelling == Spelling::Flag ? "the " + output + " output" : "out_layer '" + output + "'";
    return refusal(what, "written", writers, method, spelling);
}

bool applyMethodPresets(const std::string& quality, Settings& s) {
    bool known = false;
    for (const MethodInfo& m : methods())
        for (const MethodPreset& p : m.presets)
            if (quality == p.quality) {
                p.apply(s);
                known = true;
            }
    return known;
}

} // namespace obscura
