// The kernels/*.glsl texts, embedded at build time (gpu/embed_kernels.cmake).
#pragma once
#include <string>
#include <vector>

namespace obscura::gpu {

struct KernelSource {
    const char* name;  // file name, e.g. "hbao.glsl"
    const char* text;
};

const std::vector<KernelSource>& kernelSources();

} // namespace obscura::gpu
