#include "parallel.h"

#include "base/cancel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace obscura::cpu {

int resolveThreads(int requested) {
    if (requested > 0) return requested;
    unsigned hw = std::thread::hardware_concurrency();
    return hw > 0 ? (int)hw : 1;
}

namespace {

// Threads beyond each call's own come from one budget for the process, the cores less one: runs
// at once (an OpenFX host rendering several frames or tiles, Python threads each on a frame) share
// the cores instead of each starting a thread per core.
std::atomic<int>& spareThreads() {
    static std::atomic<int> spare{resolveThreads(0) - 1};
    return spare;
}

// Up to `wanted` threads of the budget, handed back when the call ends.
struct BorrowedThreads {
    int count = 0;
    explicit BorrowedThreads(int wanted) {
        int spare = spareThreads().load();
        while (spare > 0 && wanted > 0 && !spareThreads().compare_exchange_weak(spare, spare - std::min(spare, wanted))) {
        }
        count = std::max(0, std::min(spare, wanted));
    }
    ~BorrowedThreads() { spareThreads() += count; }
    BorrowedThreads(const BorrowedThreads&) = delete;
    BorrowedThreads& operator=(const BorrowedThreads&) = delete;
};

} // namespace

void parallelForTiles(const Box2i& region, int tileWidth, int tileHeight, int threads,
                      const std::function<void(const Box2i&)>& fn) {
    if (region.empty()) return;
    throwIfCancelled();  // every pass asks once at least, though the other threads take every tile
    const int tilesX = (region.width() + tileWidth - 1) / tileWidth;
    const int tilesY = (region.height() + tileHeight - 1) / tileHeight;
    const int tileCount = tilesX * tilesY;
    std::atomic<int> next{0};
    std::atomic<bool> cancelled{false};
    std::exception_ptr failure;
    std::mutex failureMutex;
    const std::thread::id caller = std::this_thread::get_id();
    auto worker = [&] {
        for (int i = next++; i < tileCount; i = next++) {
            const int tx = i % tilesX, ty = i / tilesX;
            Box2i tile{region.x0 + tx * tileWidth, region.y0 + ty * tileHeight, 0, 0};
            tile.x1 = std::min(tile.x0 + tileWidth, region.x1);
            tile.y1 = std::min(tile.y0 + tileHeight, region.y1);
            try {
                // The host's check, on its own thread only (base/cancel.h); the others see `next` run out.
                if (std::this_thread::get_id() == caller && cancelRequested()) {
                    cancelled = true;
                    next = tileCount;
                    break;
                }
                fn(tile);
            } catch (...) {
                std::lock_guard<std::mutex> lock(failureMutex);
                if (!failure) failure = std::current_exception();
                next = tileCount; // stop handing out work
            }
        }
    };
    const BorrowedThreads extra(std::min(resolveThreads(threads), tileCount) - 1);
    std::vector<std::thread> pool;
    {
        // Joined on every way out, an unwinding calling thread's too (a joinable thread's end terminates).
        struct JoinAll {
            std::vector<std::thread>& threads;
            ~JoinAll() {
                for (std::thread& t : threads) t.join();
            }
        } joinAll{pool};
        for (int t = 0; t < extra.count; ++t) pool.emplace_back(worker);
        worker();
    }
    if (failure) std::rethrow_exception(failure);
    if (cancelled) throw Cancelled();
}

} // namespace obscura::cpu
