#include "cpu/big_buffer.h"

#include <mutex>
#include <new>
#include <sys/mman.h>

namespace obscura::cpu {
namespace {

constexpr std::size_t kHugePage = std::size_t(2) << 20;

// The one large buffer kept after it was freed. A request takes it when it fits and needs at
// least half of it, so a small scratch plane does not pin a pyramid's memory.
std::mutex keptLock;
float* kept = nullptr;
std::size_t keptBytes = 0;

// Frees the buffer kept for the next frame, if any.
void releaseKept() {
    std::lock_guard<std::mutex> hold(keptLock);
    std::free(kept);
    kept = nullptr;
    keptBytes = 0;
}

// The kept buffer goes when the library does: a host that unloads the OpenFX plugin between
// renders (LeakSanitizer found it: 2 MiB each time) and gets no frame from it afterwards.
struct ReleaseAtUnload {
    ~ReleaseAtUnload() { releaseKept(); }
} releaseAtUnload;

} // namespace

void FreeBuffer::operator()(float* p) const {
    if (bytes == 0) {
        std::free(p);
        return;
    }
    std::lock_guard<std::mutex> hold(keptLock);
    std::free(kept);
    kept = p;
    keptBytes = bytes;
}

BigFloats allocateBigFloats(std::size_t count) {
    const std::size_t bytes = count * sizeof(float);
    // Small ones too take whole huge pages and are kept: malloc's pages come and go with its
    // trimming, and at 320 x 240 fresh ones cost HBAO's light as much as its packing.
    if (bytes == 0) {
        float* p = static_cast<float*>(std::malloc(1));
        if (!p) throw std::bad_alloc();
        return BigFloats(p, FreeBuffer{0});
    }
    // aligned_alloc wants a multiple of the alignment.
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    {
        std::lock_guard<std::mutex> hold(keptLock);
        if (kept && keptBytes >= rounded && keptBytes / 2 <= rounded) {
            BigFloats reused(kept, FreeBuffer{keptBytes});
            kept = nullptr;
            keptBytes = 0;
            return reused;
        }
    }
    // Not reusable: its memory goes back before more is taken.
    releaseKept();
    float* p = static_cast<float*>(std::aligned_alloc(kHugePage, rounded));
    if (!p) throw std::bad_alloc();
    // Advice only: where huge pages are off, or this is not Linux, it fails and nothing changes.
    (void)madvise(p, rounded, MADV_HUGEPAGE);
    return BigFloats(p, FreeBuffer{rounded});
}

} // namespace obscura::cpu
