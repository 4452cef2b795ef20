// How far HBAO's samples reach on the screen, for hosts that tile the frame (gpu/gl_backend.cpp).
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"

namespace obscura::cpu {

// The largest screen radius in pixels of HBAO's sphere over the buffer's surface texels (the
// nearest surface's), capped by p.maxRadiusPixels, as kernels/hbao.glsl computes it; 0 without surfaces.
float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth);

// The box of texels p's depth buffer holds (depthX0 ..), in buffer coordinates; the buffer
// itself where p leaves it unset (parameters made by hand).
inline Box2i depthBoxOf(const glsl::KernelParams& p) {
    const Box2i box{p.depthX0, p.depthY0, p.depthX1, p.depthY1};
    return box.empty() ? Box2i{0, 0, p.width, p.height} : box;
}

} // namespace obscura::cpu
