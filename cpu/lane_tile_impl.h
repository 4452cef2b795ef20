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
// Gi: HBAO's indirect light too (kernels/hbao_gi.glsl), a specialisation of its own so that AO
// alone runs none of it.
template <int Cosine, int Linear, int Model, int Runs, int Gi>
struct ParamsAnyCamera : KernelParams {
    static constexpr int cosineWeighting = Cosine;
    static constexpr int linearFalloff = Linear;
    static constexpr int hbaoModel = Model;
    static constexpr int hbaoRuns = Runs;
    static constexpr int hbaoGi = Gi;
};
// The common camera: perspective, planar depth.
template <int Cosine, int Linear, int Model, int Runs, int Gi>
struct ParamsPerspPlanar : ParamsAnyCamera<Cosine, Linear, Model, Runs, Gi> {
    static constexpr int orthographic = 0;
    static constexpr int radialDepth = 0;
};

template <class Params>
struct LaneCpuKernel {
    Params P;
    const float* depthData;
    const float* normalData;
    int depthXStride, depthYStride, normalXStride, normalYStride;
    const float* depthAtDisplayOrigin; // depthData - the offset of display pixel (0, 0)
    bool displayOffsetsExactInFloat;

    // The index in a plane of these strides of the buffer texel whose display corner is `corner`:
    // HBAO's reads at display corners (the depth where the float shortcut below does not hold, the
    // deep layers, the bounce source's and the normals' words).
    lint bufferTexelIndex(lvec2 corner, int xStride, int yStride) const {
        return (lint(corner.y) - P.originY) * yStride + (lint(corner.x) - P.originX) * xStride;
    }

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
        return gather(depthData, bufferTexelIndex(corner, depthXStride, depthYStride), use);
    }
    // Deep input (kernels/hbao.glsl): channel c of the (front, back) layer pairs at a display corner.
    const float* deepData = nullptr;
    int deepXStride = 0, deepYStride = 0;
    lfloat gatherDeepAtDisplay(lvec2 corner, int c, lbool use) const {
        return gather(deepData + c, bufferTexelIndex(corner, deepXStride, deepYStride), use);
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
    // HBAO's indirect light: the bounce source (one packed word per texel and layer, kernels/hbao_gi.glsl)
    // at a display corner; 0 (black) where not used.
    const float* radianceData = nullptr;
    int radianceXStride = 0, radianceYStride = 0;
    luint gatherRadianceBitsAtDisplay(lvec2 corner, int layer, lbool use) const {
        return floatBitsToUint(gather(radianceData + layer, bufferTexelIndex(corner, radianceXStride, radianceYStride), use));
    }
    // ... and the visible surface's normal (one packed word per texel, kernels/normal_word.glsl).
    const float* facingData = nullptr;
    int facingXStride = 0, facingYStride = 0;
    luint gatherNormalWordAtDisplay(lvec2 corner, lbool use) const {
        return floatBitsToUint(gather(facingData, bufferTexelIndex(corner, facingXStride, facingYStride), use));
    }
    lfloat gatherEdgeDepth(lvec2 edgeCorner, lbool use) const { return gather(edgeData, edgeRecord(edgeCorner), use); }
    lvec4 gatherEdgeTexel(lvec2 edgeCorner, lbool use) const { return gatherRecord4(edgeData, edgeRecord(edgeCorner), use); }

#include "kernels/common.glsl"
// The plan's switches as the kernel reads them: compile-time constants of Params here (defines on OpenGL).
#define HBAO_MODEL P.hbaoModel
#define HBAO_RUNS P.hbaoRuns
#define HBAO_GI P.hbaoGi
#include "kernels/hbao.glsl"
#undef HBAO_MODEL
#undef HBAO_RUNS
#undef HBAO_GI
#include "kernels/ssao.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

using glsl::KernelParams;
constexpr int kLanesHere = OBSCURA_LANES;

enum class Entry { Hbao, Ssao };

// The planes a tile reads and writes; those a kernel does not use are invalid.
struct TilePlanes {
    ConstPlane depth, normal, deep, edges, radiance, facing;
    MutablePlane ao, gi;
};

// Lane i of v (a pixel's value).
template <class V>
float laneOf(const V& v, int i) {
#if OBSCURA_LANES == 1
    (void)i;
    return v;
#else
    return v[i];
#endif
}

template <Entry E, class Params>
void runTile(const KernelParams& p, const TilePlanes& t, const Box2i& tile) {
    glsl::LaneCpuKernel<Params> k;
    static_cast<KernelParams&>(k.P) = p;
    k.edgeData = t.edges.data;
    k.deepData = t.deep.data;
    k.deepXStride = (int)t.deep.xStride;
    k.deepYStride = (int)t.deep.yStride;
    k.radianceData = t.radiance.data;
    k.radianceXStride = (int)t.radiance.xStride;
    k.radianceYStride = (int)t.radiance.yStride;
    k.facingData = t.facing.data;
    k.facingXStride = (int)t.facing.xStride;
    k.facingYStride = (int)t.facing.yStride;
    const ConstPlane& depth = t.depth;
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
    k.normalData = t.normal.data;
    k.normalXStride = (int)t.normal.xStride;
    k.normalYStride = (int)t.normal.yStride;
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += kLanesHere) {
            // Lanes past the tile compute a neighbour (or, past the buffer, nothing) and are not stored.
            const auto v = E == Entry::Hbao ? k.hbaoLanes(lane + x, y) : k.ssaoLanes(lane + x, y);
            const int count = tile.x1 - x < kLanesHere ? tile.x1 - x : kLanesHere;
            glsl::storeRow(t.ao.at(x, y), t.ao.xStride, count, v);
            if constexpr (Params::hbaoGi != 0)
                glsl::storeRow(t.gi.at(x, y), t.gi.xStride, count, k.hbaoIrradiance.x, k.hbaoIrradiance.y,
                               k.hbaoIrradiance.z);
        }
}

