#include "support/deep_elements.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

namespace obscura::test {

namespace {

// A solid the ray crosses from t0 to t1, as a deep renderer writes one: a volume sample.
std::vector<DeepSample> solid(std::optional<std::pair<double, double>> span, float r, float g, float b) {
    if (!span || span->second <= 0) return {};
    return {{(float)span->first, (float)span->second, r, g, b, 1.0f}};
}

} // namespace

void deepRay(int x, int y, int width, int height, double ray[3]) {
    const double f = 0.5 * width / std::tan(0.5 * kDeepFovDeg * M_PI / 180.0);
    ray[0] = (x + 0.5 - 0.5 * width) / f;
    ray[1] = -(y + 0.5 - 0.5 * height) / f;
    ray[2] = -1.0;
}

void writeDeepElement(const std::string& path, const DeepHit& hit, int width, int height) {
    OIIO::ImageSpec spec(width, height, 6, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
    spec.alpha_channel = 3;
    spec.z_channel = 4;
    spec.deep = true;
    spec.attribute("compression", "zips");
    std::vector<std::vector<DeepSample>> pixels;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double ray[3];
            deepRay(x, y, width, height, ray);
            pixels.push_back(hit(ray));
        }
    OIIO::DeepData dd;
    dd.init(spec);
    for (size_t p = 0; p < pixels.size(); ++p) dd.set_samples((int64_t)p, (int)pixels[p].size());
    for (size_t p = 0; p < pixels.size(); ++p)
        for (size_t s = 0; s < pixels[p].size(); ++s) {
            const DeepSample& v = pixels[p][s];
            const float values[6] = {v.r, v.g, v.b, v.a, v.z, v.zBack};
            for (int c = 0; c < 6; ++c) dd.set_deep_value((int64_t)p, c, (int)s, values[c]);
        }
    auto out = OIIO::ImageOutput::create(path);
    if (!out || !out->open(path, spec) || !out->write_deep_image(dd) || !out->close())
        throw std::runtime_error("cannot write " + path + ": " + (out ? out->geterror() : OIIO::geterror()));
}

std::vector<DeepSample> deepGround(const double d[3]) {
    if (d[1] >= -1e-9) return {};
    const float t = (float)(-1.0 / d[1]);
    return {{t, t, 0.5f, 0.5f, 0.5f, 1.0f}};
}

std::vector<DeepSample> deepBall(const double d[3]) {
    const double c[3] = {0, -0.5, -5}, r = 0.5;
    const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], b = -(d[0] * c[0] + d[1] * c[1] + d[2] * c[2]);
    const double k = c[0] * c[0] + c[1] * c[1] + c[2] * c[2] - r * r, disc = b * b - a * k;
    if (disc <= 0) return {};
    return solid(std::pair{(-b - std::sqrt(disc)) / a, (-b + std::sqrt(disc)) / a}, 1, 0, 0);
}

std::vector<DeepSample> deepBox(const double d[3], const double lo[3], const double hi[3], float r, float g, float b) {
    double t0 = 0, t1 = 1e30;
    for (int i = 0; i < 3; ++i) {
        double a = lo[i] / d[i], c = hi[i] / d[i];
        if (a > c) std::swap(a, c);
        t0 = std::max(t0, a);
        t1 = std::min(t1, c);
    }
    return solid(t0 < t1 ? std::optional{std::pair{t0, t1}} : std::nullopt, r, g, b);
}

std::vector<DeepSample> deepTree(const double d[3]) {
    const double lo[3] = {0.55, -1, -5.4}, hi[3] = {0.95, 1.5, -4.6};
    return deepBox(d, lo, hi, 0, 1, 0);
}

std::vector<bool> deepCoverage(const DeepHit& hit, int width, int height, const std::function<bool(double x)>& side) {
    std::vector<bool> on;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            double ray[3];
            deepRay(x, y, width, height, ray);
            const std::vector<DeepSample> s = hit(ray);
            on.push_back(!s.empty() && (!side || side(ray[0] * s[0].z)));
        }
    return on;
}

} // namespace obscura::test
