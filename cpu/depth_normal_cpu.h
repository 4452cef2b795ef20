// CPU backend of the normals reconstructed from the depth (kernels/depth_normal.glsl).
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

namespace obscura::cpu {

// View-space unit normals (3 channels, p.width x p.height) of the depth's surfaces; (0, 0, 0)
// where a texel is not a surface.
void runDepthNormals(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, int threads);

} // namespace obscura::cpu
