// Tiles over all cores: the CPU backend's only scheduling primitive.
#pragma once
#include "base/image.h"

#include <functional>

namespace obscura::cpu {

// 0 (or less) means every hardware thread.
int resolveThreads(int requested);

// Calls fn(tile) for tiles of tileWidth x tileHeight covering `region`, on `threads` threads at
// most: the calling thread, and others from one budget of the cores less one that calls running
// at once share (an OpenFX host's renders in parallel).
// Tiles are handed out dynamically, so uneven work (sky, radius) balances itself. Throws
// Cancelled when the calling thread's cancel check (base/cancel.h) says stop between its tiles.
void parallelForTiles(const Box2i& region, int tileWidth, int tileHeight, int threads,
                      const std::function<void(const Box2i&)>& fn);
// Square tiles.
inline void parallelForTiles(const Box2i& region, int tileSize, int threads, const std::function<void(const Box2i&)>& fn) {
    parallelForTiles(region, tileSize, tileSize, threads, fn);
}

} // namespace obscura::cpu
