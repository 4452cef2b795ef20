// vec4 / ivec4 for the CPU instantiation of the kernels, on SIMD registers.
//
// GLM's vec4 is four separate floats, and GCC does not turn the kernels' vec4 arithmetic
// into packed instructions. These types have the same GLSL spelling (constructors,
// .x/.y/.z/.w, operators, the few built-ins the kernels use on vec4) over GCC/Clang vector
// extensions, so each operation is one SSE/AVX instruction. Per lane the arithmetic is
// exactly GLM's (IEEE add, mul, div, sqrt; max as GLM's (x < y) ? y : x), so results
// do not depend on which vec4 the kernel is compiled with.
//
// Everything is in an anonymous namespace: each instruction-set TU gets its own copy,
// and the linker can never substitute an AVX-encoded one into baseline code.
#pragma once
#include <glm/glm.hpp>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace obscura::cpu::simd {
namespace {

typedef float v4sf __attribute__((vector_size(16)));
typedef int v4si __attribute__((vector_size(16)));

// GNU anonymous structs in a union: .x etc. name the lanes of the register.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
struct vec4 {
    union {
        v4sf v;
        struct {
            float x, y, z, w;
        };
    };
    vec4() : v{0.0f, 0.0f, 0.0f, 0.0f} {}
    constexpr vec4(v4sf a) : v(a) {}
    constexpr explicit vec4(float s) : v{s, s, s, s} {}
    constexpr vec4(float a, float b, float c, float d) : v{a, b, c, d} {}
};

struct ivec4 {
    union {
        v4si v;
        struct {
            int x, y, z, w;
        };
    };
    constexpr ivec4(v4si a) : v(a) {}
    // Truncation towards zero, as GLSL's ivec4(vec4) (values must fit an int).
    explicit ivec4(vec4 f) : v(__builtin_convertvector(f.v, v4si)) {}
};
// A lane mask (all bits set = true), as comparisons produce it.
struct bvec4 {
    v4si v;
    bvec4(v4si a) : v(a) {}
};
#pragma GCC diagnostic pop

inline vec4 operator+(vec4 a, vec4 b) { return a.v + b.v; }
inline vec4 operator-(vec4 a, vec4 b) { return a.v - b.v; }
inline vec4 operator*(vec4 a, vec4 b) { return a.v * b.v; }
inline vec4 operator/(vec4 a, vec4 b) { return a.v / b.v; }
inline vec4 operator+(vec4 a, float b) { return a.v + b; }
inline vec4 operator-(vec4 a, float b) { return a.v - b; }
inline vec4 operator*(vec4 a, float b) { return a.v * b; }
inline vec4 operator/(vec4 a, float b) { return a.v / b; }
inline vec4 operator+(float a, vec4 b) { return a + b.v; }
inline vec4 operator-(float a, vec4 b) { return a - b.v; }
inline vec4 operator*(float a, vec4 b) { return a * b.v; }
inline vec4 operator/(float a, vec4 b) { return a / b.v; }
inline vec4 operator-(vec4 a) { return -a.v; }
inline vec4& operator+=(vec4& a, vec4 b) { a.v += b.v; return a; }
inline vec4& operator*=(vec4& a, vec4 b) { a.v *= b.v; return a; }

inline bvec4 lessThan(vec4 a, vec4 b) { return a.v < b.v; }
inline bvec4 lessThanEqual(vec4 a, vec4 b) { return a.v <= b.v; }
inline bvec4 greaterThan(vec4 a, vec4 b) { return a.v > b.v; }
inline bvec4 greaterThanEqual(vec4 a, vec4 b) { return a.v >= b.v; }
// GLSL's mix with a boolean selector: y where a is true, else x (a select, no arithmetic).
inline vec4 mix(vec4 x, vec4 y, bvec4 a) { return a.v ? y.v : x.v; }

inline ivec4 operator-(ivec4 a, int b) { return a.v - b; }
inline ivec4 operator+(ivec4 a, int b) { return a.v + b; }

// GLM's max: (x < y) ? y : x, so a NaN x is returned as is.
inline vec4 max(vec4 x, vec4 y) {
#if defined(__SSE2__)
    return _mm_max_ps(y.v, x.v); // (y > x) ? y : x
#else
    return x.v < y.v ? y.v : x.v;
#endif
}
inline vec4 max(vec4 x, float y) { return max(x, vec4(y)); }
inline vec4 min(vec4 x, vec4 y) {
#if defined(__SSE2__)
    return _mm_min_ps(y.v, x.v); // (y < x) ? y : x
#else
    return y.v < x.v ? y.v : x.v;
#endif
}
inline vec4 min(vec4 x, float y) { return min(x, vec4(y)); }

inline vec4 sqrt(vec4 x) {
#if defined(__SSE2__)
    return _mm_sqrt_ps(x.v);
#else
    return vec4(__builtin_sqrtf(x.x), __builtin_sqrtf(x.y), __builtin_sqrtf(x.z), __builtin_sqrtf(x.w));
#endif
}
// GLM's inversesqrt: 1 / sqrt(x), correctly rounded twice (no rsqrt approximation).
inline vec4 inversesqrt(vec4 x) { return 1.0f / sqrt(x); }

inline vec4 floor(vec4 x) {
#if defined(__SSE4_1__)
    return _mm_floor_ps(x.v);
#else
    // Truncate, step down where that rounded up (negative non-integers). |x| >= 2^23 is
    // already an integer (and would overflow the int), NaN fails the test: both kept as is.
    const v4sf t = __builtin_convertvector(__builtin_convertvector(x.v, v4si), v4sf);
    const v4sf f = t - (v4sf)((v4si)(t > x.v) & (v4si)vec4(1.0f).v);
    const v4sf ax = (v4sf)((v4si)x.v & (v4si)(0x7fffffff + v4si{}));
    return ax < 8388608.0f ? f : x.v;
#endif
}

} // namespace
} // namespace obscura::cpu::simd
