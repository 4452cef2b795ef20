#include "hbao_cpu.h"

#include "cpu/hbao_tile.h"
#include "cpu/parallel.h"

#include <cstdlib>
#include <string>
#include <vector>

// The baseline (x86-64 / any target) instantiation of the HBAO kernel.
#define OBSCURA_ISA baseline
#include "cpu/hbao_tile_impl.h"
#undef OBSCURA_ISA

namespace obscura::glsl {

// The backend side of the kernels' contract: loads from strided planes.
struct CpuPasses {
    KernelParams P;
    ConstPlane depthPlane, normalPlane, aoPlane;

    float loadDepth(ivec2 t) const { return *depthPlane.at(t.x, t.y); }
    vec3 loadNormal(ivec2 t) const {
        const float* n = normalPlane.at(t.x, t.y);
        return vec3(n[0], n[1], n[2]);
    }
    vec4 loadSignal(ivec2 t) const { return vec4(*aoPlane.at(t.x, t.y), 0.0f, 0.0f, 0.0f); }
};

struct BlurCpuKernel : CpuPasses {
#include "kernels/common.glsl"
#include "kernels/blur.glsl"
};

} // namespace obscura::glsl

namespace obscura::cpu {

namespace {
constexpr int kTile = 32; // small tiles: cache-friendly and balance sky/non-sky work across threads

// The widest instantiation of the kernel this CPU runs. The x86-64-v3 one is built only
// where the compiler can target it (OBSCURA_HAVE_X86_64_V3, see CMakeLists.txt).
// OBSCURA_CPU_ISA=baseline forces the baseline one (to test or time it on any machine).
HbaoTileFn selectHbaoTile() {
#if defined(OBSCURA_HAVE_X86_64_V3)
    const char* forced = std::getenv("OBSCURA_CPU_ISA");
    if (forced && std::string(forced) == "baseline") return &baseline::hbaoTile;
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2"))
        return &x86_64_v3::hbaoTile;
#endif
    return &baseline::hbaoTile;
}
} // namespace

void runHbao(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int threads) {
    static const HbaoTileFn hbaoTile = selectHbaoTile();
    const Box2i region{0, 0, p.width, p.height};
    parallelForTiles(region, kTile, threads, [&](const Box2i& tile) { hbaoTile(p, depth, normal, ao, tile); });
}

void runBlur(const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int radius, int threads) {
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
