// Body of blurTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/blur.glsl on a row of OBSCURA_LANES pixels at a time.
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct BlurCpuKernel {
    KernelParams P;
    LanePlane depth, normal, signal;
    int channels = 1;

    lfloat gatherDepth(lint x, lint y, lbool use) const { return depth.gather1(x, y, use); }
    lvec3 gatherNormal(lint x, lint y, lbool use) const { return normal.gather3(x, y, use); }
    lvec4 gatherSignal(lint x, lint y, lbool use) const {
        const lfloat none = lfloat(0.0f);
        return lvec4(signal.gather1(x, y, use), channels > 1 ? signal.gather1(x, y, use, 1) : none,
                     channels > 2 ? signal.gather1(x, y, use, 2) : none, channels > 3 ? signal.gather1(x, y, use, 3) : none);
    }

#include "kernels/common.glsl"
#include "kernels/blur.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

void blurTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane src, MutablePlane dst,
              glm::ivec2 axis, int radius, const Box2i& tile) {
    glsl::BlurCpuKernel k;
    k.P = p;
    // The lanes are a row of pixels, and each neighbour a row too.
    k.depth = glsl::LanePlane(depth, true);
    k.normal = glsl::LanePlane(normal, true);
    k.signal = glsl::LanePlane(src, true);
    k.channels = src.channels;
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += OBSCURA_LANES) {
            const glsl::lvec4 v = k.blurLanes(lane + x, y, axis, radius);
            const int count = tile.x1 - x < OBSCURA_LANES ? tile.x1 - x : OBSCURA_LANES;
            for (int i = 0; i < count; ++i) {
                float* o = dst.at(x + i, y);
                for (int c = 0; c < dst.channels; ++c) o[c] = glsl::laneValue(v[c], i);
            }
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
