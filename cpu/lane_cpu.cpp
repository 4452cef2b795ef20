#include "lane_cpu.h"

#include "cpu/parallel.h"

namespace obscura::cpu {

namespace {
LaneTileFn entryOf(const IsaKernels& k, LaneKernel kernel) { return kernel == LaneKernel::Hbao ? k.hbaoTile : k.ssaoTile; }
} // namespace

const char* laneIsa() { return cpuIsa(); }

std::vector<std::string> laneIsas() { return cpuIsas(); }

LaneTileFn laneTileFor(LaneKernel kernel, const std::string& isa) { return entryOf(cpuKernelsNamed(isa), kernel); }

void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa) {
    const IsaKernels& k = isa.empty() ? cpuKernelsFor({depth, normal}) : cpuKernelsNamed(isa, {depth, normal});
    const LaneTileFn tileFn = entryOf(k, kernel);
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, depth, normal, ao, tile); });
}

void runHbaoDeep(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa) {
    const IsaKernels& k = isa.empty() ? cpuKernelsFor({depth, normal, deep}) : cpuKernelsNamed(isa, {depth, normal, deep});
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { k.hbaoDeepTile(p, depth, normal, deep, ao, tile); });
}

} // namespace obscura::cpu
