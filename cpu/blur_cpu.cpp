#include "cpu/blur_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

#include <vector>

namespace obscura::cpu {

void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane signal, int radius,
             int threads) {
    if (radius <= 0) return;
    const int n = signal.channels;
    std::vector<float> scratch((size_t)p.width * p.height * n);
    MutablePlane tmp{scratch.data(), p.width, p.height, n, n, (std::ptrdiff_t)p.width * n};
    const auto tileFn = cpuKernelsFor({depth, normal, ConstPlane(signal), ConstPlane(tmp)}).blurTile;
    auto pass = [&](ConstPlane src, MutablePlane dst, glm::ivec2 axis) {
        parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                         [&](const Box2i& tile) { tileFn(p, depth, normal, src, dst, axis, radius, tile); });
    };
    pass(signal, tmp, glm::ivec2(1, 0));
    pass(tmp, signal, glm::ivec2(0, 1));
}

} // namespace obscura::cpu
