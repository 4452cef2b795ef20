// CPU backend of the SSDO kernel (kernels/ssdo.glsl), in tiles over all cores.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

namespace obscura::cpu {

struct SsdoPlanes {
    ConstPlane depth, normal;  // as for HBAO
    ConstPlane radiance;       // bounce source, 3 channels (may be invalid when p.bounce == 0)
    ConstPlane albedo;         // 3 channels, or invalid: albedo 1
    ConstPlane environment;    // the prefiltered lat-long level, 3 channels, p.envWidth x p.envHeight
};

// Directional occlusion (3 channels), indirect (3 channels) and AO (1 channel), each p.width x p.height.
void runSsdo(const glsl::KernelParams& p, const SsdoPlanes& in, MutablePlane directional, MutablePlane indirect,
             MutablePlane ao, int threads);

} // namespace obscura::cpu
