#include "base/hbao_reach.h"

#include <algorithm>
#include <cmath>

namespace obscura {

namespace {

// Planar depth of the surface at buffer texel (x, y), or +inf for sky and holes. A pixel's
// screen radius falls as it grows, so the nearest surface bounds every pixel's reach.
double planarDepthAt(const glsl::KernelParams& p, ConstPlane depth, int x, int y) {
    double z = *depth.at(x, y) * (double)p.depthScale;
    if (!(z >= 1.17549435e-38 && z < p.skyDepth)) return INFINITY;
    if (p.radialDepth && !p.orthographic) {
        const double rx = (p.originX + x + 0.5 - p.cx) * p.invFx, ry = (p.cy - (p.originY + y + 0.5)) * p.invFy;
        z /= std::sqrt(1.0 + rx * rx + ry * ry);
    }
    return z;
}

// Screen radius of the sphere of radius R around a surface at planar depth z (the kernel's
// f R / sqrt(z^2 - R^2), f the larger of fx and fy, capped), or -1 without a surface.
double radiusPixelsAt(const glsl::KernelParams& p, double z) {
    if (!std::isfinite(z)) return -1.0;
    const double f = std::max(p.fx, p.fy);
    if (p.orthographic) return std::min((double)p.radius * f, (double)p.maxRadiusPixels);
    const double r = p.radius * f / std::sqrt(std::max(z * z - (double)p.radius * p.radius, 1e-30));
    return std::min(r, (double)p.maxRadiusPixels);
}

} // namespace

float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth) {
    double nearest = INFINITY;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) nearest = std::min(nearest, planarDepthAt(p, depth, x, y));
    return (float)std::max(radiusPixelsAt(p, nearest), 0.0);
}

} // namespace obscura
