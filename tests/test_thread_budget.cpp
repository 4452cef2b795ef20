// Calls of the CPU's scheduler running at once (an OpenFX host rendering several tiles or frames
// in parallel, Python threads each on a frame) share the cores: each has its own thread, and the
// others come from one budget of the cores less one, so no more than cores + (calls - 1) threads
// work at any time however many threads each call asks for.
#include "cpu/parallel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <thread>
#include <vector>

using namespace obscura;

namespace {

// Tiles that each hold their thread a while, counting how many run at once and on which threads.
struct Occupancy {
    std::atomic<int> now{0}, most{0};
    std::mutex mutex;
    std::set<std::thread::id> threads;
    void tile() {
        const int n = ++now;
        int seen = most.load();
        while (n > seen && !most.compare_exchange_weak(seen, n)) {
        }
        {
            std::lock_guard<std::mutex> lock(mutex);
            threads.insert(std::this_thread::get_id());
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        --now;
    }
};

} // namespace

TEST(ThreadBudget, CallsAtOnceShareTheCores) {
    const int cores = cpu::resolveThreads(0);
    const int calls = 3;
    Occupancy o;
    std::vector<std::thread> callers;
    for (int c = 0; c < calls; ++c)
        callers.emplace_back([&] {
            // Each asks for twice the cores.
            cpu::parallelForTiles(Box2i{0, 0, 64, 64}, 8, 2 * cores, [&](const Box2i&) { o.tile(); });
        });
    for (std::thread& t : callers) t.join();
    EXPECT_LE(o.most.load(), cores + calls - 1);
    EXPECT_GE(o.most.load(), std::min(cores, 2));  // and they do run in parallel
}

// Alone, a call gets every core it asks for, up to the cores; the budget is whole again after it.
TEST(ThreadBudget, ACallAloneTakesTheCores) {
    const int cores = cpu::resolveThreads(0);
    for (int round = 0; round < 2; ++round) {
        Occupancy o;
        cpu::parallelForTiles(Box2i{0, 0, 256, 64}, 8, 0, [&](const Box2i&) { o.tile(); });
        EXPECT_EQ((int)o.threads.size(), cores) << "round " << round;
    }
}
