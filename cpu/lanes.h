// Lane types: the kernels' per-pixel scalars, several pixels per SIMD register.
//
// The kernels in kernels/*.glsl declare per-pixel values as lfloat, lint, luint, lbool,
// lvec2 and lvec3. GLSL sees float, int, ..., vec3 (kernels/glsl_prelude.glsl); the
// scalar C++ build sees the same GLM types (cpu/lanes_scalar.h); this header makes each
// of them a register of OBSCURA_LANES pixels over GCC vector extensions, so one kernel
// text runs one pixel per GPU thread and 4, 8 or 16 pixels per CPU instruction.
// Branches on lane values do not compile: kernels use select() and anyLane() instead.
//
// Include inside an anonymous namespace per instruction set (see cpu/lane_tile_impl.h),
// so code compiled for AVX-512 is never linked into a baseline caller.
#pragma once
#include <glm/glm.hpp>
#include <immintrin.h>

#include <cstdint>

#ifndef OBSCURA_LANES
#error "define OBSCURA_LANES (4, 8 or 16) before including cpu/lanes.h"
#endif

namespace obscura::cpu::lanes {
namespace {

// The kernels call these names on uniform floats and GLM vectors too; bringing GLM's
// overloads here keeps them visible beside the lane ones.
using glm::abs;
using glm::acos;
using glm::atan;
using glm::clamp;
using glm::cos;
using glm::cross;
using glm::dot;
using glm::exp;
using glm::findLSB;
using glm::findMSB;
using glm::floor;
using glm::fract;
using glm::inversesqrt;
using glm::max;
using glm::min;
using glm::mix;
using glm::normalize;
using glm::sin;
using glm::sqrt;

constexpr int kLanes = OBSCURA_LANES;
typedef float vfloat __attribute__((vector_size(4 * kLanes)));
typedef std::int32_t vint __attribute__((vector_size(4 * kLanes)));
typedef std::uint32_t vuint __attribute__((vector_size(4 * kLanes)));

struct lint;
struct luint;

#if OBSCURA_LANES == 16
// A lane mask. AVX-512: a mask register, one bit per lane, as its comparisons produce,
// its blends and gathers consume it, and kortest tests it.
struct lbool {
    __mmask16 k;
};
#else
// A lane mask. AVX2 / SSE2: all bits set where true, as vector comparisons produce it.
struct lbool {
    vint m;
};
#endif

struct lfloat {
    vfloat v;
    lfloat() : v{} {}
    lfloat(vfloat a) : v(a) {}
    lfloat(float s) : v(s - vfloat{}) {}
    explicit lfloat(lint i);
    explicit lfloat(luint u);
    float operator[](int i) const { return v[i]; }
};

struct lint {
    vint v;
    lint() : v{} {}
    lint(vint a) : v(a) {}
    lint(int s) : v(s - vint{}) {}
    // Truncation towards zero, as GLSL's int(float).
    explicit lint(lfloat f) : v(__builtin_convertvector(f.v, vint)) {}
    explicit lint(luint u);
    int operator[](int i) const { return v[i]; }
};

struct luint {
    vuint v;
    luint() : v{} {}
    luint(vuint a) : v(a) {}
    luint(std::uint32_t s) : v(s - vuint{}) {}
    explicit luint(lint i) : v((vuint)i.v) {}
};

inline lint::lint(luint u) : v((vint)u.v) {} // the bits, as GLSL's int(uint)
inline lfloat::lfloat(lint i) : v(__builtin_convertvector(i.v, vfloat)) {}
inline lfloat::lfloat(luint u) : v(__builtin_convertvector(u.v, vfloat)) {}

// ---- lfloat arithmetic and comparisons ----
inline lfloat operator+(lfloat a, lfloat b) { return a.v + b.v; }
inline lfloat operator-(lfloat a, lfloat b) { return a.v - b.v; }
inline lfloat operator*(lfloat a, lfloat b) { return a.v * b.v; }
inline lfloat operator/(lfloat a, lfloat b) { return a.v / b.v; }
inline lfloat operator-(lfloat a) { return -a.v; }
inline lfloat& operator+=(lfloat& a, lfloat b) { return a = a + b; }
inline lfloat& operator-=(lfloat& a, lfloat b) { return a = a - b; }
inline lfloat& operator*=(lfloat& a, lfloat b) { return a = a * b; }

// ---- lint / luint ----
inline lint operator+(lint a, lint b) { return a.v + b.v; }
inline lint operator-(lint a, lint b) { return a.v - b.v; }
inline lint operator*(lint a, lint b) { return a.v * b.v; }
inline luint operator+(luint a, luint b) { return a.v + b.v; }
inline luint operator*(luint a, luint b) { return a.v * b.v; }
inline luint operator^(luint a, luint b) { return a.v ^ b.v; }
inline luint operator>>(luint a, std::uint32_t s) { return a.v >> s; }
inline luint& operator^=(luint& a, luint b) { return a = a ^ b; }
inline luint& operator*=(luint& a, luint b) { return a = a * b; }

// ---- comparisons and masks (ordered: NaN compares false, as in GLSL) ----
#if OBSCURA_LANES == 16
inline lbool operator<(lfloat a, lfloat b) { return {_mm512_cmp_ps_mask((__m512)a.v, (__m512)b.v, _CMP_LT_OQ)}; }
inline lbool operator<=(lfloat a, lfloat b) { return {_mm512_cmp_ps_mask((__m512)a.v, (__m512)b.v, _CMP_LE_OQ)}; }
inline lbool operator>(lfloat a, lfloat b) { return {_mm512_cmp_ps_mask((__m512)a.v, (__m512)b.v, _CMP_GT_OQ)}; }
inline lbool operator>=(lfloat a, lfloat b) { return {_mm512_cmp_ps_mask((__m512)a.v, (__m512)b.v, _CMP_GE_OQ)}; }
inline lbool operator<(lint a, lint b) { return {_mm512_cmplt_epi32_mask((__m512i)a.v, (__m512i)b.v)}; }
inline lbool operator>=(lint a, lint b) { return {_mm512_cmpge_epi32_mask((__m512i)a.v, (__m512i)b.v)}; }
inline lbool operator>(lint a, lint b) { return {_mm512_cmpgt_epi32_mask((__m512i)a.v, (__m512i)b.v)}; }
inline lbool operator&&(lbool a, lbool b) { return {(__mmask16)(a.k & b.k)}; }
inline lbool operator||(lbool a, lbool b) { return {(__mmask16)(a.k | b.k)}; }
inline lbool operator!(lbool a) { return {(__mmask16)~a.k}; }
// True if any lane is true: the kernels' uniform early-outs.
inline bool anyLane(lbool a) { return a.k != 0; }
// GLSL's `c ? a : b` per lane.
inline lfloat select(lbool c, lfloat a, lfloat b) { return (vfloat)_mm512_mask_blend_ps(c.k, (__m512)b.v, (__m512)a.v); }
inline lint select(lbool c, lint a, lint b) { return (vint)_mm512_mask_blend_epi32(c.k, (__m512i)b.v, (__m512i)a.v); }
#else
inline lbool operator<(lfloat a, lfloat b) { return {a.v < b.v}; }
inline lbool operator<=(lfloat a, lfloat b) { return {a.v <= b.v}; }
inline lbool operator>(lfloat a, lfloat b) { return {a.v > b.v}; }
inline lbool operator>=(lfloat a, lfloat b) { return {a.v >= b.v}; }
inline lbool operator<(lint a, lint b) { return {a.v < b.v}; }
inline lbool operator>=(lint a, lint b) { return {a.v >= b.v}; }
inline lbool operator>(lint a, lint b) { return {a.v > b.v}; }
inline lbool operator&&(lbool a, lbool b) { return {a.m & b.m}; }
inline lbool operator||(lbool a, lbool b) { return {a.m | b.m}; }
inline lbool operator!(lbool a) { return {~a.m}; }
inline bool anyLane(lbool a) {
#if OBSCURA_LANES == 8
    return _mm256_movemask_ps((__m256)a.m) != 0;
#else
    return _mm_movemask_ps((__m128)a.m) != 0;
#endif
}
inline lfloat select(lbool c, lfloat a, lfloat b) { return c.m ? a.v : b.v; }
inline lint select(lbool c, lint a, lint b) { return c.m ? a.v : b.v; }
#endif

// ---- built-ins, with GLSL's meaning ----
// min/max as GLM's: (x < y) ? y : x, so a NaN x passes through max unchanged.
// (MAXPS(a, b) is (a > b) ? a : b, so MAXPS(y, x) is GLM's max(x, y).)
// AVX-512: the zero-masking forms, as GCC 12's unmasked ones start from an 'undefined'
// register that -Wmaybe-uninitialized reports.
#if OBSCURA_LANES == 16
inline lfloat max(lfloat x, lfloat y) { return (vfloat)_mm512_maskz_max_ps(0xffff, (__m512)y.v, (__m512)x.v); }
inline lfloat min(lfloat x, lfloat y) { return (vfloat)_mm512_maskz_min_ps(0xffff, (__m512)y.v, (__m512)x.v); }
#elif OBSCURA_LANES == 8
inline lfloat max(lfloat x, lfloat y) { return (vfloat)_mm256_max_ps((__m256)y.v, (__m256)x.v); }
inline lfloat min(lfloat x, lfloat y) { return (vfloat)_mm256_min_ps((__m256)y.v, (__m256)x.v); }
#else
inline lfloat max(lfloat x, lfloat y) { return (vfloat)_mm_max_ps((__m128)y.v, (__m128)x.v); }
inline lfloat min(lfloat x, lfloat y) { return (vfloat)_mm_min_ps((__m128)y.v, (__m128)x.v); }
#endif
inline lfloat clamp(lfloat x, lfloat lo, lfloat hi) { return min(max(x, lo), hi); }
inline lfloat abs(lfloat x) { return (vfloat)((vint)x.v & 0x7fffffff); }

inline lfloat sqrt(lfloat x) {
#if OBSCURA_LANES == 16
    return (vfloat)_mm512_maskz_sqrt_ps(0xffff, (__m512)x.v); // maskz: see inversesqrt
#elif OBSCURA_LANES == 8
    return (vfloat)_mm256_sqrt_ps((__m256)x.v);
#else
    return (vfloat)_mm_sqrt_ps((__m128)x.v);
#endif
}

// 1/sqrt(x) for x > 0: the hardware estimate (14 bits with AVX-512, 12 without) and one
// Newton step, within 2 ulp of the correctly rounded value, at a fraction of a division's cost.
inline lfloat inversesqrt(lfloat x) {
#if OBSCURA_LANES == 16
    const vfloat y = (vfloat)_mm512_maskz_rsqrt14_ps(0xffff, (__m512)x.v);
#elif OBSCURA_LANES == 8
    const vfloat y = (vfloat)_mm256_rsqrt_ps((__m256)x.v);
#else
    const vfloat y = (vfloat)_mm_rsqrt_ps((__m128)x.v);
#endif
    return y * (1.5f - (0.5f * x.v) * y * y);
}

inline lfloat floor(lfloat x) {
#if OBSCURA_LANES == 16
    return (vfloat)_mm512_maskz_roundscale_ps(0xffff, (__m512)x.v, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
#elif OBSCURA_LANES == 8
    return (vfloat)_mm256_floor_ps((__m256)x.v);
#else
    // SSE2 has no floor: truncate, step down where that rounded up. |x| >= 2^23 is already
    // an integer (and would overflow the int); NaN fails the test; both are kept as they are.
    const vfloat t = __builtin_convertvector(__builtin_convertvector(x.v, vint), vfloat);
    const vfloat f = t - (vfloat)((vint)(t > x.v) & (vint)(1.0f - vfloat{}));
    return abs(x).v < 8388608.0f ? f : x.v;
#endif
}
inline lfloat fract(lfloat x) { return x - floor(x); }

// sin and cos together: reduction to [-pi/4, pi/4] by multiples of pi/2 (pi/2 split in
// three parts, exact to |x| ~ 1e4), then the minimax polynomials of Cephes' sinf/cosf
// (about 1 ulp on the reduced range).
inline void sinCos(lfloat x, lfloat& s, lfloat& c) {
    const lfloat j = floor(x * 0.636619772367581f + 0.5f); // nearest multiple of pi/2
    lfloat r = x - j * 1.5703125f;
    r = r - j * 4.837512969970703125e-4f;
    r = r - j * 7.549789948768648e-8f;
    const lfloat z = r * r;
    const lfloat sinR = r + r * z * (-1.6666654611e-1f + z * (8.3321608736e-3f + z * -1.9515295891e-4f));
    const lfloat cosR =
        1.0f - 0.5f * z + z * z * (4.166664568298827e-2f + z * (-1.388731625493765e-3f + z * 2.443315711809948e-5f));
    const vint q = lint(j).v & 3;
    const vfloat sn = q & 1 ? cosR.v : sinR.v; // quadrants 1 and 3 swap sin and cos
    const vfloat cs = q & 1 ? sinR.v : cosR.v;
    s = (q & 2) ? -sn : sn;                    // quadrants 2 and 3 negate sin
    c = ((q + 1) & 2) ? -cs : cs;              // quadrants 1 and 2 negate cos
}
inline lfloat sin(lfloat x) {
    lfloat s, c;
    sinCos(x, s, c);
    return s;
}
inline lfloat cos(lfloat x) {
    lfloat s, c;
    sinCos(x, s, c);
    return c;
}

// atan(y, x) in (-pi, pi], as GLSL's two-argument atan: atan(t) on t = min/max of |x|, |y|
// in [0, 1] by an odd degree-13 polynomial (weighted least-squares fit to a minimax error of
// 3.3e-7, this project's own), then the octant from the swap and the signs.
inline lfloat atan(lfloat y, lfloat x) {
    const lfloat ax = abs(x), ay = abs(y);
    const lbool swap = ay > ax; // atan(t) = pi/2 - atan(1/t)
    const lfloat t = min(ax, ay) / max(max(ax, ay), 1e-30f);
    const lfloat z = t * t;
    lfloat r = 6.811782252043486e-3f;
    r = r * z - 3.360418602824211e-2f;
    r = r * z + 7.962363958358765e-2f;
    r = r * z - 1.323333978652954e-1f;
    r = r * z + 1.980781555175781e-1f;
    r = r * z - 3.331736922264099e-1f;
    r = r * z + 9.999961256980896e-1f;
    r = r * t;
    r = select(swap, 1.57079632679490f - r, r);
    r = select(x < 0.0f, 3.14159265358979f - r, r);
    return (vfloat)((vint)r.v | ((vint)y.v & (vint)(0x80000000u - vuint{}))); // sign of y
}

// ---- added for SSDO and the blur ----
inline lint operator/(lint a, lint b) { return a.v / b.v; } // truncating, as GLSL's (and C's)
inline lint operator%(lint a, lint b) { return a.v % b.v; }
inline lint min(lint x, lint y) { return y.v < x.v ? y.v : x.v; }
inline lint max(lint x, lint y) { return x.v < y.v ? y.v : x.v; }
inline lint clamp(lint x, lint lo, lint hi) { return min(max(x, lo), hi); }
// Arithmetic shifts by a uniform count, as GLSL's on int (floor division by 2^s).
inline lint operator>>(lint a, int s) { return a.v >> s; }
inline lint operator<<(lint a, int s) { return a.v << s; }
inline luint operator&(luint a, luint b) { return a.v & b.v; }
inline luint operator|(luint a, luint b) { return a.v | b.v; }
inline luint operator<<(luint a, std::uint32_t s) { return a.v << s; }
inline lfloat& operator/=(lfloat& a, lfloat b) { return a = a / b; }

// ---- added for HBAO's visibility bitmask ----
// Shift by a per-lane count in [0, 31] (GLSL leaves 32 and more undefined, and so do these).
inline luint operator<<(luint a, luint s) { return a.v << s.v; }
inline luint operator>>(luint a, luint s) { return a.v >> s.v; }
inline luint operator-(luint a, luint b) { return a.v - b.v; }
inline luint operator~(luint a) { return ~a.v; }
inline luint select(lbool c, luint a, luint b) { return (vuint)select(c, lint((vint)a.v), lint((vint)b.v)).v; }
// GLSL's bit casts between float and uint lanes.
inline lfloat uintBitsToFloat(luint a) { return (vfloat)a.v; }
inline luint floatBitsToUint(lfloat a) { return (vuint)a.v; }
// The bits set in any lane, as a uniform (GLSL: the pixel's own value).
inline std::uint32_t lanesOr(luint a) {
    std::uint32_t any = 0;
    for (int i = 0; i < kLanes; ++i) any |= a.v[i];
    return any;
}

// A value the kernel knows to be equal in every lane, as a uniform scalar.
inline float uniformValue(lfloat x) { return x.v[0]; }

// acos(x) for x in [-1, 1] as atan(sqrt(1 - x^2), x), with 1 - x^2 formed as (1 - x)(1 + x):
// exact near +-1, where 1 - x*x would cancel. Within about 3e-7 of the true value.
inline lfloat acos(lfloat x) { return atan(sqrt(max((1.0f - x) * (1.0f + x), 0.0f)), x); }

// exp(x): x = k ln2 + r with |r| <= ln2/2 (ln2 split in two parts), Cephes' expf polynomial
// for e^r (about 1 ulp), times 2^k built in exponent bits. Below -87.3 (a result near the
// denormals) it returns 0, above 88.7 +inf; NaN stays NaN.
inline lfloat exp(lfloat x) {
    const lfloat xc = clamp(x, -87.3f, 88.7f);
    const lfloat k = floor(xc * 1.44269504088896341f + 0.5f);
    lfloat r = xc - k * 0.693359375f;
    r = r - k * -2.12194440e-4f;
    const lfloat z = r * r;
    const lfloat p = ((((( 1.9875691500e-4f * r + 1.3981999507e-3f) * r + 8.3334519073e-3f) * r + 4.1665795894e-2f) * r +
                       1.6666665459e-1f) * r + 5.0000001201e-1f) * z + r + 1.0f;
    // 2^k as 2^h 2^(k-h), h = k/2: each a normal float over the whole k in [-126, 128].
    const vint ki = lint(k).v, half = ki >> 1;
    const vfloat e = p.v * (vfloat)((half + 127) << 23) * (vfloat)((ki - half + 127) << 23);
    vfloat out = x.v < -87.3f ? vfloat{} : e;
    out = x.v > 88.7f ? (vfloat)(0x7f800000 - vint{}) : out;
    return x.v == x.v ? out : x.v;
}

// ---- lvec2 / lvec3: GLSL's vec2 / vec3 of lanes ----
struct lvec2 {
    lfloat x, y;
    lvec2() = default;
    lvec2(lfloat a, lfloat b) : x(a), y(b) {}
};
inline lvec2 operator+(lvec2 a, lvec2 b) { return {a.x + b.x, a.y + b.y}; }
inline lvec2 operator-(lvec2 a, lvec2 b) { return {a.x - b.x, a.y - b.y}; }
inline lvec2 operator+(lvec2 a, const glm::vec2& b) { return {a.x + b.x, a.y + b.y}; }
inline lvec2 operator-(lvec2 a, const glm::vec2& b) { return {a.x - b.x, a.y - b.y}; }
inline lvec2 operator*(lvec2 a, lfloat s) { return {a.x * s, a.y * s}; }
inline lvec2 floor(lvec2 a) { return {floor(a.x), floor(a.y)}; }
inline lfloat dot(lvec2 a, lvec2 b) { return a.x * b.x + a.y * b.y; }

struct lvec3 {
    lfloat x, y, z;
    lvec3() = default;
    lvec3(lfloat a, lfloat b, lfloat c) : x(a), y(b), z(c) {}
    lvec3(const glm::vec3& u) : x(u.x), y(u.y), z(u.z) {}
};
inline lvec3 operator+(lvec3 a, lvec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline lvec3 operator-(lvec3 a, lvec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline lvec3 operator-(lvec3 a) { return {-a.x, -a.y, -a.z}; }
inline lvec3 operator*(lvec3 a, lfloat s) { return {a.x * s, a.y * s, a.z * s}; }
inline lvec3 operator*(lfloat s, lvec3 a) { return a * s; }
inline lvec3 operator*(float s, lvec3 a) { return a * lfloat(s); }
inline lvec3 operator/(lvec3 a, lfloat s) { return a * (1.0f / s); }
inline lvec3& operator*=(lvec3& a, lfloat s) { return a = a * s; }
inline lvec3& operator+=(lvec3& a, lvec3 b) { return a = a + b; }
inline lfloat dot(lvec3 a, lvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline lvec3 cross(lvec3 a, lvec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline lvec3 normalize(lvec3 a) { return a * inversesqrt(dot(a, a)); }
inline lvec3 select(lbool c, lvec3 a, lvec3 b) { return {select(c, a.x, b.x), select(c, a.y, b.y), select(c, a.z, b.z)}; }
// A uniform matrix times a lane vector (GLM's mat3 is column-major, as GLSL's).
inline lvec3 operator*(const glm::mat3& m, lvec3 a) {
    return {m[0][0] * a.x + m[1][0] * a.y + m[2][0] * a.z, m[0][1] * a.x + m[1][1] * a.y + m[2][1] * a.z,
            m[0][2] * a.x + m[1][2] * a.y + m[2][2] * a.z};
}

// ---- added for SSDO and the blur ----
inline lvec3 operator*(lvec3 a, lvec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
// GLSL's mix: a (1 - t) + b t, as GLM computes it.
inline lvec3 mix(lvec3 a, lvec3 b, lfloat t) { return a * (1.0f - t) + b * t; }

struct lvec4 {
    lfloat x, y, z, w;
    lvec4() = default;
    lvec4(lfloat a, lfloat b, lfloat c, lfloat d) : x(a), y(b), z(c), w(d) {}
    lfloat operator[](int i) const { return i == 0 ? x : i == 1 ? y : i == 2 ? z : w; }
};
inline lvec4 operator+(lvec4 a, lvec4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
inline lvec4 operator-(lvec4 a, lvec4 b) { return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w}; }
inline lvec4 operator*(lfloat s, lvec4 a) { return {s * a.x, s * a.y, s * a.z, s * a.w}; }
inline lvec4 operator/(lvec4 a, lfloat s) { return {a.x / s, a.y / s, a.z / s, a.w / s}; }
inline lvec4& operator+=(lvec4& a, lvec4 b) { return a = a + b; }
inline lvec4 select(lbool c, lvec4 a, lvec4 b) {
    return {select(c, a.x, b.x), select(c, a.y, b.y), select(c, a.z, b.z), select(c, a.w, b.w)};
}

// Lane i holds i: the x offsets of a row of pixels.
inline lint laneIndex() {
    lint r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = i;
    return r;
}

// base[index] per lane where `use`, 0 elsewhere (which no kernel mistakes for a surface).
inline lfloat gather(const float* base, lint index, lbool use) {
#if OBSCURA_LANES == 16
    return (vfloat)_mm512_mask_i32gather_ps(_mm512_setzero_ps(), use.k, (__m512i)index.v, base, 4);
#elif OBSCURA_LANES == 8
    return (vfloat)_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, (__m256i)index.v, (__m256)use.m, 4);
#else
    lfloat r;
    for (int i = 0; i < kLanes; ++i) r.v[i] = use.m[i] ? base[index.v[i]] : 0.0f;
    return r;
#endif
}

} // namespace
} // namespace obscura::cpu::lanes
