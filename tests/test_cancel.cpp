// A host's stop (base/cancel.h): the operator asks the calling thread's check between tiles, on
// the CPU and on every GL device, stops at the first "yes" with Cancelled, and without a check,
// or with one that never says stop, computes what it always does.
#include "base/cancel.h"
#include "core/operator.h"
#include "cpu/parallel.h"
#include "support/gl_devices.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

using namespace obscura;
using namespace obscura::test;

namespace {

constexpr int kW = 256, kH = 192;

Settings settingsOn(const std::string& device, const std::string& method) {
    Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, 0.8f);
    s.device = device;
    s.method = method;
    s.threads = 2;
    return s;
}

std::vector<std::string> devices() {
    std::vector<std::string> all{"cpu"};
    for (const std::string& d : glDevicesUnderTest()) all.push_back(d);
    return all;
}

// A check that says stop from its `stopAt`-th call on (0: never), counting its calls and threads.
struct CountingCheck {
    int stopAt = 0;
    std::atomic<int> calls{0};
    std::mutex mutex;
    std::set<std::thread::id> threads;
    CancelCheck check() {
        return [this] {
            {
                std::lock_guard<std::mutex> lock(mutex);
                threads.insert(std::this_thread::get_id());
            }
            const int n = ++calls;
            return stopAt > 0 && n >= stopAt;
        };
    }
};

} // namespace

TEST(Cancel, ACheckThatNeverStopsIsAskedAndChangesNothing) {
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(kW, kH), kW, kH);
    for (const std::string& device : devices()) {
        for (const char* method : {"hbao", "ssao", "discs", "ssdo"}) {
            const Settings s = settingsOn(device, method);
            const OperatorOutputs plain = runOperator(sb.inputs(), s);
            CountingCheck counter;
            OperatorOutputs checked;
            {
                const CancelScope scope(counter.check());
                checked = runOperator(sb.inputs(), s);
            }
            EXPECT_GT(counter.calls.load(), 0) << device << " " << method << ": the check was never asked";
            EXPECT_EQ(counter.threads, std::set<std::thread::id>{std::this_thread::get_id()})
                << device << " " << method << ": asked on a thread the caller does not own";
            EXPECT_EQ(maxAbsDiff(plain.ao, checked.ao), 0.0) << device << " " << method;
        }
    }
}

TEST(Cancel, TheFirstStopEndsTheRun) {
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(kW, kH), kW, kH);
    for (const std::string& device : devices()) {
        // The CPU asks before each tile its caller's thread takes (on one thread: every tile, so
        // the count does not hang on which thread wins a tile); GL before each dispatch, of which
        // this frame has one.
        for (int stopAt : device == "cpu" ? std::vector<int>{1, 2, 5} : std::vector<int>{1}) {
            CountingCheck counter;
            counter.stopAt = stopAt;
            const CancelScope scope(counter.check());
            Settings s = settingsOn(device, "hbao");
            s.threads = 1;
            EXPECT_THROW(runOperator(sb.inputs(), s), Cancelled) << device;
            EXPECT_EQ(counter.calls.load(), stopAt) << device << ": asked again after it said stop";
        }
    }
}

// Scopes nest: the inner check is asked while it stands, the outer one again after it.
TEST(Cancel, ScopesRestoreTheCheckBefore) {
    EXPECT_FALSE(cancelRequested());
    {
        const CancelScope outer([] { return true; });
        EXPECT_TRUE(cancelRequested());
        {
            const CancelScope inner([] { return false; });
            EXPECT_FALSE(cancelRequested());
            EXPECT_NO_THROW(throwIfCancelled());
        }
        EXPECT_TRUE(cancelRequested());
        EXPECT_THROW(throwIfCancelled(), Cancelled);
    }
    EXPECT_FALSE(cancelRequested());
}

// The tiles the other threads hold run to their end; no new tile starts after the stop.
TEST(Cancel, TilesStopBeingHandedOut) {
    const Box2i region{0, 0, 64, 64};
    std::atomic<int> ran{0};
    int asked = 0;
    const CancelScope scope([&] { return ++asked >= 3; });
    EXPECT_THROW(cpu::parallelForTiles(region, 8, 1, [&](const Box2i&) { ++ran; }), Cancelled);
    EXPECT_EQ(ran.load(), 1);  // one thread: the call's own question, then one before each tile
}

// A costly check asked at most every interval: the first time at once, then its answer stands
// until the interval has passed; once it said stop it is not asked again.
TEST(Cancel, AChecksAnswerStandsForItsInterval) {
    int asked = 0;
    bool answer = false;
    CancelCheck slow = askedAtMostEvery(std::chrono::hours(1), [&] { return ++asked, answer; });
    EXPECT_FALSE(slow());
    answer = true;
    EXPECT_FALSE(slow());  // the last answer stands
    EXPECT_EQ(asked, 1);
    CancelCheck each = askedAtMostEvery(std::chrono::milliseconds(0), [&] { return ++asked, answer; });
    EXPECT_TRUE(each());
    EXPECT_TRUE(each());
    EXPECT_EQ(asked, 2);  // not asked again after it said stop
}
