// Bodies of the disc AO entry points (discsBaseTile, discsTile) for one instruction set:
// included by cpu/isa_kernels.cpp after OBSCURA_ISA and OBSCURA_LANES are defined. The kernel
// text is kernels/discs.glsl, the one the GPU compiles; the pyramid it reads is
// cpu/discs_cpu.cpp's (a plane per channel, P.discStride apart, levels at P.discLevelOffset).

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
    // Channel c of pyramid texel `index`; masked-off lanes read nothing and get 0. A row of
    // lanes visits neighbouring nodes (from level 3 up usually one node): then one broadcast,
    // or one load of 16 neighbours of the channel's plane and a permute, not a gather. The
    // kernel reads a node's channels one after another with the same index: its span is kept.
    lfloat gatherDisc(lint index, int c, lbool use) const {
        const float* plane = pyramid + (size_t)c * (size_t)P.discStride;
#if OBSCURA_LANES == 16
        const __m512i idx = (__m512i)index.v;
        if (!(use.k == spanUse && _mm512_mask_cmpneq_epi32_mask(use.k, idx, spanIndex) == 0)) {
            spanUse = use.k;
            spanIndex = idx;
            spanLo = use.k ? reduceMin(_mm512_mask_blend_epi32(use.k, _mm512_set1_epi32(INT_MAX), idx)) : 0;
            // The largest index: minus the smallest of the negated ones.
            const int hi = use.k ? -reduceMin(_mm512_mask_blend_epi32(use.k, _mm512_set1_epi32(INT_MAX),
                                                                      _mm512_sub_epi32(_mm512_setzero_si512(), idx)))
                                 : 0;
            spanWidth = hi - spanLo;
            spanRel = _mm512_sub_epi32(idx, _mm512_set1_epi32(spanLo));
        }
        if (spanWidth == 0) return (vfloat)_mm512_maskz_mov_ps(use.k, _mm512_set1_ps(plane[spanLo]));
        // Past the last plane the pyramid holds cpu::kDiscPad floats, so the load stays inside.
        if (spanWidth < 16) return (vfloat)_mm512_maskz_permutexvar_ps(use.k, spanRel, _mm512_loadu_ps(plane + spanLo));
#elif OBSCURA_LANES > 1
        if (sameNode(index, use)) return lfloat(plane[index[0]]);
#endif
        return gather(plane, index, use);
    }
#if OBSCURA_LANES > 1 && OBSCURA_LANES != 16
    // Every lane reads the same node (AVX2: one broadcast instead of a gather).
    static bool sameNode(lint index, lbool use) {
        bool same = true;
        for (int i = 1; i < cpu::lanes::kLanes; ++i) same = same && index[i] == index[0] && use.m[i] != 0;
        return same && use.m[0] != 0;
    }
#endif
#if OBSCURA_LANES == 16
    // The smallest of 16 ints, halving with vector shuffles (GCC 12's reduce and extract
    // intrinsics warn inside their own header under -Wall).
    static int reduceMin(__m512i v) {
        typedef int v16 __attribute__((vector_size(64)));
        typedef int v8 __attribute__((vector_size(32)));
        typedef int v4 __attribute__((vector_size(16)));
        const v16 w = (v16)v;
        const v8 a = __builtin_shufflevector(w, w, 0, 1, 2, 3, 4, 5, 6, 7);
        const v8 b = __builtin_shufflevector(w, w, 8, 9, 10, 11, 12, 13, 14, 15);
        const v8 m = a < b ? a : b;
        const v4 c = __builtin_shufflevector(m, m, 0, 1, 2, 3);
        const v4 d = __builtin_shufflevector(m, m, 4, 5, 6, 7);
        const v4 n = c < d ? c : d;
        return std::min(std::min(n[0], n[1]), std::min(n[2], n[3]));
    }
    mutable __mmask16 spanUse = 0;
    mutable __m512i spanIndex = _mm512_setzero_si512();
    mutable __m512i spanRel = _mm512_setzero_si512();
    mutable int spanLo = 0, spanWidth = -1;
#endif

#include "kernels/common.glsl"
#include "kernels/depth_normal.glsl"
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
                float* t = base + (size_t)y * p.width + x + i;
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
                for (int c = 0; c < cpu::kDiscChannels; ++c) t[(size_t)c * (size_t)p.discStride] = v[c];
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
