#include "integrators.h"

#include "sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace reference {

const char* const kAoLayerNames[kAoLayers] = {"AO_uniform_linear", "AO_uniform_none", "AO_cosine_linear",
                                              "AO_cosine_none"};

namespace {
constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Seeds of the independent 2D sample sets used in one pixel.
enum SampleUse : uint32_t { kAoUniformSet = 1, kAoCosineSet, kBounceSet, kBounceSkySet };

double luminance(const glm::vec3& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

double standardError(double sum, double sumSquares, int n) {
    if (n < 2) return 0;
    const double mean = sum / n, variance = std::max(0.0, (sumSquares - n * mean * mean) / (n - 1));
    return std::sqrt(variance / n);
}
} // namespace

double offsetEpsilon(const glm::dvec3& p, double distance) {
    const double magnitude = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), distance});
    return 5e-6 * magnitude + 1e-9;
}

glm::vec3 Integrator::lights(const glm::dvec3& p, const glm::dvec3& n, double eps) const {
    const Lighting& l = scene_.lighting;
    const glm::dvec3 origin = p + eps * n;
    glm::vec3 sum(0.0f);
    const double sunCos = glm::dot(n, l.sunDirection);
    if (sunCos > 0 && glm::length(l.sunColour) > 0 && !tracer_.occluded(origin, l.sunDirection, 0, kInfinity))
        sum += l.sunColour * float(sunCos);
    for (const PointLight& pl : l.points) {
        const glm::dvec3 d = pl.position - p;
        const double dist = glm::length(d), c = glm::dot(n, d) / dist;
        if (c > 0 && !tracer_.occluded(origin, d / dist, 0, float(dist * (1 - 1e-5))))
            sum += pl.intensity * float(c / (dist * dist));
    }
    return sum;
}

// AO = 1 - E[W(t)]: W = 1 - t/R (linear) or 1 (none) for a hit at t <= R, 0 otherwise.
void Integrator::ambientOcclusion(const glm::dvec3& origin, const glm::dvec3& n, uint32_t pixelSeed,
                                  PixelResult& out) const {
    const int count = settings_.aoRays;
    const double R = settings_.radius;
    for (int cosine = 0; cosine < 2; ++cosine) {
        const SobolSet samples(hashCombine(pixelSeed, cosine ? kAoCosineSet : kAoUniformSet));
        double linear = 0, linear2 = 0, none = 0;  // none == none^2 (binary)
        const EnvironmentMap* env = cosine ? settings_.environment.get() : nullptr;
        glm::dvec3 directional(0.0);  // sum of L_env(w) (1 - W), W linear
        for (int first = 0; first < count; first += 8) {
            const int batch = std::min(8, count - first);
            glm::dvec3 dirs[8];
            float t[8];
            for (int k = 0; k < batch; ++k) {
                const glm::dvec2 u = samples(uint32_t(first + k));
                dirs[k] = toWorld(cosine ? cosineHemisphere(u) : uniformHemisphere(u), n);
            }
            tracer_.hitDistances8(origin, dirs, batch, float(R), t);
            for (int k = 0; k < batch; ++k) {
                const bool hit = t[k] <= R;  // else a miss, or beyond R: W = 0
                const double w = hit ? std::max(0.0, 1.0 - t[k] / R) : 0.0;
                if (env && w < 1) directional += (1 - w) * env->radiance(dirs[k]);
                if (!hit) continue;
                linear += w, linear2 += w * w, none += 1;
            }
        }
        const int lin = cosine ? kCosineLinear : kUniformLinear, bin = cosine ? kCosineNone : kUniformNone;
        out.ao[lin] = 1 - linear / count;
        out.ao[bin] = 1 - none / count;
        out.aoStdErr[lin] = standardError(linear, linear2, count);
        out.aoStdErr[bin] = standardError(none, none, count);
        // Cosine-weighted: irradiance = pi / n * sum of L (1 - W).
        if (env) out.directionalOcclusion = glm::vec3(directional * (M_PI / count));
    }
    const Lighting& l = scene_.lighting;
    const double sunCos = glm::dot(n, l.sunDirection);
    if (settings_.environment && settings_.sunInDo && sunCos > 0 && !tracer_.occluded(origin, l.sunDirection, 0, float(R)))
        out.directionalOcclusion += l.sunColour * float(M_PI * sunCos);  // sunColour is DiffDir: irradiance / pi
}

