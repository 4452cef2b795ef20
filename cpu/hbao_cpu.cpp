#include "hbao_cpu.h"

#include "cpu/isa.h"
#include "cpu/parallel.h"

namespace obscura::cpu {

namespace {
void runTiles(const IsaKernels& kernels, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
              int threads) {
    const auto tileFn = kernels.hbaoTile;
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, depth, normal, ao, tile); });
}
} // namespace

const char* hbaoIsa() { return cpuIsa(); }

void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads) {
    runTiles(cpuKernelsFor({depth, normal}), p, depth, normal, ao, threads);
}

void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads,
             const std::string& isa) {
    runTiles(cpuKernelsNamed(isa, {depth, normal}), p, depth, normal, ao, threads);
}

} // namespace obscura::cpu
