// Body of blurTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/blur.glsl on a row of OBSCURA_LANES pixels at a time.
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct BlurCpuKernel {
    KernelParams P;
    LanePlane depth, normal, signal, second;
    int channels = 1, secondChannels = 0; // the signal's channels, then the second plane's after them

    lfloat gatherDepth(lint x, lint y, lbool use) const { return depth.gather1(x, y, use); }
    lvec3 gatherNormal(lint x, lint y, lbool use) const { return normal.gather3(x, y, use); }
    lfloat gatherChannel(lint x, lint y, lbool use, int c) const {
        if (c < channels) return signal.gather1(x, y, use, c);
        if (c < channels + secondChannels) return second.gather1(x, y, use, c - channels);
        return lfloat(0.0f);
    }
    lvec4 gatherSignal(lint x, lint y, lbool use) const {
        if (channels == 3) { // GI or DO (AO beside it): one read of the three channels' row
            const lvec3 rgb = signal.gather3(x, y, use);
            return lvec4(rgb.x, rgb.y, rgb.z, gatherChannel(x, y, use, 3));
        }
        return lvec4(gatherChannel(x, y, use, 0), gatherChannel(x, y, use, 1), gatherChannel(x, y, use, 2),
                     gatherChannel(x, y, use, 3));
    }

#include "kernels/common.glsl"
#include "kernels/blur.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

// Channels first.. of v into `plane`'s row y from x: whole rows of 1 or 3 channels as vectors.
void store(const MutablePlane& plane, int x, int y, int count, const glsl::lvec4& v, int first) {
    float* o = plane.at(x, y);
    if (plane.channels == 1) {
        glsl::storeRow(o, plane.xStride, count, v[first]);
    } else if (plane.channels == 3) {
        glsl::storeRow(o, plane.xStride, count, v[first], v[first + 1], v[first + 2]);
    } else {
        for (int i = 0; i < count; ++i)
            for (int c = 0; c < plane.channels; ++c) o[i * plane.xStride + c] = glsl::laneValue(v[first + c], i);
    }
}

void blurTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, const BlurSource& src,
              const BlurTarget& dst, glm::ivec2 axis, int radius, const Box2i& tile) {
    glsl::BlurCpuKernel k;
    k.P = p;
    // The lanes are a row of pixels, and each neighbour a row too.
    k.depth = glsl::LanePlane(depth, true);
    k.normal = glsl::LanePlane(normal, true);
    k.signal = glsl::LanePlane(src.first, true);
    k.channels = src.first.channels;
    if (src.second.valid()) {
        k.second = glsl::LanePlane(src.second, true);
        k.secondChannels = src.second.channels;
    }
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += OBSCURA_LANES) {
            const glsl::lvec4 v = k.blurLanes(lane + x, y, axis, radius);
            const int count = tile.x1 - x < OBSCURA_LANES ? tile.x1 - x : OBSCURA_LANES;
            store(dst.first, x, y, count, v, 0);
            if (dst.second.valid()) store(dst.second, x, y, count, v, k.channels);
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
