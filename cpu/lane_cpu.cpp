#include "lane_cpu.h"

#include "cpu/parallel.h"

#include <climits>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

namespace obscura::cpu {

namespace {
struct IsaChoice {
    const char* name;
    LaneTileFn hbao, ssao;
};

#define OBSCURA_ISA_CHOICE(label, isa) IsaChoice{label, &isa::hbaoTile, &isa::ssaoTile}

// Every instantiation this CPU runs, narrowest first (the AVX builds exist only where the
// compiler targets them, see CMakeLists.txt).
std::vector<IsaChoice> usableIsas() {
    std::vector<IsaChoice> usable = {OBSCURA_ISA_CHOICE("scalar", scalar), OBSCURA_ISA_CHOICE("baseline", baseline)};
#if defined(OBSCURA_HAVE_X86_64_V3)
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2");
    if (v3) usable.push_back(OBSCURA_ISA_CHOICE("x86-64-v3", x86_64_v3));
#if defined(OBSCURA_HAVE_X86_64_V4)
    if (v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
        usable.push_back(OBSCURA_ISA_CHOICE("x86-64-v4", x86_64_v4));
#endif
#endif
    return usable;
}

// The widest, unless OBSCURA_CPU_ISA=scalar|baseline|x86-64-v3|x86-64-v4 names another this
// CPU runs (to test or time it).
const IsaChoice& chosenIsa() {
    static const IsaChoice choice = [] {
        const std::vector<IsaChoice> usable = usableIsas();
        if (const char* forced = std::getenv("OBSCURA_CPU_ISA"))
            for (const IsaChoice& c : usable)
                if (std::string(forced) == c.name) return c;
        return usable.back();
    }();
    return choice;
}

// The lane kernels address texels with 32-bit offsets (one gather instruction each).
bool fitsInt32(const ConstPlane& p) {
    const long long extent = (long long)(p.width - 1) * std::llabs(p.xStride) +
                             (long long)(p.height - 1) * std::llabs(p.yStride) + p.channels;
    return extent < INT_MAX;
}

LaneTileFn entryOf(const IsaChoice& c, LaneKernel kernel) { return kernel == LaneKernel::Hbao ? c.hbao : c.ssao; }
} // namespace

const char* laneIsa() { return chosenIsa().name; }

std::vector<std::string> laneIsas() {
    std::vector<std::string> names;
    for (const IsaChoice& c : usableIsas()) names.push_back(c.name);
    return names;
}

LaneTileFn laneTileFor(LaneKernel kernel, const std::string& isa) {
    for (const IsaChoice& c : usableIsas())
        if (isa == c.name) return entryOf(c, kernel);
    throw std::invalid_argument("this CPU cannot run the lane kernels built for '" + isa + "'");
}

void runLaneKernel(LaneKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                   int threads, const std::string& isa) {
    LaneTileFn tileFn = isa.empty() ? entryOf(chosenIsa(), kernel) : laneTileFor(kernel, isa);
    if (!fitsInt32(depth) || !fitsInt32(normal)) tileFn = entryOf(usableIsas().front(), kernel); // beyond 2^31 floats
    const Box2i region{0, 0, p.width, p.height};
    parallelForTiles(region, kLaneTileWidth, kLaneTileHeight, threads,
                     [&](const Box2i& tile) { tileFn(p, depth, normal, ao, tile); });
}

} // namespace obscura::cpu
