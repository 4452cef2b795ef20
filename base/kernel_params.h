// The kernels' parameter blocks as C++ types (the same text the GPU compiles as GLSL).
#pragma once
#include "kernels/glsl_cpp.h"

namespace obscura::glsl {
#include "kernels/kernel_params.glsl"
static_assert(sizeof(KernelParams) == 64 + 6 * 16 + 64 + 9 * 16 + 3 * 16 + 33 * 16 + 4 * 16 + 3 * 16, "KernelParams must match its std140 layout");
} // namespace obscura::glsl
