#include "cpu/depth_normal_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

namespace obscura::cpu {

void runDepthNormals(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, int threads) {
    const auto tileFn = cpuKernelsFor({depth, ConstPlane(normal)}).depthNormalTile;
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, depth, normal, tile); });
}

} // namespace obscura::cpu
