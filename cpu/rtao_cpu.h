// Ray-traced AO against the mesh of the depth pass (method rtao), with Embree, on the CPU.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

namespace obscura::cpu {

struct RtaoOptions {
    int rays = 16;          // per traced texel, cosine- (or uniformly) distributed over the hemisphere
    float thickness = 0.0f; // extrusion away from the eye, world units (+inf: a height field); 0: a sheet
    int grid = 1;           // trace texels whose display coordinates are multiples of it; interpolate the rest
};

struct RtaoStats {
    long long triangles = 0, rays = 0;
    double meshSeconds = 0, bvhSeconds = 0, traceSeconds = 0;
};

// AO for every texel of `ao` (p.width x p.height). The weighting and falloff are p's. Each
// texel's rays depend on its display coordinates only, so the result is the same for any
// thread count; hits imaged beyond p.maxRadiusPixels of the texel are ignored, so a buffer
// cropped with an apron of that cap (plus 3 texels for the mesh, plus the grid) agrees with
// the whole frame inside the apron.
void runRtao(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, const RtaoOptions& o,
             int threads, RtaoStats* stats = nullptr);

} // namespace obscura::cpu
