#include "hbao_cpu.h"

#include "cpu/parallel.h"

#include <vector>

namespace obscura::glsl {

// The backend side of the kernels' contract: loads from strided planes.
struct CpuPasses {
    HbaoParams P;
    ConstPlane depthPlane, normalPlane, aoPlane;

    float loadDepth(ivec2 t) const { return *depthPlane.at(t.x, t.y); }
    vec3 loadNormal(ivec2 t) const {
        const float* n = normalPlane.at(t.x, t.y);
        return vec3(n[0], n[1], n[2]);
    }
    float loadAo(ivec2 t) const { return *aoPlane.at(t.x, t.y); }
};

struct HbaoCpuKernel : CpuPasses {
#include "kernels/common.glsl"
#include "kernels/hbao.glsl"
};

struct BlurCpuKernel : CpuPasses {
#include "kernels/common.glsl"
#include "kernels/blur.glsl"
};

} // namespace obscura::glsl

namespace obscura::cpu {

namespace {
constexpr int kTile = 32; // small tiles: cache-friendly and balance sky/non-sky work across threads
}

void runHbao(const HbaoParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads) {
    const Box2i region{0, 0, p.width, p.height};
    parallelForTiles(region, kTile, threads, [&](const Box2i& tile) {
        glsl::HbaoCpuKernel k;
        k.P = p;
        k.depthPlane = depth;
        k.normalPlane = normal;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) *ao.at(x, y) = k.hbaoPixel(glm::ivec2(x, y));
    });
}

void runBlur(const HbaoParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int radius, int threads) {
    if (radius <= 0) return;
    std::vector<float> scratch((size_t)p.width * p.height);
    MutablePlane tmp{scratch.data(), p.width, p.height, 1, 1, p.width};
    const Box2i region{0, 0, p.width, p.height};
    auto pass = [&](ConstPlane src, MutablePlane dst, glm::ivec2 axis) {
        parallelForTiles(region, kTile, threads, [&](const Box2i& tile) {
            glsl::BlurCpuKernel k;
            k.P = p;
            k.depthPlane = depth;
            k.normalPlane = normal;
            k.aoPlane = src;
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) *dst.at(x, y) = k.blurPixel(glm::ivec2(x, y), axis, radius);
        });
    };
    ConstPlane aoIn{ao.data, ao.width, ao.height, 1, ao.xStride, ao.yStride};
    pass(aoIn, tmp, glm::ivec2(1, 0));
    pass(ConstPlane{tmp.data, tmp.width, tmp.height, 1, 1, tmp.yStride}, ao, glm::ivec2(0, 1));
}

} // namespace obscura::cpu
