// CPU backend of the lane kernels that read depth and normals only (kernels/hbao.glsl,
// kernels/ssao.glsl): the widest instruction set this CPU runs (cpu/isa.h), tiles over all cores.
#pragma once
#include "base/image.h"
#include "cpu/isa.h"
#include "base/kernel_params.h"

#include <string>
#include <vector>

namespace obscura::cpu {

using glsl::KernelParams;

enum class LaneKernel { Hbao, Ssao };

// HBAO's tile, as each instruction set provides it.
using HbaoTileFn = decltype(IsaKernels::hbaoTile);

// Name of the instruction set the kernels run with here ("x86-64-v4", ...), for reports.
const char* laneIsa();
// Every instruction set this CPU can run the kernels with, from "scalar" (a pixel at a time,
// the reference) to the widest; the last is the one used unless OBSCURA_CPU_ISA says otherwise.
std::vector<std::string> laneIsas();

// HBAO's tile function for a named instruction set from laneIsas() (std::invalid_argument for
// another): for tests and benchmarks.
HbaoTileFn hbaoTileFor(const std::string& isa);

// The texels on the buffer's edge, which HBAO's continued border (p.hbaoBorder) reads, as one
// row of records (depth, normal x, y, z): the top row (W), the bottom row (W), the left column
// (H), the right column (H). Tabled once per frame, they stay in the caches; read in place, the
// columns' texels are a row's stride apart in four planes (cpu/lane_tile_impl.h reads them).
Image hbaoEdgeTexels(ConstPlane depth, ConstPlane normal);

// The kernel for every texel of `ao` (same size as depth/normal buffers, p.width x p.height);
// `isa` empty: the chosen one.
void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa = "");

// HBAO with deep input: `deep` holds p.deepLayers (front, back) depth pairs per texel over the
// same buffer as depth, and p.hbaoModel is HBAO_DEEP (core/hbao_plan.cpp plans both).
void runHbaoDeep(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa = "");

// HBAO with its indirect light (kernels/hbao_gi.glsl): `radiance` the bounce source over the same
// buffer (albedo applied, one packed RGB word per texel: kernels/hbao_gi.glsl), `gi` the irradiance
// (3 channels). With deep input (`deep` valid, p.hbaoModel HBAO_DEEP) `radiance` holds
// p.deepLayers words per texel: the visible layer's source, then each hidden layer's colour.
// `facing` holds the visible surface's normal, one packed word per texel (kernels/normal_word.glsl).
void runHbaoGi(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
               ConstPlane facing, MutablePlane ao, MutablePlane gi, int threads, const std::string& isa = "");

inline void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
                    const std::string& isa = "") {
    runLaneKernel(LaneKernel::Hbao, p, depth, normal, ao, threads, isa);
}
inline void runSsao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
                    const std::string& isa = "") {
    runLaneKernel(LaneKernel::Ssao, p, depth, normal, ao, threads, isa);
}

} // namespace obscura::cpu
