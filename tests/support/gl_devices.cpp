#include "support/gl_devices.h"

#include "gpu/gl_backend.h"
#include "support/scenes.h"

#include <cmath>

namespace obscura::test {

::testing::AssertionResult glParity(const Image& cpu, const Image& gl, double tol, const std::string& device) {
    if (cpu.pixels.size() != gl.pixels.size()) return ::testing::AssertionFailure() << device << ": sizes differ";
    size_t over = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) over += !(std::abs((double)cpu.pixels[i] - gl.pixels[i]) <= tol);
    const bool software = gpu::glBackendFor(device).info().software;
    if (software ? over == 0 : over * 1000 <= cpu.pixels.size()) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << device << (software ? " (software): " : " (hardware): ")
                                         << diffSummary(cpu, gl, tol);
}

} // namespace obscura::test
