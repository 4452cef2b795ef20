// CPU backend of the geometry-aware blur (kernels/blur.glsl): AO, DO or GI alike.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

namespace obscura::cpu {

// Blurs the 1..4-channel `signal` in place: a horizontal then a vertical pass.
void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane signal, int radius,
             int threads);
// Blurs `first` and `second` (4 channels together) in place with one set of weights: each the
// same as blurred alone, the depths and normals read once for both.
void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane first,
             MutablePlane second, int radius, int threads);

} // namespace obscura::cpu
