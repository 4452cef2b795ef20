// HBAO's frame border, clamp or tangent (--border; kernels/hbao.glsl, continuedDepth): the depth
// past the buffer's edge is written once around a copy of the depth plane, as far as any sample
// reaches, so the march reads a texel past the edge as it reads one inside (one load, no
// bounds test) instead of finding the edge texel's plane again at every sample.
#pragma once
#include "core/image.h"
#include "cpu/big_buffer.h"
#include "cpu/isa.h"
#include "cpu/kernel_params.h"

namespace obscura::cpu {

// The largest screen radius in pixels of HBAO's sphere over the buffer's surface texels (the
// nearest surface's), capped by p.maxRadiusPixels, as kernels/hbao.glsl computes it; 0 without surfaces.
float hbaoReachPixels(const glsl::KernelParams& p, ConstPlane depth);

struct BorderedDepth {
    BorderedDepth() = default;
    // `depth` points into `storage`: moving keeps it valid, a copy would not.
    BorderedDepth(BorderedDepth&&) = default;
    BorderedDepth& operator=(BorderedDepth&&) = default;
    BorderedDepth(const BorderedDepth&) = delete;
    BorderedDepth& operator=(const BorderedDepth&) = delete;
    glsl::KernelParams params; // p, with the depth box (depthX0 ..) the depth plane below holds
    BigFloats storage;         // the box's depths, every one written (none when p.hbaoBorder is 0)
    ConstPlane box;            // `storage` as a plane from the box's corner (invalid without a border)
    ConstPlane depth;          // addressed in buffer coordinates: texel (0, 0) is the buffer's; the
                               // caller's plane when there is no border
};

// The box of texels p's depth buffer holds (depthX0 ..), in buffer coordinates; the buffer
// itself where p leaves it unset (parameters made by hand).
inline Box2i depthBoxOf(const glsl::KernelParams& p) {
    const Box2i box{p.depthX0, p.depthY0, p.depthX1, p.depthY1};
    return box.empty() ? Box2i{0, 0, p.width, p.height} : box;
}

// The depth plane HBAO reads: the caller's, or for border clamp/tangent a copy with the border
// written past each edge as far as that edge's samples reach (the kernels of `k`, on `threads`).
BorderedDepth continueBorder(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, int threads,
                             const IsaKernels& k);

} // namespace obscura::cpu
