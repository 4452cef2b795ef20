// CPU backend: kernels/ compiled as C++, run in tiles over all cores.
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"

#include <string>
#include <vector>

namespace obscura::cpu {

using glsl::KernelParams;

// Name of the instruction set the kernel runs with here ("x86-64-v4", ...), for reports.
const char* hbaoIsa();

// AO for every texel of `ao` (same size as depth/normal buffers, p.width x p.height).
void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads);
// The same with a named instruction set from cpuIsas() (cpu/isa.h), for tests and benchmarks.
void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
             const std::string& isa);

} // namespace obscura::cpu
