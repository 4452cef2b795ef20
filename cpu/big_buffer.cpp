#include "cpu/big_buffer.h"

#include <new>
#include <sys/mman.h>

namespace obscura::cpu {

BigFloats allocateBigFloats(std::size_t count) {
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    const std::size_t bytes = count * sizeof(float);
    if (bytes < kHugePage) {
        float* p = static_cast<float*>(std::malloc(bytes > 0 ? bytes : 1));
        if (!p) throw std::bad_alloc();
        return BigFloats(p);
    }
    // aligned_alloc wants a multiple of the alignment.
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    float* p = static_cast<float*>(std::aligned_alloc(kHugePage, rounded));
    if (!p) throw std::bad_alloc();
    // Advice only: where huge pages are off, or this is not Linux, it fails and nothing changes.
    (void)madvise(p, rounded, MADV_HUGEPAGE);
    return BigFloats(p);
}

} // namespace obscura::cpu
