// GLSL side of the common subset (see kernels/glsl_cpp.h for the C++ side).
#define OUT(T) out T
#define INOUT(T) inout T
#define CONST_GLOBAL const