// Cosine-weighted rays: a miss sees the sky (direct light, DiffDir); a hit sees a
// surface lit by the sun, point lights and one sky sample (indirect, DiffInd).
// With pdf cos/pi, (1/pi) * integral(L cos) is the plain mean of L.
void Integrator::diffuseLight(const glm::dvec3& origin, const glm::dvec3& n, uint32_t pixelSeed,
                              PixelResult& out) const {
    const int count = settings_.giRays;
    const SobolSet bounceSamples(hashCombine(pixelSeed, kBounceSet)), skySamples(hashCombine(pixelSeed, kBounceSkySet));
    glm::dvec3 skySum(0.0), indirectSum(0.0), nearSum(0.0);
    double lum = 0, lum2 = 0;
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 dir = toWorld(cosineHemisphere(bounceSamples(uint32_t(i))), n);
        const Hit h = tracer_.intersect(origin, dir, 0, kInfinity);
        if (!h.found) {
            skySum += glm::dvec3(scene_.lighting.sky(dir));
            continue;
        }
        const glm::dvec3 q = origin + double(h.t) * dir;
        const double eps = offsetEpsilon(q, h.t);
        glm::vec3 light = lights(q, h.normal, eps);
        const glm::dvec3 skyDir = toWorld(cosineHemisphere(skySamples(uint32_t(i))), h.normal);
        if (!tracer_.occluded(q + eps * h.normal, skyDir, 0, kInfinity)) light += scene_.lighting.sky(skyDir);
        const glm::vec3 radiance = h.albedo * light;
        indirectSum += glm::dvec3(radiance);
        if (h.t <= settings_.radius) nearSum += glm::dvec3(radiance);
        const double y = luminance(radiance);
        lum += y, lum2 += y * y;
    }
    if (count > 0) {
        out.direct += glm::vec3(skySum / double(count));
        out.indirect = glm::vec3(indirectSum / double(count));
        // Irradiance = pi x the mean radiance of cosine-distributed rays.
        out.giFull = glm::vec3(indirectSum * (M_PI / count));
        out.giNear = glm::vec3(nearSum * (M_PI / count));
        out.indirectStdErr = standardError(lum, lum2, count);
    }
}

uint32_t Integrator::pixelSeed(int x, int y) const {
    return hashCombine(hashCombine(settings_.seed, uint32_t(x)), uint32_t(y));
}

// The sky half of diffuseLight's rays alone (same samples, same sum and order), so the result is
// shade's DiffDir to the bit where the hits agree.
glm::vec3 Integrator::directDiffuse(const glm::dvec3& p, const glm::dvec3& n, double eps, uint32_t seed) const {
    glm::vec3 direct = lights(p, n, eps);
    const int count = settings_.giRays;
    if (count <= 0) return direct;
    const glm::dvec3 origin = p + eps * n;
    const SobolSet samples(hashCombine(seed, kBounceSet));
    glm::dvec3 skySum(0.0);
    for (int i = 0; i < count; ++i) {
        const glm::dvec3 dir = toWorld(cosineHemisphere(samples(uint32_t(i))), n);
        if (!tracer_.intersect(origin, dir, 0, kInfinity).found) skySum += glm::dvec3(scene_.lighting.sky(dir));
    }
    return direct + glm::vec3(skySum / double(count));
}

PixelResult Integrator::shade(int x, int y) const {
    PixelResult out;
    const glm::dvec3 ray = camera_.ray(x + 0.5, y + 0.5);  // planar depth 1
    const Hit h = tracer_.intersect(camera_.eye, ray, 0, kInfinity);
    if (!h.found) {
        out.beauty = scene_.lighting.sky(glm::normalize(ray));
        return out;
    }
    out.sky = false;
    out.depth = h.t;  // planar, since |ray . forward| = 1
    out.position = camera_.eye + double(h.t) * ray;
    out.normal = h.normal;
    out.albedo = h.albedo;
    const double eps = offsetEpsilon(out.position, h.t * glm::length(ray));
    const glm::dvec3 origin = out.position + eps * out.normal;
    const uint32_t seed = pixelSeed(x, y);
    out.direct = lights(out.position, out.normal, eps);
    diffuseLight(origin, out.normal, seed, out);
    ambientOcclusion(origin, out.normal, seed, out);
    out.beauty = out.albedo * (out.direct + out.indirect);
    return out;
}

} // namespace reference
