#include "lane_cpu.h"

#include "cpu/parallel.h"

namespace obscura::cpu {

namespace {
LaneTileFn entryOf(const IsaKernels& k, LaneKernel kernel) { return kernel == LaneKernel::Hbao ? k.hbaoTile : k.ssaoTile; }

const IsaKernels& kernelsFor(const std::string& isa, std::initializer_list<ConstPlane> planes) {
    return isa.empty() ? cpuKernelsFor(planes) : cpuKernelsNamed(isa, planes);
}
} // namespace

const char* laneIsa() { return cpuIsa(); }

std::vector<std::string> laneIsas() { return cpuIsas(); }

LaneTileFn laneTileFor(LaneKernel kernel, const std::string& isa) { return entryOf(cpuKernelsNamed(isa), kernel); }

namespace {
// HBAO, with deep layers when `deep` is valid.
void runHbaoWith(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa) {
    const IsaKernels& k = kernelsFor(isa, {depth, normal, deep});
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads, [&](const Box2i& tile) {
        if (deep.valid()) k.hbaoDeepTile(p, depth, normal, deep, ao, tile);
        else k.hbaoTile(p, depth, normal, ao, tile);
    });
}
} // namespace

void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa) {
    if (kernel == LaneKernel::Hbao) return runHbaoWith(p, depth, normal, ConstPlane{}, ao, threads, isa);
    const IsaKernels& k = kernelsFor(isa, {depth, normal});
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { k.ssaoTile(p, depth, normal, ao, tile); });
}

void runHbaoDeep(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa) {
    runHbaoWith(p, depth, normal, deep, ao, threads, isa);
}

} // namespace obscura::cpu
