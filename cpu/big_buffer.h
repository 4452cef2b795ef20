// Large scratch buffers of floats (hundreds of MB for a disc pyramid at 1080p): allocated on
// 2 MiB boundaries and offered to the kernel as transparent huge pages, so touching them the
// first time costs one page fault per 2 MiB instead of one per 4 KiB. The last one freed is
// kept for the next frame of the process (a farm task's chunk of frames, a Dask worker, a
// host's renders) until the library is unloaded: fresh pages come zeroed by the kernel, which
// cost a disc frame at 1080p a tenth of its time or more (on a virtual machine, the host backs
// them on first touch too).
#pragma once
#include <cstddef>
#include <cstdlib>
#include <memory>

namespace obscura::cpu {

struct FreeBuffer {
    std::size_t bytes = 0;  // 0: the empty request's malloc'ed byte, freed at once
    void operator()(float* p) const;
};
using BigFloats = std::unique_ptr<float[], FreeBuffer>;

// `count` floats, not zeroed; throws std::bad_alloc when the memory is not there.
BigFloats allocateBigFloats(std::size_t count);

} // namespace obscura::cpu
