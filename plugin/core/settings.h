// The user-facing settings of the operator: one struct shared by every host
// (CLI flags, OFX parameters, Python keyword arguments).
#pragma once
#include <limits>
#include <string>
#include <vector>

namespace obscura {

enum class Weighting { Uniform, Cosine };   // HBAO paper's solid angle / projected solid angle (ray-traced AO)
enum class Falloff { Linear, None };        // W(r) = max(0, 1 - r/R) / binary visibility within R
enum class DepthKind { Planar, Radial };    // camera-space Z / distance to the eye
// How a file stores its depth (--depth): as the operator reads it (planar, radial), or encoded,
// which plugin/io decodes to planar before the operator: inverse 1/z (Nuke's ScanlineRender),
// normalized (z - A) / (B - A) over --depth-range A,B (A > B: white is near).
enum class DepthEncoding { Planar, Radial, Inverse, Normalized };
// Camera space is OpenGL's: looking down -Z, +Y up. Depth: no normals are given (or they are
// ignored); the operator reconstructs them from the depth (kernels/depth_normal.glsl).
enum class NormalSpace { World, Camera, Depth };

constexpr float kThicknessInfinite = std::numeric_limits<float>::infinity();
constexpr float kThicknessAuto = -1.0f;
// Settings::border: open sky past the edge, the edge texel's depth, or its tangent plane continued.
constexpr int kBorderOpen = 0, kBorderClamp = 1, kBorderTangent = 2;
// Settings::blur: the method's own default, resolvedBlur().
constexpr int kBlurAuto = -1;

// The most sky radiance or light irradiance a component may have: beyond it the sums over a
// pixel's samples overflow float (1e38 gave NaN everywhere). --env-intensity has the same bound.
inline constexpr float kMaxLight = 1e9f;
// Whether `v` is such a component (NaN is not): the one test every host and the operator make.
inline bool withinLight(double v) { return v >= 0.0 && v <= kMaxLight; }

struct Settings {
    std::string method = "hbao";
    float radius = 1.0f;        // world units
    int directions = 8;         // N_d
    int steps = 8;              // N_s per direction
    Weighting weighting = Weighting::Uniform;
    Falloff falloff = Falloff::Linear;
    int blur = kBlurAuto;       // geometry-aware blur radius in pixels, 0 = off; kBlurAuto: resolvedBlur()
    int presetBlur = kBlurAuto; // the --quality level's blur, used where `blur` is kBlurAuto (not by ssdo)
    float skyDepth = 1e9f;      // depth at or beyond this (and inf/NaN/<=0) is background
    int threads = 0;            // 0 = all cores
    std::string device = "cpu";

    // ---- method "ssdo" (Ritschel et al. 2009); `radius` is r_max ----
    int ssdoSamples = 64;           // N, the sample set shared by an interleaving block
    int interleave = 2;             // M: an M x M block splits the set (N / M^2 samples per pixel)
    bool bounce = false;            // also compute one indirect bounce (GI)
    float skyRadiance[3] = {1.0f, 1.0f, 1.0f};  // constant sky when there is no environment map (<= kMaxLight)
    float envRotationDeg = 0.0f;    // turns the environment about the up axis
    float envIntensity = 1.0f;
    bool zUp = false;               // world up is +Z (Blender) rather than +Y, for the environment
    struct DirectionalLight {
        float direction[3];         // world space, towards the light
        float irradiance[3];        // at normal incidence
    };
    std::vector<DirectionalLight> lights;  // at most 4
    // Cap on the projected sampling radius in pixels; 0 = automatic (the data window's
    // extent). Hosts that render in tiles pin it so every tile uses the same cap.
    float maxRadiusPixels = 0.0f;

    // ---- method "ssao" (Crytek's screen-space AO) ----
    int ssaoSamples = 16;           // points per pixel
    bool ssaoHemisphere = false;    // normal-oriented hemisphere instead of the whole sphere

    // ---- methods "hbao" and "rtao": how deep the surfaces the depth pass shows are ----
    // World units behind each visible point that are solid; kThicknessInfinite: the depth
    // buffer is a height field (HBAO's classic horizon); kThicknessAuto: rtao resolvedThickness(),
    // hbao each occluder's width across the slice, at most resolvedThickness().
    float thickness = kThicknessAuto;

    // ---- method "hbao": samples past the buffer's edge (where there is no overscan) ----
    int border = kBorderTangent;
    // ---- method "hbao" with deep input: at most this many surfaces per texel (docs/deep.md) ----
    int deepLayers = 4;

    // ---- method "rtao" (rays against the mesh of the depth pass) ----
    int rtaoRays = 16;              // cosine-distributed rays per traced point
    int rtaoGrid = 1;               // trace every N-th pixel and interpolate; 1: every pixel

    // ---- method "discs" (hierarchical disc form factors, docs/discs.md) ----
    int discsWindow = 1;            // k: a node is opened within k + 1/2 of its sizes of the receiver (1: the speed budget, docs/discs.md)
    int discsPasses = 1;            // 2: weight each element by its own first-pass AO (correction c)
    bool discsBlendLevels = false;  // blend between levels, no seams (correction a); default: hard windows
    bool discsNoPolygon = false;    // discs for the nearest pixels too (correction b off)
    bool discsSum = false;          // sum the form factors, without the hemisphere bins' union
};

// Named quality levels: directions x steps (and blur), from a preview to near-converged.
struct QualityPreset {
    const char* name;
    int directions, steps, blur;
};
const std::vector<QualityPreset>& qualityPresets();  // low, medium, high, ultra
// Applies every method's level `name` (core/methods.h) to `s`; false for an unknown name.
bool applyQualityPreset(const std::string& name, Settings& s);

// The blur radius in pixels that `s` asks for: `blur` when given, else the quality level's, else
// the `medium` preset's, so the default hbao (8 x 8), ssao (16 points) and rtao (16 rays) are
// medium; docs/cli.md measures the grain it removes. ssdo gathers its M x M interleaving block
// instead: kBlurAuto or 0 give M (0 when M is 1), whatever the quality level.
int resolvedBlur(const Settings& s);

// The thickness in world units that `s` asks for: s.thickness, or for kThicknessAuto
// kAutoThicknessPerRadius times R (hbao: the most a measured occluder gets); +inf for
// kThicknessInfinite.
constexpr float kAutoThicknessPerRadius = 0.85f;
float resolvedThickness(const Settings& s);

const char* toString(Weighting);
const char* toString(Falloff);
const char* toString(DepthKind);
const char* toString(DepthEncoding);
const char* toString(NormalSpace);
// Parse helpers: return false on an unknown spelling.
bool parse(const std::string&, Weighting&);
bool parse(const std::string&, Falloff&);
bool parse(const std::string&, DepthKind&);
bool parse(const std::string&, DepthEncoding&);
// The kind the operator reads once the encoding is decoded: radial for radial, else planar.
DepthKind decodedKind(DepthEncoding);
bool parse(const std::string&, NormalSpace&);

} // namespace obscura
