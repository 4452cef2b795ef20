// The CPU implementation of core/backend.h (internal to plugin/core).
#pragma once
#include "core/backend.h"

namespace obscura {
std::unique_ptr<Backend> makeCpuBackend(int threads);
} // namespace obscura
