// What every per-ISA kernel instantiation (cpu/*_tile_impl.h) shares: the lane types for
// OBSCURA_LANES (1: GLM scalars, one pixel at a time; 4, 8, 16: SIMD registers of a row of
// pixels), loads with the lane kernels' signature, and the store of one lane.
// Included by cpu/isa_kernels.cpp once per ISA, so everything here has internal linkage.
#pragma once
#include "cpu/isa.h"
#include "cpu/kernel_params.h"

#if OBSCURA_LANES == 1
#include "cpu/lanes_scalar.h"
#else
#include "cpu/lanes.h"
#endif

namespace obscura::glsl {
namespace {
#if OBSCURA_LANES > 1
using namespace cpu::lanes;
#endif

#if OBSCURA_LANES == 1
// One pixel: plain loads.
inline float gather(const float* base, int index, bool use) { return use ? base[index] : 0.0f; }
inline int laneIndex() { return 0; }
inline float laneValue(float v, int) { return v; }
#else
inline float laneValue(lfloat v, int i) { return v[i]; }
#endif

// A plane as the lane kernels read it: element c of texel (x, y) at data[y*yStride + x*xStride + c].
struct LanePlane {
    const float* data = nullptr;
    int xStride = 0, yStride = 0;
    LanePlane() = default;
    explicit LanePlane(const ConstPlane& p) : data(p.data), xStride((int)p.xStride), yStride((int)p.yStride) {}
    // Masked-off lanes read nothing and get 0.
    lfloat gather1(lint x, lint y, lbool use, int c = 0) const { return gather(data + c, y * yStride + x * xStride, use); }
    lvec3 gather3(lint x, lint y, lbool use) const {
        const lint i = y * yStride + x * xStride;
        return lvec3(gather(data, i, use), gather(data + 1, i, use), gather(data + 2, i, use));
    }
};

} // namespace
} // namespace obscura::glsl
