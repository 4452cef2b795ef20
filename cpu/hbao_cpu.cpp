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


} // namespace obscura::cpu
