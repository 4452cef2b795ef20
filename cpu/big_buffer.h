// Large scratch buffers of floats (hundreds of MB for a disc pyramid at 1080p): allocated on
// 2 MiB boundaries and offered to the kernel as transparent huge pages, so touching them the
// first time costs one page fault per 2 MiB instead of one per 4 KiB.
#pragma once
#include <cstddef>
#include <cstdlib>
#include <memory>

namespace obscura::cpu {

struct FreeBuffer {
    void operator()(float* p) const { std::free(p); }
};
using BigFloats = std::unique_ptr<float[], FreeBuffer>;

// `count` floats, not zeroed; throws std::bad_alloc when the memory is not there.
BigFloats allocateBigFloats(std::size_t count);

} // namespace obscura::cpu
