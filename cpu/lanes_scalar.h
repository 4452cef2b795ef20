// The lane names of kernels/*.glsl as plain GLM scalars and vectors: one pixel at a time,
// exactly as GLSL reads them. Used by the CPU kernels that run a pixel per call (SSDO,
// the blur) and by the pixel-at-a-time HBAO reference the lane build is tested against.
#pragma once
#include "kernels/glsl_cpp.h"

namespace obscura::glsl {

using lfloat = float;
using lint = int;
using luint = uint;
using lbool = bool;
using lvec2 = vec2;
using lvec3 = vec3;

inline bool anyLane(bool b) { return b; }
inline float select(bool c, float a, float b) { return c ? a : b; }
inline int select(bool c, int a, int b) { return c ? a : b; }
inline vec3 select(bool c, vec3 a, vec3 b) { return c ? a : b; }
// Added for SSDO and the blur.
using lvec4 = vec4;
inline vec4 select(bool c, vec4 a, vec4 b) { return c ? a : b; }
inline float uniformValue(float x) { return x; }
// Added for HBAO's visibility bitmask.
inline uint select(bool c, uint a, uint b) { return c ? a : b; }
inline uint lanesOr(uint a) { return a; }

} // namespace obscura::glsl
