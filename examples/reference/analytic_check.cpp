#include "analytic_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <utility>
#include <vector>

namespace reference {
namespace {
constexpr double kPi = 3.14159265358979323846;

bool isFloor(const PixelResult& p) { return !p.sky && p.normal.z > 0.999 && std::abs(p.position.z) < 1e-4; }

// Floor pixels far from all geometry but the floor must be exactly unoccluded.
bool openPlaneCheck(const Frame& f, const std::function<bool(const glm::dvec3&)>& open) {
    size_t count = 0;
    double worst = 0;
    for (const PixelResult& p : f.pixels)
        if (isFloor(p) && open(p.position)) {
            ++count;
            for (double a : p.ao) worst = std::max(worst, std::abs(1 - a));
        }
    std::printf("  open plane: %zu floor pixels beyond R of any other surface, max |1 - AO| = %.3g (all 4 layers)\n",
                count, worst);
    return count > 0 && worst == 0;
}
} // namespace

std::array<double, kAoLayers> cornerAo(double c) {
    if (c >= 1) return {1, 1, 1, 1};
    // Hit distance along a direction with wall-ward component u >= c is d / u, so
    // W_linear = 1 - c / u. Uniform: u is uniform on [0, 1] over the half facing the
    // wall; cosine: u is the x of a point uniform on the unit disk.
    const double s = std::sqrt(1 - c * c);
    const double uniformNone = (1 - c) / 2;
    const double uniformLinear = ((1 - c) + c * std::log(c)) / 2;
    const double cosineNone = (std::acos(c) - c * s) / kPi;
    const double cosineLinear = (2 / kPi) * ((kPi / 4 - (c * s + std::asin(c)) / 2) - c * (std::log((1 + s) / c) - s));
    return {1 - uniformLinear, 1 - uniformNone, 1 - cosineLinear, 1 - cosineNone};
}

bool runAnalyticChecks(const std::string& sceneName, const Frame& f, const RenderSettings& settings, const Scene& scene) {
    const double R = settings.radius;
    bool ok = true;
    if (sceneName == "corner") {
        std::printf("analytic check: corner, floor pixels binned by distance d to the wall (R = %g)\n", R);
        std::printf("  %-6s %-7s", "d/R", "pixels");
        for (const char* n : kAoLayerNames) std::printf("  %-26s", n);
        std::printf("\n  %-14s", "");
        for (int l = 0; l < kAoLayers; ++l) std::printf("  %-8s %-8s %-8s", "ref", "exact", "err/se");
        std::printf("\n");
        for (double c : {0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.98, 1.5}) {
            std::array<double, kAoLayers> ref{}, exact{}, se{};
            size_t n = 0;
            for (const PixelResult& p : f.pixels) {
                if (!isFloor(p) || std::abs(p.position.x / R - c) > 0.01) continue;
                const auto e = cornerAo(p.position.x / R);
                for (int l = 0; l < kAoLayers; ++l) ref[l] += p.ao[l], exact[l] += e[l], se[l] += p.aoStdErr[l] * p.aoStdErr[l];
                ++n;
            }
            if (n == 0) continue;
            std::printf("  %-6.2f %-7zu", c, n);
            for (int l = 0; l < kAoLayers; ++l) {
                // The bin mean's standard error; the iid estimate overstates it for Sobol samples.
                const double mean = ref[l] / n, truth = exact[l] / n, stderrMean = std::sqrt(se[l]) / n;
                const double z = stderrMean > 0 ? (mean - truth) / stderrMean : (mean == truth ? 0 : 1e9);
                std::printf("  %-8.5f %-8.5f %-8.2f", mean, truth, z);
                if (std::abs(z) > 4 && std::abs(mean - truth) > 1e-3) ok = false;
            }
            std::printf("\n");
        }
        ok = openPlaneCheck(f, [R](const glm::dvec3& p) { return p.x > R * 1.001; }) && ok;
    } else if (scene.groundMesh >= 0) {
        // Bounding spheres of everything but the ground: floor pixels farther than R from all of them are open.
        std::vector<std::pair<glm::dvec3, double>> bounds;
        for (const Sphere& s : scene.spheres) bounds.push_back({s.centre, s.radius});
        for (size_t i = 0; i < scene.meshes.size(); ++i) {
            if (int(i) == scene.groundMesh) continue;
            glm::dvec3 lo(1e300), hi(-1e300);
            for (const glm::vec3& v : scene.meshes[i].vertices) lo = glm::min(lo, glm::dvec3(v)), hi = glm::max(hi, glm::dvec3(v));
            bounds.push_back({0.5 * (lo + hi), 0.5 * glm::length(hi - lo)});
        }
        std::printf("analytic check: %s (R = %g)\n", sceneName.c_str(), R);
        ok = openPlaneCheck(f, [&](const glm::dvec3& p) {
            for (const auto& [centre, radius] : bounds)
                if (glm::length(p - centre) <= radius + R * 1.001) return false;
            return true;
        });
    } else {
        std::printf("analytic check: no closed form for scene %s\n", sceneName.c_str());
        return true;
    }
    std::printf("analytic check: %s\n", ok ? "passed" : "FAILED");
    return ok;
}

} // namespace reference
