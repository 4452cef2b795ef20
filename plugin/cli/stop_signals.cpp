#include "cli/stop_signals.h"

#include <csignal>

namespace obscura::cli {

namespace {

volatile std::sig_atomic_t gStop = 0;

void onStop(int signal) { gStop = signal; }

void install(int signal, void (*handler)(int), int flags) {
    struct sigaction action {};
    action.sa_handler = handler;
    action.sa_flags = flags;
    sigemptyset(&action.sa_mask);
    sigaction(signal, &action, nullptr);
}

} // namespace

StopSignals::StopSignals() : scope_([] { return gStop != 0; }) {
    gStop = 0;
    for (int s : {SIGINT, SIGTERM}) install(s, onStop, SA_RESETHAND);  // the second one: the default
}

StopSignals::~StopSignals() {
    for (int s : {SIGINT, SIGTERM}) install(s, SIG_DFL, 0);
}

int stopSignal() { return gStop; }

const char* stopSignalName() { return gStop == SIGTERM ? "SIGTERM" : "SIGINT"; }

} // namespace obscura::cli
