// CPU backend: kernels/ compiled as C++, run in tiles over all cores.
#pragma once
#include "core/image.h"
#include "cpu/hbao_tile.h"
#include "cpu/kernel_params.h"

#include <string>
#include <vector>

namespace obscura::cpu {

using glsl::KernelParams;

// Name of the instruction set the kernel runs with here ("x86-64-v4", ...), for reports.
const char* hbaoIsa();
// Every instruction set this CPU can run the kernel with, from "scalar" (a pixel at a time,
// the reference) to the widest; the last is the one runHbao uses.
std::vector<std::string> hbaoIsas();

// AO for every texel of `ao` (same size as depth/normal buffers, p.width x p.height).
void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads);
// The tile function of a named instruction set from hbaoIsas() (std::invalid_argument for
// another), and runHbao with it: for tests and benchmarks.
HbaoTileFn hbaoTileFor(const std::string& isa);
void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
             const std::string& isa);

} // namespace obscura::cpu
