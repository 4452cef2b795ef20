// Bodies of the disc AO entry points (discsBaseTile, discsTile) for one instruction set:
// included by cpu/isa_kernels.cpp after OBSCURA_ISA and OBSCURA_LANES are defined. The kernel
// text is kernels/discs.glsl, the one the GPU compiles; the pyramid it reads is
// cpu/discs_cpu.cpp's (texels of DISC_CHANNELS floats, levels at P.discLevelOffset).

#include "cpu/discs_cpu.h"
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct DiscsCpuKernel {
    KernelParams P;
    LanePlane depth, normal;
    const float* pyramid = nullptr;

    lfloat gatherDepth(lint x, lint y, lbool use) const { return depth.gather1(x, y, use); }
    lvec3 gatherNormal(lint x, lint y, lbool use) const { return normal.gather3(x, y, use); }
    // Channel c of pyramid texel `index`; masked-off lanes read nothing and get 0. From level 3
    // up a row of 16 lanes usually visits one node: then one broadcast load, not a gather.
    lfloat gatherDisc(lint index, int c, lbool use) const {
#if OBSCURA_LANES > 1
        if (sameNode(index, use)) return lfloat(pyramid[c + index[0] * cpu::kDiscChannels]);
#endif
        return gather(pyramid + c, index * cpu::kDiscChannels, use);
    }
#if OBSCURA_LANES > 1
    static bool sameNode(lint index, lbool use) {
        bool same = true;
        for (int i = 1; i < cpu::lanes::kLanes; ++i) same = same && index[i] == index[0];
#if OBSCURA_LANES == 16
        return same && use.k == 0xffff;
#else
        bool all = true;
        for (int i = 0; i < cpu::lanes::kLanes; ++i) all = all && use.m[i] != 0;
        return same && all;
#endif
    }
#endif

#include "kernels/common.glsl"
#include "kernels/discs.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

constexpr int kDiscLanes = OBSCURA_LANES;

// Lanes past the tile compute a neighbour (or nothing) and are not stored.
int lanesToStore(int x, int x1) { return x1 - x < kDiscLanes ? x1 - x : kDiscLanes; }

float discsBaseTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, float* base, const Box2i& tile) {
    glsl::DiscsCpuKernel k;
    k.P = p;
    k.depth = glsl::LanePlane(depth);
    k.normal = glsl::LanePlane(normal);
    const auto lane = glsl::laneIndex();
    float reach = 0.0f;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += kDiscLanes) {
            glsl::lvec3 pos, n, wallPos, wallN, stripPos, stripN;
            glsl::lfloat area, wallArea, wallLen, facing, stripArea;
            k.discBase(lane + x, y, pos, n, area, wallPos, wallN, wallArea, wallLen, facing, stripPos, stripN, stripArea);
            const glsl::lfloat laneReach = k.discReachPixels(pos);
            for (int i = 0; i < lanesToStore(x, tile.x1); ++i) {
                if (glsl::laneValue(area, i) > 0.0f) reach = std::max(reach, glsl::laneValue(laneReach, i));
                float* t = base + ((size_t)y * p.width + x + i) * cpu::kDiscChannels;
                const float v[cpu::kDiscChannels] = {
                    glsl::laneValue(pos.x, i),     glsl::laneValue(pos.y, i),     glsl::laneValue(pos.z, i),
                    glsl::laneValue(area, i),      glsl::laneValue(n.x, i),       glsl::laneValue(n.y, i),
                    glsl::laneValue(n.z, i),       1.0f,
                    glsl::laneValue(wallPos.x, i), glsl::laneValue(wallPos.y, i), glsl::laneValue(wallPos.z, i),
                    glsl::laneValue(wallArea, i),  glsl::laneValue(wallN.x, i),   glsl::laneValue(wallN.y, i),
                    glsl::laneValue(wallN.z, i),   glsl::laneValue(wallLen, i),   glsl::laneValue(facing, i),
                    glsl::laneValue(stripPos.x, i), glsl::laneValue(stripPos.y, i), glsl::laneValue(stripPos.z, i),
                    glsl::laneValue(stripArea, i), glsl::laneValue(stripN.x, i),  glsl::laneValue(stripN.y, i),
                    glsl::laneValue(stripN.z, i)};
                for (int c = 0; c < cpu::kDiscChannels; ++c) t[c] = v[c];
            }
        }
    return reach;
}

void discsTile(const glsl::KernelParams& p, const float* pyramid, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    glsl::DiscsCpuKernel k;
    k.P = p;
    k.pyramid = pyramid;
    k.normal = glsl::LanePlane(normal);
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += kDiscLanes) {
            const auto v = k.discsLanes(lane + x, y);
            for (int i = 0; i < lanesToStore(x, tile.x1); ++i) *ao.at(x + i, y) = glsl::laneValue(v, i);
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
