#include "cpu/hbao_border.h"

#include "cpu/parallel.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace obscura::cpu {

namespace {

// Planar depth of the surface at buffer texel (x, y), or +inf for sky and holes. A pixel's
// screen radius falls as it grows, so a row's or a column's nearest surface bounds its reach.
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
// f R / sqrt(z^2 - R^2), capped), or -1 without a surface.
double radiusPixelsAt(const glsl::KernelParams& p, double z) {
    if (!std::isfinite(z)) return -1.0;
    if (p.orthographic) return std::min((double)p.radius * p.fx, (double)p.maxRadiusPixels);
    const double r = p.radius * (double)p.fx / std::sqrt(std::max(z * z - (double)p.radius * p.radius, 1e-30));
    return std::min(r, (double)p.maxRadiusPixels);
}

// How far past each edge a sample reaches: a sample's texel lies within its pixel's radius
// plus one texel of rounding; one more keeps the kernel's test with a texel to spare passing.
// Pixels under a radius of 1 compute nothing (the kernel's test).
Box2i readBox(const glsl::KernelParams& p, ConstPlane depth) {
    std::vector<double> columnNearest(depth.width, INFINITY), rowNearest(depth.height, INFINITY);
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const double z = planarDepthAt(p, depth, x, y);
            columnNearest[x] = std::min(columnNearest[x], z);
            rowNearest[y] = std::min(rowNearest[y], z);
        }
    double left = 0, top = 0, right = 0, bottom = 0;
    for (int x = 0; x < depth.width; ++x) {
        const double r = radiusPixelsAt(p, columnNearest[x]);
        if (r < 1.0) continue;
        left = std::max(left, r - x);
        right = std::max(right, r - (depth.width - 1 - x));
    }
    for (int y = 0; y < depth.height; ++y) {
        const double r = radiusPixelsAt(p, rowNearest[y]);
        if (r < 1.0) continue;
        top = std::max(top, r - y);
        bottom = std::max(bottom, r - (depth.height - 1 - y));
    }
    const auto pad = [](double reach) { return reach > 0 ? (int)std::ceil(reach) + 2 : 0; };
    return Box2i{-pad(left), -pad(top), depth.width + pad(right), depth.height + pad(bottom)};
}

} // namespace

float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth) {
    double nearest = INFINITY;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) nearest = std::min(nearest, planarDepthAt(p, depth, x, y));
    return (float)std::max(radiusPixelsAt(p, nearest), 0.0);
}

BorderedDepth continueBorder(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, int threads,
                             const IsaKernels& k) {
    BorderedDepth b;
    b.params = p;
    const Box2i box = p.hbaoBorder != 0 ? readBox(p, depth) : Box2i{0, 0, p.width, p.height};
    b.params.depthX0 = box.x0;
    b.params.depthY0 = box.y0;
    b.params.depthX1 = box.x1;
    b.params.depthY1 = box.y1;
    if (p.hbaoBorder == 0) {
        b.depth = depth;
        return b;
    }
    // Not zeroed: the border kernel writes every texel of the box. Large boxes (a radius spanning
    // the frame) take huge pages: a page fault per 2 MiB.
    b.storage = allocateBigFloats((std::size_t)box.width() * box.height());
    const MutablePlane stored{b.storage.get(), box.width(), box.height(), 1, 1, box.width()};
    b.box = stored;
    // Addressed in buffer coordinates: the box's corner (x0, y0) is the plane's first texel.
    MutablePlane out = stored;
    out.data -= box.y0 * out.yStride + box.x0 * out.xStride;
    out.width = p.width;
    out.height = p.height;
    parallelForTiles(box, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { k.hbaoBorderTile(b.params, depth, normal, out, tile); });
    b.depth = out;
    return b;
}

} // namespace obscura::cpu
