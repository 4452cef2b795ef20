// Bodies of the lane kernels' tile entry points (hbaoTile, ssaoTile) for one instruction set: define OBSCURA_ISA (the namespace of the
// entry point) and OBSCURA_LANES (pixels per register: 16 AVX-512, 8 AVX2, 4 SSE2, or 1
// for the pixel-at-a-time reference), then include this once, at file scope.
//
// The kernel text is the one the GPU compiles (kernels/hbao.glsl, kernels/ssao.glsl, written
// on lane types).
// The CPU side chooses how the lane types and the parameter block are seen: lanes are
// SIMD registers of a row of pixels, and the switches (weighting, falloff, projection,
// depth kind) are compile-time constants in specialised instantiations, so the untaken
// paths leave the inner loop instead of being tested per sample.

#include "cpu/lane_kernel.h"

#include <cstdlib>

namespace obscura::glsl {
namespace {

// A parameter block whose switches are fixed at compile time: the static members
// hide KernelParams' run-time ones, so `P.cosineWeighting` in the kernel is a constant.
template <int Cosine, int Linear, int Bitmask>
struct ParamsPerspPlanar : KernelParams {
    static constexpr int cosineWeighting = Cosine;
    static constexpr int linearFalloff = Linear;
    static constexpr int hbaoBitmask = Bitmask;
    static constexpr int orthographic = 0;
    static constexpr int radialDepth = 0;
};
template <int Cosine, int Linear, int Bitmask>
struct ParamsAnyCamera : KernelParams {
    static constexpr int cosineWeighting = Cosine;
    static constexpr int linearFalloff = Linear;
    static constexpr int hbaoBitmask = Bitmask;
};

template <class Params>
struct LaneCpuKernel {
    Params P;
    const float* depthData;
    const float* normalData;
    int depthXStride, depthYStride, normalXStride, normalYStride;
    const float* depthAtDisplayOrigin; // depthData - the offset of display pixel (0, 0)
    bool displayOffsetsExactInFloat;

