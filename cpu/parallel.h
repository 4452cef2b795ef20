// Tiles over all cores: the CPU backend's only scheduling primitive.
#pragma once
#include "core/image.h"

#include <functional>

namespace obscura::cpu {

// 0 (or less) means every hardware thread.
int resolveThreads(int requested);

// Calls fn(tile) for tiles of `tileSize` covering `region`, on `threads` threads.
// Tiles are handed out dynamically, so uneven work (sky, radius) balances itself.
void parallelForTiles(const Box2i& region, int tileSize, int threads, const std::function<void(const Box2i&)>& fn);

} // namespace obscura::cpu
