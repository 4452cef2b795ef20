// CPU side of disc AO (kernels/discs.glsl): the pyramid of elements, which both devices read,
// and the traversal over tiles on all cores with the widest instruction set (cpu/isa.h).
#pragma once
#include "cpu/big_buffer.h"
#include "base/image.h"
#include "base/kernel_params.h"

#include <memory>
#include <string>
#include <vector>

namespace obscura::cpu {

using glsl::KernelParams;

// Floats a texel (kernels/discs.glsl's DISC_CHANNELS): mean position (3), area, unit mean
// normal (3), visibility; the side wall's centre (3), area, unit normal (3), length, facing;
// a second element like the first (area 0: none).
constexpr int kDiscChannels = 24;
// Floats past the last plane, so a row of lanes may load 16 neighbouring texels of any plane.
constexpr int kDiscPad = 16;

// Level 0: one texel per pixel; level L: one per 2^L x 2^L block. Stored a plane per channel
// (kDiscChannels planes, `stride` floats apart, each holding every level at `offsets`): the
// lanes of a row read neighbouring nodes, so a channel's values for them lie together.
struct DiscPyramid {
    BigFloats data;  // not zeroed first: every texel of the stored levels is written
    size_t floats = 0;  // kDiscChannels * stride, plus kDiscPad
    size_t stride = 0;
    std::vector<int> offsets;  // texel offset of each stored level
    int width = 0, height = 0;
    float invF = 1.0f;     // p.invFx: node sizes in the world (mergeElements)
    bool orthographic = false;
};

// Builds the pyramid for the buffers p describes and fills p's disc fields: the level
// offsets and the top level T, the coarsest any pixel's window needs to cover R on the
// screen (p.maxRadiusPixels at most). Throws obscura::Error when
// the pyramid would not fit 32-bit texel indices.
DiscPyramid buildDiscPyramid(KernelParams& p, ConstPlane depth, ConstPlane normal, int threads);

// Channel 7 at level 0 becomes `ao` (each element's own first-pass AO: correction c), merged
// up the levels by area like the positions.
void setDiscVisibility(DiscPyramid& pyramid, ConstPlane ao, int threads);

// The traversal for every texel of `ao` (p.width x p.height), each receiver's hemisphere about
// its `normal` (the pass's); `isa` empty: the chosen one.
void runDiscs(const KernelParams& p, const DiscPyramid& pyramid, ConstPlane normal, MutablePlane ao, int threads,
              const std::string& isa = "");

} // namespace obscura::cpu
