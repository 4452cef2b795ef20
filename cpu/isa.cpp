#include "cpu/isa.h"

#include <climits>
#include <cstdlib>
#include <stdexcept>
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

const std::vector<IsaChoice>& usable() {
    static const std::vector<IsaChoice> all = usableIsas();
    return all;
}

const IsaChoice* find(const std::string& name) {
    const std::vector<IsaChoice>& all = usable();
    if (name.empty()) return &all.back();
    for (const IsaChoice& c : all)
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

std::vector<std::string> cpuIsas() {
    std::vector<std::string> names;
    for (const IsaChoice& c : usable()) names.push_back(c.name);
    return names;
}

const IsaKernels& cpuKernelsNamed(const std::string& name, std::initializer_list<ConstPlane> planes) {
    const IsaChoice* c = name.empty() ? nullptr : find(name);
    if (!c) throw std::invalid_argument("this CPU cannot run the kernels built for '" + name + "'");
    for (const ConstPlane& p : planes)
        if (!fitsInt32(p)) return scalar::kernels;
    return *c->kernels;
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
