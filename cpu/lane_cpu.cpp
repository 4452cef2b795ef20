#include "lane_cpu.h"

#include "cpu/parallel.h"

namespace obscura::cpu {

namespace {
const IsaKernels& kernelsFor(const std::string& isa, std::initializer_list<ConstPlane> planes) {
    return isa.empty() ? cpuKernelsFor(planes) : cpuKernelsNamed(isa, planes);
}
} // namespace

const char* laneIsa() { return cpuIsa(); }

std::vector<std::string> laneIsas() { return cpuIsas(); }

HbaoTileFn hbaoTileFor(const std::string& isa) { return cpuKernelsNamed(isa).hbaoTile; }

Image hbaoEdgeTexels(ConstPlane depth, ConstPlane normal) {
    const int w = depth.width, h = depth.height;
    Image edges(2 * (w + h), 1, 4);
    float* record = edges.pixels.data();
    const auto put = [&](int x, int y) {
        record[0] = *depth.at(x, y);
        for (int c = 0; c < 3; ++c) record[1 + c] = normal.at(x, y)[c];
        record += 4;
    };
    for (int x = 0; x < w; ++x) put(x, 0);
    for (int x = 0; x < w; ++x) put(x, h - 1);
    for (int y = 0; y < h; ++y) put(0, y);
    for (int y = 0; y < h; ++y) put(w - 1, y);
    return edges;
}

namespace {
// HBAO, with deep layers when `deep` is valid.
void runHbaoWith(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                 int threads, const std::string& isa) {
    const IsaKernels& k = kernelsFor(isa, {depth, normal, deep});
    const Image edges = p.hbaoBorder != 0 ? hbaoEdgeTexels(depth, normal) : Image();
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads, [&](const Box2i& tile) {
        if (deep.valid()) k.hbaoDeepTile(p, depth, normal, deep, edges.view(), ao, tile);
        else k.hbaoTile(p, depth, normal, edges.view(), ao, tile);
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

void runHbaoGi(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
               ConstPlane facing, MutablePlane ao, MutablePlane gi, int threads, const std::string& isa) {
    const IsaKernels& k = kernelsFor(isa, {depth, normal, deep, radiance, facing});
    const Image edges = p.hbaoBorder != 0 ? hbaoEdgeTexels(depth, normal) : Image();
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kLaneTileWidth, kLaneTileHeight, threads, [&](const Box2i& tile) {
        k.hbaoGiTile(p, depth, normal, deep, radiance, facing, edges.view(), ao, gi, tile);
    });
}

} // namespace obscura::cpu
