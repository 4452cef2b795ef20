#include "cli/stop_signals.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>

namespace obscura::cli {

namespace {

constexpr int kSignals[2] = {SIGINT, SIGTERM};

// Written by the handler on whichever thread the signal lands, read by the run's thread.
std::atomic<int> gStop{0};
static_assert(std::atomic<int>::is_always_lock_free, "the handler may only write a lock-free atomic");

void onStop(int signal) { gStop = signal; }

} // namespace

StopSignals::StopSignals() : scope_([] { return gStop.load() != 0; }) {
    gStop = 0;
    for (int i = 0; i < 2; ++i) {
        sigaction(kSignals[i], nullptr, &before_[i]);
        if (before_[i].sa_handler == SIG_IGN) continue;  // the parent's choice
        struct sigaction stop {};
        stop.sa_handler = onStop;
        // The second signal: the default. Reads and writes go on where the signal interrupts them.
        stop.sa_flags = SA_RESETHAND | SA_RESTART;
        sigemptyset(&stop.sa_mask);
        sigaction(kSignals[i], &stop, nullptr);
    }
}

StopSignals::~StopSignals() {
    for (int i = 0; i < 2; ++i) sigaction(kSignals[i], &before_[i], nullptr);
}

void endIfStopped(const char* what) {
    if (gStop.load() != 0) endByStopSignal(what);
}

void endByStopSignal(const char* what) {
    const int signal = gStop.load() ? gStop.load() : SIGINT;
    std::fprintf(stderr, "obscura: stopped by %s; %s\n", signal == SIGTERM ? "SIGTERM" : "SIGINT", what);
    std::fflush(nullptr);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    std::_Exit(128 + signal);  // where the signal is blocked
}

} // namespace obscura::cli
