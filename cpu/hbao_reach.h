// How far HBAO's samples reach on the screen, for hosts that tile the frame (gpu/gl_backend.cpp).
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"

namespace obscura::cpu {

// The largest screen radius in pixels of HBAO's sphere over the buffer's surface texels (the
// nearest surface's), capped by p.maxRadiusPixels, as kernels/hbao.glsl computes it; 0 without surfaces.
float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth);

} // namespace obscura::cpu
