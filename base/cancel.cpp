#include "base/cancel.h"

#include <utility>

namespace obscura {

namespace {
thread_local CancelCheck tCheck;
} // namespace

CancelScope::CancelScope(CancelCheck check) : outer_(std::exchange(tCheck, std::move(check))) {}

CancelScope::~CancelScope() { tCheck = std::move(outer_); }

CancelCheck askedAtMostEvery(std::chrono::milliseconds interval, CancelCheck check) {
    using Clock = std::chrono::steady_clock;
    return [interval, check = std::move(check), last = Clock::time_point(), asked = false, stop = false]() mutable {
        const Clock::time_point now = Clock::now();
        if (!stop && (!asked || now - last >= interval)) {
            asked = true;
            last = now;
            stop = check();
        }
        return stop;
    };
}

bool cancelRequested() { return tCheck && tCheck(); }

void throwIfCancelled() {
    if (cancelRequested()) throw Cancelled();
}

} // namespace obscura
