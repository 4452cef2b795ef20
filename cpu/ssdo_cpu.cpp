#include "cpu/ssdo_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

namespace obscura::cpu {

void runSsdo(const glsl::KernelParams& p, const SsdoPlanes& in, MutablePlane directional, MutablePlane indirect,
             MutablePlane ao, int threads) {
    const auto tileFn = cpuKernelsFor({in.depth, in.normal, in.radiance, in.albedo, in.environment}).ssdoTile;
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, in, directional, indirect, ao, tile); });
}

} // namespace obscura::cpu
