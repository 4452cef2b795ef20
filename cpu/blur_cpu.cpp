#include "cpu/blur_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

#include <memory>

namespace obscura::cpu {

namespace {

// A scratch plane of w x h texels of `like`'s channels, for the pass between the two (left
// uninitialised: the first pass writes every texel); invalid for invalid.
MutablePlane scratchLike(const MutablePlane& like, int w, int h, std::unique_ptr<float[]>& storage) {
    if (!like.valid()) return MutablePlane{};
    const int n = like.channels;
    storage.reset(new float[(size_t)w * h * n]);
    return MutablePlane{storage.get(), w, h, n, n, (std::ptrdiff_t)w * n};
}

} // namespace

void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane first,
             MutablePlane second, int radius, int threads) {
    if (radius <= 0) return;
    std::unique_ptr<float[]> scratch1, scratch2;
    const BlurTarget signal{first, second}, tmp{scratchLike(first, p.width, p.height, scratch1),
                                                   scratchLike(second, p.width, p.height, scratch2)};
    const auto tileFn = cpuKernelsFor({depth, normal, ConstPlane(first), ConstPlane(tmp.first)}).blurTile;
    auto pass = [&](const BlurTarget& src, const BlurTarget& dst, glm::ivec2 axis) {
        const BlurSource from{ConstPlane(src.first), ConstPlane(src.second)};
        parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                         [&](const Box2i& tile) { tileFn(p, depth, normal, from, dst, axis, radius, tile); });
    };
    pass(signal, tmp, glm::ivec2(1, 0));
    pass(tmp, signal, glm::ivec2(0, 1));
}

void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane signal, int radius,
             int threads) {
    runBlur(p, depth, normal, signal, MutablePlane{}, radius, threads);
}

} // namespace obscura::cpu