    // Masked-off lanes read nothing and get 0: not a surface.
    lfloat gatherDepth(lint x, lint y, lbool use) const {
        return gather(depthData, y * depthYStride + x * depthXStride, use);
    }
    // At the texel whose corner, in display coordinates, is `corner` (whole numbers). Where
    // every offset is below 2^24 it is exact in float arithmetic, and the buffer origin is
    // folded into the base pointer: one multiply-add and one conversion per sample.
    lfloat gatherDepthAtDisplay(lvec2 corner, lbool use) const {
        if (displayOffsetsExactInFloat)
            return gather(depthAtDisplayOrigin, lint(corner.y * float(depthYStride) + corner.x * float(depthXStride)), use);
        return gatherDepth(lint(corner.x) - P.originX, lint(corner.y) - P.originY, use);
    }
    // Deep input (kernels/hbao.glsl): channel c of the (front, back) layer pairs at a display corner.
    const float* deepData = nullptr;
    int deepXStride = 0, deepYStride = 0;
    lfloat gatherDeepAtDisplay(lvec2 corner, int c, lbool use) const {
        return gather(deepData + c, (lint(corner.y) - P.originY) * deepYStride + (lint(corner.x) - P.originX) * deepXStride,
                      use);
    }
    lvec3 gatherNormal(lint x, lint y, lbool use) const {
        const lint i = y * normalYStride + x * normalXStride;
        return lvec3(gather(normalData, i, use), gather(normalData + 1, i, use), gather(normalData + 2, i, use));
    }
    // HBAO's edge texels, tabled once per frame (cpu/lane_cpu.h, hbaoEdgeTexels: top row, bottom
    // row, left column, right column, 4 floats each), so the continued border's reads stay in the
    // caches instead of striding down the planes, and a texel's depth and normal are one record.
    // `edgeCorner` is on the buffer's edge; its offsets are whole numbers below 2^24, exact in float.
    const float* edgeData = nullptr;
    lint edgeRecord(lvec2 edgeCorner) const {
        const lfloat x = edgeCorner.x - float(P.originX);
        const lfloat y = edgeCorner.y - float(P.originY);
        const float w = float(P.width), h = float(P.height);
        const lfloat column = select(x < 0.5f, 2.0f * w + y, 2.0f * w + h + y);
        return lint(select(y < 0.5f, x, select(y > h - 1.5f, w + x, column))) * 4;
    }
    lfloat gatherEdgeDepth(lvec2 edgeCorner, lbool use) const { return gather(edgeData, edgeRecord(edgeCorner), use); }
    lvec4 gatherEdgeTexel(lvec2 edgeCorner, lbool use) const { return gatherRecord4(edgeData, edgeRecord(edgeCorner), use); }

#include "kernels/common.glsl"
#include "kernels/hbao.glsl"
#include "kernels/ssao.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

using glsl::KernelParams;
constexpr int kLanesHere = OBSCURA_LANES;

enum class Entry { Hbao, Ssao };

template <Entry E, class Params>
void runTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
             MutablePlane ao, const Box2i& tile) {
    glsl::LaneCpuKernel<Params> k;
    static_cast<KernelParams&>(k.P) = p;
    k.edgeData = edges.data;
    k.deepData = deep.data;
    k.deepXStride = (int)deep.xStride;
    k.deepYStride = (int)deep.yStride;
    k.depthData = depth.data;
    k.depthXStride = (int)depth.xStride;
    k.depthYStride = (int)depth.yStride;
    // Display coordinates of the depth texels reach |origin| + size; the offsets stay below 2^24.
    const long long reachX = std::llabs(p.originX) + p.width;
    const long long reachY = std::llabs(p.originY) + p.height;
    k.displayOffsetsExactInFloat = reachY * std::llabs(depth.yStride) + reachX * std::llabs(depth.xStride) < (1ll << 24);
    // Only formed (and only dereferenced at in-buffer texels) when the offsets fit.
    k.depthAtDisplayOrigin =
        k.displayOffsetsExactInFloat ? depth.data - (p.originY * depth.yStride + p.originX * depth.xStride) : depth.data;
    k.normalData = normal.data;
    k.normalXStride = (int)normal.xStride;
    k.normalYStride = (int)normal.yStride;
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += kLanesHere) {
            // Lanes past the tile compute a neighbour (or, past the buffer, nothing) and are not stored.
            const auto v = E == Entry::Hbao ? k.hbaoLanes(lane + x, y) : k.ssaoLanes(lane + x, y);
            const int count = tile.x1 - x < kLanesHere ? tile.x1 - x : kLanesHere;
            for (int i = 0; i < count; ++i) {
#if OBSCURA_LANES == 1
                *ao.at(x + i, y) = v;
#else
                *ao.at(x + i, y) = v[i];
#endif
            }
        }
}

template <Entry E, int Cosine, int Linear, int Bitmask = 0>
void runTileFor(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
                MutablePlane ao, const Box2i& tile) {
    if (p.orthographic == 0 && p.radialDepth == 0)
        runTile<E, glsl::ParamsPerspPlanar<Cosine, Linear, Bitmask>>(p, depth, normal, deep, edges, ao, tile);
    else
        runTile<E, glsl::ParamsAnyCamera<Cosine, Linear, Bitmask>>(p, depth, normal, deep, edges, ao, tile);
}

// The weighting and falloff switches as template arguments, for one bitmask mode.
template <Entry E, int Bitmask>
void runSwitches(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
                 MutablePlane ao, const Box2i& tile) {
    const bool linear = Bitmask != 2 && p.linearFalloff != 0; // deep input takes no falloff (operator.cpp)
    if (p.cosineWeighting != 0) {
        if constexpr (Bitmask != 2) {
            if (linear) return runTileFor<E, 1, 1, Bitmask>(p, depth, normal, deep, edges, ao, tile);
        }
        runTileFor<E, 1, 0, Bitmask>(p, depth, normal, deep, edges, ao, tile);
    } else {
        if constexpr (Bitmask != 2) {
            if (linear) return runTileFor<E, 0, 1, Bitmask>(p, depth, normal, deep, edges, ao, tile);
        }
        runTileFor<E, 0, 0, Bitmask>(p, depth, normal, deep, edges, ao, tile);
    }
}

// HBAO's bitmask mode as a template argument too (SSAO never takes it): the deep layers (2), so
// input without them runs no deep code, and the runs (3), whose bookkeeping a run-time test in
// the march slowed by a tenth. Linear falloff with deep layers keeps the horizon (bitmask 0), as
// the operator asks.
template <Entry E>
void runEntry(const KernelParams& p, int bitmask, ConstPlane depth, ConstPlane normal, ConstPlane deep,
              ConstPlane edges, MutablePlane ao, const Box2i& tile) {
    if constexpr (E == Entry::Hbao) {
        if (bitmask == 1) return runSwitches<E, 1>(p, depth, normal, deep, edges, ao, tile);
        if (bitmask == 3) return runSwitches<E, 3>(p, depth, normal, deep, edges, ao, tile);
        if (bitmask == 2 && p.linearFalloff == 0) return runSwitches<E, 2>(p, depth, normal, deep, edges, ao, tile);
    }
    runSwitches<E, 0>(p, depth, normal, deep, edges, ao, tile);
}

} // namespace

void hbaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane edges, MutablePlane ao,
              const Box2i& tile) {
    // No deep plane here: the bitmask without its deep layers.
    runEntry<Entry::Hbao>(p, p.hbaoBitmask == 2 ? 1 : p.hbaoBitmask, depth, normal, ConstPlane{}, edges, ao, tile);
}

void hbaoDeepTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
                  MutablePlane ao, const Box2i& tile) {
    runEntry<Entry::Hbao>(p, p.hbaoBitmask, depth, normal, deep, edges, ao, tile);
}

void ssaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    runEntry<Entry::Ssao>(p, 0, depth, normal, ConstPlane{}, ConstPlane{}, ao, tile);
}

} // namespace obscura::cpu::OBSCURA_ISA