template <Entry E, int Cosine, int Linear, int Model, int Runs, int Gi>
void runTileFor(const KernelParams& p, const TilePlanes& t, const Box2i& tile) {
    if (p.orthographic == 0 && p.radialDepth == 0)
        runTile<E, glsl::ParamsPerspPlanar<Cosine, Linear, Model, Runs, Gi>>(p, t, tile);
    else
        runTile<E, glsl::ParamsAnyCamera<Cosine, Linear, Model, Runs, Gi>>(p, t, tile);
}

// One variant (HBAO's model, runs and falloff as core/hbao_plan.cpp plans them) if p asks for it,
// with the weighting as a template argument too.
template <Entry E, int Model, int Runs, int Linear, int Gi = 0>
bool runIf(const KernelParams& p, const TilePlanes& t, const Box2i& tile) {
    if (p.hbaoModel != Model || p.hbaoRuns != Runs || p.linearFalloff != Linear) return false;
    if (p.cosineWeighting != 0) runTileFor<E, 1, Linear, Model, Runs, Gi>(p, t, tile);
    else runTileFor<E, 0, Linear, Model, Runs, Gi>(p, t, tile);
    return true;
}

// HBAO's plans, each its own instantiation, so the untaken models leave the march: input without
// deep layers runs no deep code, and the runs' bookkeeping (a run-time test in the march slowed
// it by a tenth) only where they are planned.
void runHbaoPlan(const KernelParams& p, const TilePlanes& t, const Box2i& tile) {
    using glsl::HBAO_HORIZON, glsl::HBAO_FIXED_THICKNESS, glsl::HBAO_MEASURED_THICKNESS, glsl::HBAO_DEEP;
    constexpr Entry H = Entry::Hbao;
    const bool planned = runIf<H, HBAO_HORIZON, 0, 0>(p, t, tile) || runIf<H, HBAO_HORIZON, 0, 1>(p, t, tile) ||
                         runIf<H, HBAO_FIXED_THICKNESS, 0, 0>(p, t, tile) ||
                         runIf<H, HBAO_FIXED_THICKNESS, 1, 1>(p, t, tile) ||
                         runIf<H, HBAO_MEASURED_THICKNESS, 1, 0>(p, t, tile) ||
                         runIf<H, HBAO_MEASURED_THICKNESS, 1, 1>(p, t, tile) || runIf<H, HBAO_DEEP, 0, 0>(p, t, tile);
    if (!planned) std::abort(); // a parameter block core/hbao_plan.cpp did not fill
}

// The same plans with the indirect light.
void runHbaoGiPlan(const KernelParams& p, const TilePlanes& t, const Box2i& tile) {
    using glsl::HBAO_HORIZON, glsl::HBAO_FIXED_THICKNESS, glsl::HBAO_MEASURED_THICKNESS, glsl::HBAO_DEEP;
    constexpr Entry H = Entry::Hbao;
    const bool planned = runIf<H, HBAO_HORIZON, 0, 0, 1>(p, t, tile) || runIf<H, HBAO_HORIZON, 0, 1, 1>(p, t, tile) ||
                         runIf<H, HBAO_FIXED_THICKNESS, 0, 0, 1>(p, t, tile) ||
                         runIf<H, HBAO_FIXED_THICKNESS, 1, 1, 1>(p, t, tile) ||
                         runIf<H, HBAO_MEASURED_THICKNESS, 1, 0, 1>(p, t, tile) ||
                         runIf<H, HBAO_MEASURED_THICKNESS, 1, 1, 1>(p, t, tile) ||
                         runIf<H, HBAO_DEEP, 0, 0, 1>(p, t, tile);
    if (!planned) std::abort(); // a parameter block core/hbao_plan.cpp did not fill
}

} // namespace

void hbaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane edges, MutablePlane ao,
              const Box2i& tile) {
    if (p.hbaoModel == glsl::HBAO_DEEP) std::abort(); // deep layers come through hbaoDeepTile
    runHbaoPlan(p, TilePlanes{depth, normal, {}, edges, {}, {}, ao, {}}, tile);
}

void hbaoDeepTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane edges,
                  MutablePlane ao, const Box2i& tile) {
    runHbaoPlan(p, TilePlanes{depth, normal, deep, edges, {}, {}, ao, {}}, tile);
}

void hbaoGiTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                ConstPlane facing, ConstPlane edges, MutablePlane ao, MutablePlane gi, const Box2i& tile) {
    runHbaoGiPlan(p, TilePlanes{depth, normal, deep, edges, radiance, facing, ao, gi}, tile);
}

void ssaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    // SSAO reads the weighting and the falloff, no HBAO switch (HBAO's horizon instantiations serve).
    constexpr Entry S = Entry::Ssao;
    constexpr int H = glsl::HBAO_HORIZON;
    const TilePlanes t{depth, normal, {}, {}, {}, {}, ao, {}};
    if (p.cosineWeighting != 0) {
        if (p.linearFalloff != 0) runTileFor<S, 1, 1, H, 0, 0>(p, t, tile);
        else runTileFor<S, 1, 0, H, 0, 0>(p, t, tile);
    } else {
        if (p.linearFalloff != 0) runTileFor<S, 0, 1, H, 0, 0>(p, t, tile);
        else runTileFor<S, 0, 0, H, 0, 0>(p, t, tile);
    }
}

} // namespace obscura::cpu::OBSCURA_ISA
