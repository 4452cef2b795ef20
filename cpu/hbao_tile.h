// The HBAO kernel (kernels/hbao.glsl) instantiated for the CPU, one tile at a time.
// Included by one translation unit per instruction set (hbao_cpu.cpp: baseline x86-64;
// hbao_cpu_v3.cpp: x86-64-v3, AVX2 + FMA), each inside its own namespace, and
// selected at run time by runHbao(). Everything here except hbaoTile has internal
// linkage, so no out-of-line copy compiled for one ISA can be picked by the linker
// for the other.
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"

namespace obscura::cpu {

// Runs hbaoPixel over every texel of the tile; the entry point each ISA provides.
using HbaoTileFn = void (*)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                            const Box2i& tile);

namespace baseline {
void hbaoTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile);
}
namespace x86_64_v3 {
void hbaoTile(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const Box2i& tile);
}

} // namespace obscura::cpu
