// What every per-ISA kernel instantiation (cpu/*_tile_impl.h) shares: the lane types for
// OBSCURA_LANES (1: GLM scalars, one pixel at a time; 4, 8, 16: SIMD registers of a row of
// pixels), loads with the lane kernels' signature, and the store of one lane.
// Included by cpu/isa_kernels.cpp and cpu/isa_lane_kernels.cpp once per ISA, so everything here
// has internal linkage.
#pragma once
#include "cpu/isa.h"
#include "base/kernel_params.h"

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

#if OBSCURA_LANES == 16
// True where every lane is used and lane i reads index[0] + i * stride: a row of whole
// texels, as the blur's lanes read. Then plain loads (and permutes) replace a gather.
inline bool wholeRow(lint index, lbool use, int stride) {
    const vint expect = index.v[0] + laneIndex().v * stride;
    return _mm512_cmpeq_epi32_mask((__m512i)index.v, (__m512i)expect) == 0xffff &&
           use.k == 0xffff;
}
// Channel c (< 3) of 16 texels of 3 floats from p: 48 floats in three loads, picked out by
// two two-register permutes.
inline lfloat deinterleave3(const float* p, int c) {
    const __m512 a0 = _mm512_loadu_ps(p), a1 = _mm512_loadu_ps(p + 16), a2 = _mm512_loadu_ps(p + 32);
    vint first, second;
    for (int j = 0; j < 16; ++j) {
        const int e = 3 * j + c; // element of the 48
        first[j] = e < 32 ? e : 0;
        second[j] = e < 32 ? j : 16 + e - 32;
    }
    const __m512 t = _mm512_permutex2var_ps(a0, (__m512i)first, a1);
    return (vfloat)_mm512_permutex2var_ps(t, (__m512i)second, a2);
}
// The inverse: 16 texels of 3 floats to p from their channels, two permutes and a store each.
inline void interleave3(float* p, lfloat r, lfloat g, lfloat b) {
    for (int k = 0; k < 3; ++k) {
        vint first, second;
        for (int j = 0; j < 16; ++j) {
            const int e = 16 * k + j, texel = e / 3, c = e % 3; // element e of the 48
            first[j] = c == 0 ? texel : c == 1 ? 16 + texel : 0;
            second[j] = c == 2 ? 16 + texel : j;
        }
        const __m512 t = _mm512_permutex2var_ps((__m512)r.v, (__m512i)first, (__m512)g.v);
        _mm512_storeu_ps(p + 16 * k, _mm512_permutex2var_ps(t, (__m512i)second, (__m512)b.v));
    }
}
#endif

// A row of `count` lanes to dst, xStride floats apart: one vector store where the row is whole
// and contiguous, else lane by lane. One channel, and three (RGB).
inline void storeRow(float* dst, std::ptrdiff_t xStride, int count, lfloat v) {
#if OBSCURA_LANES == 16
    if (count == 16 && xStride == 1) {
        _mm512_storeu_ps(dst, (__m512)v.v);
        return;
    }
#endif
    for (int i = 0; i < count; ++i) dst[i * xStride] = laneValue(v, i);
}
inline void storeRow(float* dst, std::ptrdiff_t xStride, int count, lfloat r, lfloat g, lfloat b) {
#if OBSCURA_LANES == 16
    if (count == 16 && xStride == 3) {
        interleave3(dst, r, g, b);
        return;
    }
#endif
    for (int i = 0; i < count; ++i) {
        dst[i * xStride] = laneValue(r, i);
        dst[i * xStride + 1] = laneValue(g, i);
        dst[i * xStride + 2] = laneValue(b, i);
    }
}

