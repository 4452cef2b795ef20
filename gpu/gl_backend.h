// The GPU backend: the same kernels/ text as the CPU backend, compiled as GLSL
// compute shaders, run in tiles (with an apron) sized to the context's limits.
#pragma once
#include "core/image.h"
#include "cpu/kernel_params.h"
#include "gpu/device_info.h"

#include <map>
#include <memory>
#include <string>

namespace obscura::gpu {

class GlContext;
enum class ContextKind;

struct GlTimings {
    double upload = 0, compute = 0, readback = 0;  // seconds
    int tiles = 0;
};

class GlBackend {
public:
    // Makes the context and compiles every registered kernel; throws obscura::Error.
    GlBackend(ContextKind kind, bool hardwareOnly);
    ~GlBackend();

    const ContextInfo& info() const;

    // AO (then `blur` passes of the geometry-aware blur) for the buffers p describes;
    // p.maxRadiusPixels bounds how far a pixel reads, which sizes the tile apron.
    // maxTexels (0 = from the context's limits) caps a tile, for tests of tiling.
    void runHbao(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int blur,
                 GlTimings* timings = nullptr, long long maxTexels = 0);

private:
    std::unique_ptr<GlContext> context_;
    std::map<std::string, unsigned> programs_;  // GL program names
    unsigned buffers_[5] = {0, 0, 0, 0, 0};
};

// "cpu", "auto", "gl", "gl-egl", "gl-osmesa"; returns false for an unknown name.
bool isDeviceName(const std::string& name);

// The backend for a device name, made once per thread and reused.
// "gl" tries EGL then OSMesa. Throws obscura::Error saying why it cannot be made.
GlBackend& glBackendFor(const std::string& device);

} // namespace obscura::gpu
