// Body of hbaoTile for one instruction set: define OBSCURA_ISA (the namespace of the
// entry point) and include this once, at file scope (see hbao_cpu.cpp, hbao_cpu_v3.cpp).
//
// The kernel text is the one the GPU compiles. The CPU side only chooses how the
// parameter block is seen: the switches (weighting, falloff, projection, depth kind)
// become compile-time constants in specialised instantiations, so the compiler drops
// the untaken paths from the inner loop instead of testing them per sample.

#include "cpu/hbao_tile.h"
#include "cpu/simd_vec4.h"

namespace obscura::glsl {
namespace {

// A parameter block whose switches are fixed at compile time: the static members
// hide KernelParams' run-time ones, so `P.cosineWeighting` in the kernel is a constant.
template <int Cosine, int Linear>
struct ParamsPerspPlanar : KernelParams {
    static constexpr int cosineWeighting = Cosine;
    static constexpr int linearFalloff = Linear;
    static constexpr int orthographic = 0;
    static constexpr int radialDepth = 0;
};
template <int Cosine, int Linear>
struct ParamsAnyCamera : KernelParams {
    static constexpr int cosineWeighting = Cosine;
    static constexpr int linearFalloff = Linear;
};

template <class Params>
struct HbaoCpuKernel {
    // The kernel's vec4 arithmetic (four steps of a slice at once) on SIMD registers.
    using vec4 = cpu::simd::vec4;
    using ivec4 = cpu::simd::ivec4;
    using bvec4 = cpu::simd::bvec4;

    Params P;
    const float* depthData;
    const float* normalData;
    std::ptrdiff_t depthXStride, depthYStride, normalXStride, normalYStride;

    float loadDepth(ivec2 t) const { return depthData[t.y * depthYStride + t.x * depthXStride]; }
    vec3 loadNormal(ivec2 t) const {
        const float* n = normalData + t.y * normalYStride + t.x * normalXStride;
        return vec3(n[0], n[1], n[2]);
    }

#include "kernels/common.glsl"
#include "kernels/hbao.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

using glsl::KernelParams;

template <class Params>
void runTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    glsl::HbaoCpuKernel<Params> k;
    static_cast<KernelParams&>(k.P) = p;
    k.depthData = depth.data;
    k.depthXStride = depth.xStride;
    k.depthYStride = depth.yStride;
    k.normalData = normal.data;
    k.normalXStride = normal.xStride;
    k.normalYStride = normal.yStride;
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) *ao.at(x, y) = k.hbaoPixel(glsl::ivec2(x, y));
}

template <int Cosine, int Linear>
void runTileFor(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    if (p.orthographic == 0 && p.radialDepth == 0)
        runTile<glsl::ParamsPerspPlanar<Cosine, Linear>>(p, depth, normal, ao, tile);
    else
        runTile<glsl::ParamsAnyCamera<Cosine, Linear>>(p, depth, normal, ao, tile);
}

} // namespace

void hbaoTile(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile) {
    if (p.cosineWeighting != 0) {
        if (p.linearFalloff != 0) runTileFor<1, 1>(p, depth, normal, ao, tile);
        else runTileFor<1, 0>(p, depth, normal, ao, tile);
    } else {
        if (p.linearFalloff != 0) runTileFor<0, 1>(p, depth, normal, ao, tile);
        else runTileFor<0, 0>(p, depth, normal, ao, tile);
    }
}

} // namespace obscura::cpu::OBSCURA_ISA
