#include "hbao_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

namespace obscura::cpu {

const char* hbaoIsa() { return cpuIsa(); }

void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads) {
    const auto tileFn = cpuKernelsFor({depth, normal}).hbaoTile;
    const Box2i region{0, 0, p.width, p.height};
    parallelForTiles(region, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, depth, normal, ao, tile); });
}

} // namespace obscura::cpu
