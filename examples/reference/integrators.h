// Per-pixel estimators: primary hit, direct light, one-bounce indirect diffuse,
// and the four ray-traced AO definitions of docs/hbao.md (weighting x falloff).
#pragma once
#include "camera.h"
#include "environment.h"
#include "tracer.h"

#include <array>
#include <cstdint>
#include <memory>

namespace reference {

enum AoLayer { kUniformLinear, kUniformNone, kCosineLinear, kCosineNone, kAoLayers };
extern const char* const kAoLayerNames[kAoLayers];  // "AO_uniform_linear", ...

struct RenderSettings {
    int width = 320, height = 240;
    double radius = 1;
    int aoRays = 256;  // per weighting; both falloffs share one hit distance
    int giRays = 64;   // cosine-weighted rays per pixel for the sky light and one bounce
    uint32_t seed = 1;
    int threads = 0;   // 0: all cores
    // Pixels rendered past each edge of the width x height display window (a data window
    // 2 overscan larger each way), as renderers write overscan; AO is traced there too.
    int overscan = 0;
    // --env: a lat-long map; when set, each pixel also gets the ground-truth directional
    // occlusion (Reference.DO), from the cosine-weighted AO rays.
    std::shared_ptr<const EnvironmentMap> environment;
    // --do-sun: Reference.DO also holds the sun as obscura's --light: its irradiance (pi x sunColour) x cos,
    // unless something lies within `radius` towards it.
    bool sunInDo = false;
};

struct PixelResult {
    bool sky = true;
    glm::vec3 beauty{0.0f};
    double depth = 1e10;
    glm::dvec3 normal{0.0}, position{0.0};
    glm::vec3 albedo{0.0f}, direct{0.0f}, indirect{0.0f};
    std::array<double, kAoLayers> ao{1, 1, 1, 1}, aoStdErr{0, 0, 0, 0};
    double indirectStdErr = 0;  // of the luminance of `indirect`
    // With an environment: integral of L_env(w) (1 - W(t(w))) cos(theta) dw, W linear (obscura's SSDO DO).
    glm::vec3 directionalOcclusion{0.0f};
    // One-bounce irradiance (not / pi): integral of L_s(w) cos(theta) dw, L_s = albedo x direct irradiance / pi of
    // the first surface hit along w; `giNear` counts only hits within `radius` (SSDO's GI), `giFull` every hit.
    glm::vec3 giNear{0.0f}, giFull{0.0f};
};

class Integrator {
public:
    Integrator(const Scene& scene, const Tracer& tracer, const PinholeCamera& camera, const RenderSettings& settings)
        : scene_(scene), tracer_(tracer), camera_(camera), settings_(settings) {}
    PixelResult shade(int x, int y) const;
    // The seed of display pixel (x, y)'s sample sets.
    uint32_t pixelSeed(int x, int y) const;
    // DiffDir at a surface point p (normal n facing the viewer, eps its ray offset): the lights with
    // their shadow rays plus the sky through giRays cosine rays of `seed`'s bounce set. At a pixel's
    // primary hit with pixelSeed(x, y) this is the flat DiffDir (what shade computes, here without the
    // bounce); x albedo it is what the surface radiates as Reference.GI's sender.
    glm::vec3 directDiffuse(const glm::dvec3& p, const glm::dvec3& n, double eps, uint32_t seed) const;

private:
    // Sun and point lights at p (DiffDir units), with shadow rays.
    glm::vec3 lights(const glm::dvec3& p, const glm::dvec3& n, double eps) const;
    void ambientOcclusion(const glm::dvec3& origin, const glm::dvec3& n, uint32_t pixelSeed, PixelResult& out) const;
    void diffuseLight(const glm::dvec3& origin, const glm::dvec3& n, uint32_t pixelSeed, PixelResult& out) const;

    const Scene& scene_;
    const Tracer& tracer_;
    const PinholeCamera& camera_;
    const RenderSettings& settings_;
};

// Ray-origin offset along the normal, relative to the magnitude of the position
// and the distance travelled (float precision scales with both): works from
// centimetres to kilometres in one scene.
double offsetEpsilon(const glm::dvec3& p, double distance);

} // namespace reference
