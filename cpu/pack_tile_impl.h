// Body of packSourceTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/shared_exponent.glsl's packing of the bounce source, and kernels/normal_word.glsl's of
// its surface's normal (in view space, facing the eye) in a plane of its own, a row of
// OBSCURA_LANES texels at a time.
#include "cpu/lane_kernel.h"

namespace obscura::glsl {
namespace {

struct PackCpuKernel {
    KernelParams P;
#include "kernels/shared_exponent.glsl"
#include "kernels/view_ray.glsl"
#include "kernels/normal_word.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

void packSourceTile(ConstPlane rgb, ConstPlane albedo, ConstPlane normal, const KernelParams& p, MutablePlane words,
                    int channel, MutablePlane facing, const Box2i& tile) {
    glsl::PackCpuKernel k;
    k.P = p;
    const glsl::LanePlane colour(rgb, true), sender(albedo, true), facingNormal(normal, true);
    const bool times = albedo.valid(), normals = normal.valid();
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
            if (!normals) continue;
            const glsl::lvec3 n = glm::mat3(p.normalToView) * facingNormal.gather3(xs, glsl::lint(y), use);
            const glsl::lvec2 centre(glsl::lfloat(xs) + float(p.originX) + 0.5f, float(y + p.originY) + 0.5f);
            const glsl::luint word = k.packNormalWord(n, k.viewVector(k.viewRay(centre)));
            glsl::storeRow(facing.at(x, y), facing.xStride, count, glsl::uintBitsToFloat(word));
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
