#include "lane_cpu.h"

#include "cpu/hbao_border.h"
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

void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa) {
    if (kernel == LaneKernel::Ssao) {
        const LaneTileFn tileFn = entryOf(kernelsFor(isa, {depth, normal}), kernel);
        parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                         [&](const Box2i& tile) { tileFn(p, depth, normal, ao, tile); });
        return;
    }
    // HBAO reads its depth with the border continued (cpu/hbao_border.h); the kernels are chosen
    // again for the bordered plane, whose offsets are larger.
    const BorderedDepth b = continueBorder(p, depth, normal, threads, kernelsFor(isa, {depth, normal}));
    const LaneTileFn tileFn = entryOf(kernelsFor(isa, {b.plane.view(), depth, normal}), kernel);
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(b.params, b.depth, normal, ao, tile); });
}

void runHbaoDeep(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa) {
    const BorderedDepth b = continueBorder(p, depth, normal, threads, kernelsFor(isa, {depth, normal, deep}));
    const IsaKernels& k = kernelsFor(isa, {b.plane.view(), depth, normal, deep});
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { k.hbaoDeepTile(b.params, b.depth, normal, deep, ao, tile); });
}

} // namespace obscura::cpu
