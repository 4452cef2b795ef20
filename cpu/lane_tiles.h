// The lane kernels (kernels/hbao.glsl, kernels/ssao.glsl) instantiated for the CPU, one tile
// at a time. Included by one translation unit per instruction set, each inside its own
// namespace (cpu/lane_tile_impl.h), and selected at run time (cpu/lane_cpu.cpp). Everything
// there except the entry points has internal linkage, so no out-of-line copy compiled for
// one ISA can be picked by the linker for another.
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"

namespace obscura::cpu {

// Tiles 64 wide (four AVX-512 registers of pixels) and 16 high: cache-friendly, and small
// enough that sky and non-sky work balance across threads.
constexpr int kLaneTileWidth = 64, kLaneTileHeight = 16;

// Runs a kernel over every texel of the tile; the entry points each ISA provides.
using LaneTileFn = void (*)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                            const Box2i& tile);

#define OBSCURA_DECLARE_LANE_TILES(isa)                                                                          \
    namespace isa {                                                                                               \
    void hbaoTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile); \
    void ssaoTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile); \
    }
OBSCURA_DECLARE_LANE_TILES(scalar)    // one pixel at a time: the reference the lane builds are tested against
OBSCURA_DECLARE_LANE_TILES(baseline)  // x86-64 (SSE2), 4 pixels per register
OBSCURA_DECLARE_LANE_TILES(x86_64_v3) // AVX2 + FMA, 8 pixels
OBSCURA_DECLARE_LANE_TILES(x86_64_v4) // AVX-512, 16 pixels
#undef OBSCURA_DECLARE_LANE_TILES

} // namespace obscura::cpu
