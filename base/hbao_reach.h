// How far HBAO's samples reach on the screen: the apron a backend that tiles the frame reads
// around each tile (gpu/gl_backend.cpp), from the parameter block and the depth alone.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

namespace obscura {

// The largest screen radius in pixels of HBAO's sphere over the buffer's surface texels (the
// nearest surface's), capped by p.maxRadiusPixels, as kernels/hbao.glsl computes it; 0 without surfaces.
float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth);

} // namespace obscura
