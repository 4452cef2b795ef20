// A host's request to stop a run early: the OpenFX host's abort (the user scrubbed on), Python's
// Ctrl-C. The host installs its check on the thread that calls the operator; the schedulers ask it
// between tiles (cpu/parallel.cpp, the GL backend's tiles) on that thread only, because a host's
// function need not be safe to call from threads it does not know.
#pragma once
#include <chrono>
#include <exception>
#include <functional>

namespace obscura {

// Thrown out of the run when the check said stop. Not an Error: nothing failed, there is no
// message to show, and no handler that names a file should take it for one.
struct Cancelled : std::exception {
    const char* what() const noexcept override { return "cancelled"; }
};

using CancelCheck = std::function<bool()>;

// `check` is this thread's until the scope ends; the scope before it is restored then.
class CancelScope {
public:
    explicit CancelScope(CancelCheck check);
    ~CancelScope();
    CancelScope(const CancelScope&) = delete;
    CancelScope& operator=(const CancelScope&) = delete;

private:
    CancelCheck outer_;
};

// `check` asked at most once every `interval` (the first time at once), its last answer standing
// in between: for a host whose check is costly (OpenFX's guide says a host's abort may be) or
// takes a lock (Python's GIL). Checks made this way belong to one thread, as a scope's do.
CancelCheck askedAtMostEvery(std::chrono::milliseconds interval, CancelCheck check);

// Whether this thread's check asks to stop (false without one).
bool cancelRequested();
// Throws Cancelled when it does.
void throwIfCancelled();

} // namespace obscura
