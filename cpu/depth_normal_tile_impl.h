// Body of depthNormalTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/depth_normal.glsl, the text the GPU compiles, on a row of OBSCURA_LANES pixels at a time.
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct DepthNormalCpuKernel {
    KernelParams P;
    LanePlane depth;

    lfloat gatherDepth(lint x, lint y, lbool use) const { return depth.gather1(x, y, use); }

#include "kernels/common.glsl"
#include "kernels/depth_normal.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

void depthNormalTile(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, const Box2i& tile) {
    glsl::DepthNormalCpuKernel k;
    k.P = p;
    k.depth = glsl::LanePlane(depth);
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += OBSCURA_LANES) {
            const glsl::lvec3 n = k.depthNormalLanes(lane + x, y);
            const int count = tile.x1 - x < OBSCURA_LANES ? tile.x1 - x : OBSCURA_LANES;
            for (int i = 0; i < count; ++i) {
                float* o = normal.at(x + i, y);
                o[0] = glsl::laneValue(n.x, i);
                o[1] = glsl::laneValue(n.y, i);
                o[2] = glsl::laneValue(n.z, i);
            }
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
