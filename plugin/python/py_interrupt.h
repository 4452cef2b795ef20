// Ctrl-C in Python during a long call: while the GIL is released the interpreter cannot raise
// KeyboardInterrupt, so the operator's tiles ask it whether a signal is pending (base/cancel.h).
#pragma once
#include "base/cancel.h"

namespace obscura::python {

// The check to install, with the GIL released, on the thread that runs the operator: true once
// the interpreter's signal handlers raised (KeyboardInterrupt then stands as Python's error, and
// the module's translator leaves it there when Cancelled comes out).
CancelCheck pythonSignalPending();

} // namespace obscura::python
