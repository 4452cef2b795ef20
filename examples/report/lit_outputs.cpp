#include "lit_outputs.h"

#include "reference/environment.h"

#include "base/error.h"
#include "io/frame_job.h"

#include <cmath>

namespace report {

namespace {

// An RGB layer of `exrPath`, read by the frame reader the way the CLI reads a bounce source.
obscura::Image readRgbLayer(const std::string& exrPath, const std::string& layer) {
    obscura::FrameJob job;
    job.input = exrPath;
    job.preset = "blender";
    job.settings.method = "ssdo";
    job.writeIndirect = true;
    job.bounceSource = layer;
    obscura::Image rgb = std::move(obscura::loadFramePasses(job, {}).radiance);
    if (rgb.empty()) throw obscura::Error("'" + exrPath + "' has no " + layer + " layer");
    return rgb;
}

obscura::Image luminance(const obscura::Image& rgb) {
    obscura::Image y(rgb.width, rgb.height, 1);
    for (size_t i = 0, n = size_t(rgb.width) * rgb.height; i < n; ++i)
        y.pixels[i] = 0.2126f * rgb.pixels[3 * i] + 0.7152f * rgb.pixels[3 * i + 1] + 0.0722f * rgb.pixels[3 * i + 2];
    return y;
}

double surfaceMean(const obscura::Image& y, const LoadedFrame& f) {
    double sum = 0;
    long long n = 0;
    for (int row = 0; row < y.height; ++row)
        for (int x = 0; x < y.width; ++x) {
            const float d = *f.passes.depth.at(x, row);
            if (d > 0.0f && d < f.skyDepth && std::isfinite(*y.at(x, row))) {
                sum += *y.at(x, row);
                ++n;
            }
        }
    return n ? sum / double(n) : 0.0;
}

} // namespace

LitReferences loadLitReferences(const std::string& exrPath) {
    return {readRgbLayer(exrPath, "Reference.DO"), readRgbLayer(exrPath, "Reference.GI"),
            readRgbLayer(exrPath, "Reference.GI_unlimited")};
}

obscura::Image skyEnvironment(const reference::Scene& scene) {
    const reference::EnvironmentMap map = reference::skyMap(scene.lighting);
    obscura::Image env(map.width, map.height, 3);
    env.pixels.assign(map.rgb.begin(), map.rgb.end());
    return env;
}

void applySceneLights(const reference::Scene& scene, obscura::Settings& s) {
    s.zUp = true;
    s.envRotationDeg = 0;
    s.envIntensity = 1;
    const reference::Lighting& l = scene.lighting;
    if (glm::length(l.sunColour) <= 0) return;
    obscura::Settings::DirectionalLight sun{};
    for (int c = 0; c < 3; ++c) {
        sun.direction[c] = float(l.sunDirection[c]);
        sun.irradiance[c] = float(M_PI * l.sunColour[c]);
    }
    s.lights = {sun};
}

LitError litError(const obscura::Image& rgb, const obscura::Image& referenceRgb, const LoadedFrame& f) {
    if (rgb.empty() || referenceRgb.empty()) throw obscura::Error("litError: an empty image");
    const obscura::Image y = luminance(rgb), ref = luminance(referenceRgb);
    LitError e;
    e.metrics = nonSkyError(y, ref, f);
    e.referenceMean = surfaceMean(ref, f);
    if (e.referenceMean > 0) {
        e.relativeRmse = e.metrics.rmse / e.referenceMean;
        e.meanRatio = surfaceMean(y, f) / e.referenceMean;
    }
    return e;
}

} // namespace report
