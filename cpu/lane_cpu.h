// CPU backend of the lane kernels (kernels/hbao.glsl, kernels/ssao.glsl): compiled as C++
// once per instruction set, the widest this CPU runs chosen at run time, tiles over all cores.
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"
#include "cpu/lane_tiles.h"

#include <string>
#include <vector>

namespace obscura::cpu {

using glsl::KernelParams;

enum class LaneKernel { Hbao, Ssao };

// Name of the instruction set the kernels run with here ("x86-64-v4", ...), for reports.
const char* laneIsa();
// Every instruction set this CPU can run the kernels with, from "scalar" (a pixel at a time,
// the reference) to the widest; the last is the one used unless OBSCURA_CPU_ISA says otherwise.
std::vector<std::string> laneIsas();

// The tile function of a kernel for a named instruction set from laneIsas()
// (std::invalid_argument for another): for tests and benchmarks.
LaneTileFn laneTileFor(LaneKernel kernel, const std::string& isa);

// The kernel for every texel of `ao` (same size as depth/normal buffers, p.width x p.height);
// `isa` empty: the chosen one.
void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa = "");

inline void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
                    const std::string& isa = "") {
    runLaneKernel(LaneKernel::Hbao, p, depth, normal, ao, threads, isa);
}
inline void runSsao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
                    const std::string& isa = "") {
    runLaneKernel(LaneKernel::Ssao, p, depth, normal, ao, threads, isa);
}

} // namespace obscura::cpu