// The 4 floats at base + index per lane (a 16-byte record; index a multiple of 4) where `use`, 0
// elsewhere. AVX-512 reads each lane's record with one 16-byte load and transposes the sixteen
// instead of issuing four gathers, which are microcoded here (HBAO's border: docs/hbao.md).
inline lvec4 gatherRecord4(const float* base, lint index, lbool use) {
#if OBSCURA_LANES == 1
    return use ? vec4(base[index], base[index + 1], base[index + 2], base[index + 3]) : vec4(0.0f);
#elif OBSCURA_LANES == 16
    alignas(64) int at[16];
    _mm512_store_si512(at, _mm512_maskz_mov_epi32(use.k, (__m512i)index.v)); // unused lanes read record 0
    // z[r] holds the records of lanes r, 4 + r, 8 + r, 12 + r in its four 128-bit slots ...
    __m512 z[4];
    for (int r = 0; r < 4; ++r) {
        __m512 v = _mm512_zextps128_ps512(_mm_loadu_ps(base + at[r]));
        v = _mm512_insertf32x4(v, _mm_loadu_ps(base + at[4 + r]), 1);
        v = _mm512_insertf32x4(v, _mm_loadu_ps(base + at[8 + r]), 2);
        z[r] = _mm512_insertf32x4(v, _mm_loadu_ps(base + at[12 + r]), 3);
    }
    // ... so a 4 x 4 transpose within each slot puts component c of lanes 4s .. 4s + 3 in slot s.
    // (The zero-masked unpacks: GCC 12's plain ones warn of an "uninitialized" undefined source.)
    const __m512 t0 = _mm512_maskz_unpacklo_ps(0xffff, z[0], z[1]), t1 = _mm512_maskz_unpackhi_ps(0xffff, z[0], z[1]);
    const __m512 t2 = _mm512_maskz_unpacklo_ps(0xffff, z[2], z[3]), t3 = _mm512_maskz_unpackhi_ps(0xffff, z[2], z[3]);
    const auto lanes = [&](__m512 c) { return lfloat((vfloat)_mm512_maskz_mov_ps(use.k, c)); };
    return lvec4(lanes(_mm512_shuffle_ps(t0, t2, 0x44)), lanes(_mm512_shuffle_ps(t0, t2, 0xee)),
                 lanes(_mm512_shuffle_ps(t1, t3, 0x44)), lanes(_mm512_shuffle_ps(t1, t3, 0xee)));
#else
    return lvec4(gather(base, index, use), gather(base + 1, index, use), gather(base + 2, index, use),
                 gather(base + 3, index, use));
#endif
}

// A plane as the lane kernels read it: element c of texel (x, y) at data[y*yStride + x*xStride + c].
// `rows`: the kernel's lanes usually read whole rows of texels (the blur), worth a test for it.
struct LanePlane {
    const float* data = nullptr;
    int xStride = 0, yStride = 0;
    bool rows = false;
    LanePlane() = default;
    explicit LanePlane(const ConstPlane& p, bool rowsOfTexels = false)
        : data(p.data), xStride((int)p.xStride), yStride((int)p.yStride), rows(rowsOfTexels) {}
    // Masked-off lanes read nothing and get 0.
    lfloat gather1(lint x, lint y, lbool use, int c = 0) const {
        const lint i = y * yStride + x * xStride;
#if OBSCURA_LANES == 16
        if (rows && xStride == 1 && wholeRow(i, use, 1)) return (vfloat)_mm512_loadu_ps(data + c + i[0]);
        if (rows && xStride == 3 && c < 3 && wholeRow(i, use, 3)) return deinterleave3(data + i[0], c);
#endif
        return gather(data + c, i, use);
    }
    lvec3 gather3(lint x, lint y, lbool use) const {
        const lint i = y * yStride + x * xStride;
#if OBSCURA_LANES == 16
        if (rows && xStride == 3 && wholeRow(i, use, 3))
            return lvec3(deinterleave3(data + i[0], 0), deinterleave3(data + i[0], 1), deinterleave3(data + i[0], 2));
#endif
        return lvec3(gather(data, i, use), gather(data + 1, i, use), gather(data + 2, i, use));
    }
};

} // namespace
} // namespace obscura::glsl
