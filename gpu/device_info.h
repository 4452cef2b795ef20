// What a GL backend runs on, for --inspect, --report and the benchmark.
#pragma once
#include <string>

namespace obscura::gpu {

struct ContextInfo {
    std::string backend;    // "gl-egl" or "gl-osmesa"
    std::string renderer;   // GL_RENDERER
    std::string version;    // GL_VERSION
    std::string vendor;     // GL_VENDOR
    bool software = false;  // llvmpipe / softpipe / Mesa's software EGL device
    long long maxStorageBlockBytes = 0;
    int maxStorageBindings = 0;   // GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS
    int maxWorkGroups[2] = {0, 0};
};

} // namespace obscura::gpu
