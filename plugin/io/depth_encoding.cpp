#include "io/depth_encoding.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace obscura {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// One stored value of a normalised depth: A + v (B - A), the far end or beyond being sky.
float normalised(float v, double a, double b) {
    if (std::isnan(v)) return v;
    const double z = a + (double)v * (b - a);
    return z >= std::max(a, b) ? kInf : (float)z;
}

} // namespace

void requireDecodable(const DepthDecoding& d) {
    if (d.encoding == DepthEncoding::Normalized && !d.range)
        throw Error("--depth normalized needs --depth-range NEAR,FAR: the distances its 0 and 1 stand for");
}

void decodeDepth(Image& depth, const DepthDecoding& d) {
    requireDecodable(d);
    for (float& v : depth.pixels) {
        if (std::isinf(v)) {
            v = kInf;
            continue;
        }
        if (d.encoding == DepthEncoding::Normalized) v = normalised(v, (*d.range)[0], (*d.range)[1]);
        else if (v == 0.0f) v = kInf;  // no surface: a plate's background (alpha 0), inverse's sky
        else if (d.encoding == DepthEncoding::Inverse) v = 1.0f / v;
    }
}

Image depthFromPositions(const Image& positions, const Camera& camera) {
    if (!camera.hasPose)
        throw Error("the file has no depth layer, and its depth from the position pass needs the camera's pose "
                    "(--camera-to-world, a sidecar or the header's camera)");
    const glm::dmat4 toCamera = camera.worldToCamera();
    Image depth(positions.width, positions.height, 1);
    for (size_t i = 0; i < depth.pixels.size(); ++i) {
        const float* p = &positions.pixels[3 * i];
        const bool none = !(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) ||
                          (p[0] == 0.0f && p[1] == 0.0f && p[2] == 0.0f);
        const glm::dvec4 c = toCamera * glm::dvec4(p[0], p[1], p[2], 1.0);
        depth.pixels[i] = none ? kInf : (float)-c.z;  // planar: the distance along the view axis
    }
    return depth;
}

DepthStatistics depthStatistics(const Image& stored, float skyDepth, const std::string& type) {
    DepthStatistics s;
    s.type = type;
    double lo = INFINITY, hi = -INFINITY;
    long long sky = 0, ones = 0;
    for (float v : stored.pixels) {
        if (!std::isfinite(v) || v == 0.0f || v >= skyDepth) {
            ++sky;
            continue;
        }
        lo = std::min(lo, (double)v);
        hi = std::max(hi, (double)v);
        ones += v == 1.0f;
    }
    const double n = (double)std::max<size_t>(stored.pixels.size(), 1);
    s.skyShare = sky / n;
    if (lo > hi) return s;
    s.min = lo, s.max = hi;
    if (lo < 0.0 || hi > 1.0) return s;
    s.hint = ones >= 0.01 * n ? "a normalised depth whose far end (1) is the sky: try --depth normalized --depth-range NEAR,FAR"
                              : "every value is in [0, 1]: an inverse (--depth inverse) or normalised (--depth normalized "
                                "--depth-range NEAR,FAR) depth rather than a distance";
    return s;
}

} // namespace obscura
