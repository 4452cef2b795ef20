// The kernels' parameter blocks as C++ types (the same text the GPU compiles as GLSL).
#pragma once
#include "kernels/glsl_cpp.h"

namespace obscura::glsl {
#include "kernels/hbao_params.glsl"
static_assert(sizeof(HbaoParams) == 64 + 6 * 16, "HbaoParams must match its std140 layout");
} // namespace obscura::glsl
