// Ctrl-C, and the SIGTERM a farm's scheduler sends when a job is cancelled or out of time: the
// run stops between the operator's tiles (base/cancel.h) and between frames, writes nothing
// more, leaves no temporary file, and exits 128 + the signal's number. A second signal ends the
// process at once, as it would without this.
#pragma once
#include "base/cancel.h"

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
};

// The signal that asked the run to stop (SIGINT, SIGTERM), 0 when none did.
int stopSignal();
// "SIGINT", "SIGTERM".
const char* stopSignalName();

} // namespace obscura::cli
