// Body of packSourceTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/shared_exponent.glsl's packing of the bounce source, a row of OBSCURA_LANES texels at a time.
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct PackCpuKernel {
#include "kernels/shared_exponent.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

void packSourceTile(ConstPlane rgb, ConstPlane albedo, MutablePlane words, int channel, const Box2i& tile) {
    glsl::PackCpuKernel k;
    const glsl::LanePlane colour(rgb, true), sender(albedo, true);
    const bool times = albedo.valid();
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += OBSCURA_LANES) {
            const glsl::lint xs = lane + x;
            const glsl::lbool use = xs < glsl::lint(tile.x1);
            glsl::lvec3 c = colour.gather3(xs, glsl::lint(y), use);
            if (times) c = c * sender.gather3(xs, glsl::lint(y), use);
            const glsl::lfloat packed = glsl::uintBitsToFloat(k.packSharedExponent(c)); // the word's bits
            const int count = tile.x1 - x < OBSCURA_LANES ? tile.x1 - x : OBSCURA_LANES;
            glsl::storeRow(words.at(x, y) + channel, words.xStride, count, packed);
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
