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

void parallelForTiles(const Box2i& region, int tileWidth, int tileHeight, int threads,
                      const std::function<void(const Box2i&)>& fn) {
    if (region.empty()) return;
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
            // The host's check, on its own thread only (base/cancel.h); the others see `next` run out.
            if (std::this_thread::get_id() == caller && cancelRequested()) {
                cancelled = true;
                next = tileCount;
                break;
            }
            const int tx = i % tilesX, ty = i / tilesX;
            Box2i tile{region.x0 + tx * tileWidth, region.y0 + ty * tileHeight, 0, 0};
            tile.x1 = std::min(tile.x0 + tileWidth, region.x1);
            tile.y1 = std::min(tile.y0 + tileHeight, region.y1);
            try {
                fn(tile);
            } catch (...) {
                std::lock_guard<std::mutex> lock(failureMutex);
                if (!failure) failure = std::current_exception();
                next = tileCount; // stop handing out work
            }
        }
    };
    const int n = std::max(1, std::min(resolveThreads(threads), tileCount));
    std::vector<std::thread> pool;
    for (int t = 1; t < n; ++t) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();
    if (failure) std::rethrow_exception(failure);
    if (cancelled) throw Cancelled();
}

} // namespace obscura::cpu
