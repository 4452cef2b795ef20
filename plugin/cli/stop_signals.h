// Ctrl-C, and the SIGTERM a farm's scheduler sends when a job is cancelled or out of time: the
// run stops between the operator's tiles (base/cancel.h) and between frames, writes nothing
// more and leaves no temporary file, then ends by that signal, so that a shell loop or a
// scheduler sees the signal (status 130, 143). A second signal ends the process at once, as it
// would without this; a signal the parent set to be ignored stays ignored.
#pragma once
#include "base/cancel.h"

#include <csignal>

namespace obscura::cli {

// Installs the handlers, and this thread's cancel check, until the scope ends.
class StopSignals {
public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    CancelScope scope_;
    struct sigaction before_[2];  // SIGINT's and SIGTERM's actions as they were
};

// After Cancelled: prints "obscura: stopped by SIG...; `what`" and ends the process by that signal.
[[noreturn]] void endByStopSignal(const char* what);
// The same when a signal came after the last point the run looked (a stop during the last write,
// which finishes whole): the caller of a one-frame run sees the signal it sent, not success.
void endIfStopped(const char* what);

} // namespace obscura::cli
