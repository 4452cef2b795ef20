// Ctrl-C in Python during a long call: while the GIL is released the interpreter cannot raise
// KeyboardInterrupt, so the operator's tiles ask it whether a signal handler raised
// (base/cancel.h). Only Python's main thread runs signal handlers; elsewhere nothing is asked.
#pragma once
#include "base/cancel.h"

#include <optional>

namespace obscura::python {

// Construct with the GIL held, on the thread that then releases it and runs the operator. On
// Python's main thread it installs a check that takes the GIL at most every 20 ms; when it says
// stop, KeyboardInterrupt stands as Python's error and the module's translator leaves it there.
class CtrlCStops {
public:
    CtrlCStops();

private:
    std::optional<CancelScope> scope_;
};

} // namespace obscura::python
