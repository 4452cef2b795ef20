// Registration of the GPU kernels: each is a kernels/ file plus the entry point
// that calls it. Adding a kernel is one line in gl_kernels.cpp.
#pragma once
#include <string>
#include <vector>

namespace obscura::glsl {
struct KernelParams;
}

namespace obscura::gpu {

struct GlKernel {
    const char* name;   // program name
    const char* file;   // kernels/<file> holding its per-pixel function
    const char* main;   // GLSL main() calling it
    // Defines that specialise the program for a parameter block, as the CPU's templates do
    // (cpu/lane_tile_impl.h): one program per distinct text, compiled on its first use. Null: one
    // program, compiled with the backend.
    std::string (*defines)(const glsl::KernelParams& p) = nullptr;
};

const std::vector<GlKernel>& glKernels();

// GLSL text between the kernel parameter block and the kernels: buffer bindings and
// the backend's load functions (the GPU side of the kernels' contract).
extern const char* const kGlBindings;

} // namespace obscura::gpu
