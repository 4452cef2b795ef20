// The OpenGL implementation of core/backend.h over a GL context (internal to plugin/core).
#pragma once
#include "core/backend.h"

namespace obscura {
namespace gpu {
class GlBackend;
}
std::unique_ptr<Backend> makeGlBackend(gpu::GlBackend& gl);
} // namespace obscura
