// The user-facing settings of the operator: one struct shared by every host
// (CLI flags, OFX parameters, Python keyword arguments).
#pragma once
#include <string>
#include <vector>

namespace obscura {

enum class Weighting { Uniform, Cosine };   // HBAO paper's solid angle / projected solid angle (ray-traced AO)
enum class Falloff { Linear, None };        // W(r) = max(0, 1 - r/R) / binary visibility within R
enum class DepthKind { Planar, Radial };    // camera-space Z / distance to the eye
enum class NormalSpace { World, Camera };   // camera space is OpenGL's: looking down -Z, +Y up

struct Settings {
    std::string method = "hbao";
    float radius = 1.0f;        // world units
    int directions = 8;         // N_d
    int steps = 8;              // N_s per direction
    Weighting weighting = Weighting::Uniform;
    Falloff falloff = Falloff::Linear;
    int blur = 0;               // geometry-aware blur radius in pixels, 0 = off
    float skyDepth = 1e9f;      // depth at or beyond this (and inf/NaN/<=0) is background
    int threads = 0;            // 0 = all cores
    std::string device = "cpu";
};

// Named quality levels: directions x steps (and blur), from a preview to near-converged.
struct QualityPreset {
    const char* name;
    int directions, steps, blur;
};
const std::vector<QualityPreset>& qualityPresets();  // low, medium, high, ultra
// Applies the preset's sample counts to `s`; false for an unknown name.
bool applyQualityPreset(const std::string& name, Settings& s);

const char* toString(Weighting);
const char* toString(Falloff);
const char* toString(DepthKind);
const char* toString(NormalSpace);
// Parse helpers: return false on an unknown spelling.
bool parse(const std::string&, Weighting&);
bool parse(const std::string&, Falloff&);
bool parse(const std::string&, DepthKind&);
bool parse(const std::string&, NormalSpace&);

} // namespace obscura
