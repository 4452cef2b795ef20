#include "cpu/isa.h"

#include <climits>
#include <cstdlib>
#include <vector>

namespace obscura::cpu {

namespace {

struct IsaChoice {
    const char* name;
    const IsaKernels* kernels;
};

// The instantiations this CPU runs, narrowest first (the AVX builds exist only where the
// compiler targets them, see CMakeLists.txt).
std::vector<IsaChoice> usableIsas() {
    std::vector<IsaChoice> usable = {{"scalar", &scalar::kernels}, {"baseline", &baseline::kernels}};
#if defined(OBSCURA_HAVE_X86_64_V3)
    __builtin_cpu_init();
    const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2");
    if (v3) usable.push_back({"x86-64-v3", &x86_64_v3::kernels});
#if defined(OBSCURA_HAVE_X86_64_V4)
    if (v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl"))
        usable.push_back({"x86-64-v4", &x86_64_v4::kernels});
#endif
#endif
    return usable;
}

const IsaChoice* find(const std::string& name) {
    static const std::vector<IsaChoice> usable = usableIsas();
    if (name.empty()) return &usable.back();
    for (const IsaChoice& c : usable)
        if (name == c.name) return &c;
    return nullptr;
}

const IsaChoice& automatic() {
    static const IsaChoice choice = [] {
        const char* forced = std::getenv("OBSCURA_CPU_ISA");
        const IsaChoice* c = forced ? find(forced) : nullptr;
        return c ? *c : *find("");
    }();
    return choice;
}

const IsaChoice* gForced = nullptr;

const IsaChoice& chosen() { return gForced ? *gForced : automatic(); }

// The lane kernels address texels with 32-bit offsets (one gather instruction each).
bool fitsInt32(const ConstPlane& p) {
    if (!p.valid()) return true;
    const long long extent = (long long)(p.width - 1) * std::llabs(p.xStride) +
                             (long long)(p.height - 1) * std::llabs(p.yStride) + p.channels;
    return extent < INT_MAX;
}

} // namespace

const IsaKernels& cpuKernels() { return *chosen().kernels; }
const char* cpuIsa() { return chosen().name; }

const IsaKernels& cpuKernelsFor(std::initializer_list<ConstPlane> planes) {
    for (const ConstPlane& p : planes)
        if (!fitsInt32(p)) return scalar::kernels; // beyond 2^31 floats
    return cpuKernels();
}

bool forceCpuIsa(const std::string& name) {
    if (name.empty()) {
        gForced = nullptr;
        return true;
    }
    const IsaChoice* c = find(name);
    if (c) gForced = c;
    return c != nullptr;
}

} // namespace obscura::cpu
