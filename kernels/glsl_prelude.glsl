// GLSL side of the common subset (see kernels/glsl_cpp.h for the C++ side).
#define IN(T) T
#define OUT(T) out T
#define INOUT(T) inout T
#define CONST_GLOBAL const
#define OUT_OF_LINE

// Lane types (cpu/lanes.h): per-pixel values. A GPU thread is one pixel, so each is its
// scalar type here; the CPU build makes them registers of several pixels.
#define lfloat float
#define lint int
#define luint uint
#define lbool bool
#define lvec2 vec2
#define lvec3 vec3
#define lvec4 vec4

// Branch-free selection and uniform early-outs, as lane code spells them.
bool anyLane(bool b) { return b; }
float select(bool c, float a, float b) { return c ? a : b; }
int select(bool c, int a, int b) { return c ? a : b; }
vec3 select(bool c, vec3 a, vec3 b) { return c ? a : b; }
// Added for SSDO and the blur.
vec4 select(bool c, vec4 a, vec4 b) { return c ? a : b; }
float uniformValue(float x) { return x; } // a value equal in every lane, as a uniform
// Added for HBAO's visibility bitmask.
uint select(bool c, uint a, uint b) { return c ? a : b; }
uint lanesOr(uint a) { return a; } // the bits set in any lane: a pixel's own
