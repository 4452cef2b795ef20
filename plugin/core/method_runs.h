// How the operator hands a method its work, and each method's run function (the table in
// core/methods.cpp points at these). Internal to plugin/core.
#pragma once
#include "core/operator.h"

#include <chrono>

namespace obscura {

class Backend;

struct MethodRun {
    const OperatorInputs& in;
    const Settings& settings;
    const KernelParams& params;   // makeKernelParams(in, settings)
    const Backend& backend;       // where the kernels run (core/backend.h)
    int threads;                  // CPU threads for the work around the kernels (the disc pyramid)
    OperatorOutputs& out;         // out.ao is allocated (1 everywhere)
};

using Clock = std::chrono::steady_clock;
inline double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Throws obscura::Error unless `plane` is valid, covers `window` and has `channels` channels.
void checkPlane(const ConstPlane& plane, int channels, const Box2i& window, const char* what);

void runHbaoMethod(const MethodRun& r);
void runSsdoMethod(const MethodRun& r);
void runSsaoMethod(const MethodRun& r);
void runRtaoMethod(const MethodRun& r);
void runDiscsMethod(const MethodRun& r);

} // namespace obscura
