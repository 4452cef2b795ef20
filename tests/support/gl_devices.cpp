#include "support/gl_devices.h"

#include "gpu/gl_backend.h"
#include "support/scenes.h"

#include <cmath>

namespace obscura::test {

::testing::AssertionResult glParity(const Image& cpu, const Image& gl, double tol, const std::string& device) {
    if (cpu.pixels.size() != gl.pixels.size()) return ::testing::AssertionFailure() << device << ": sizes differ";
    size_t over = 0;
    double sum = 0;
    for (size_t i = 0; i < cpu.pixels.size(); ++i) {
        const double d = std::abs((double)cpu.pixels[i] - gl.pixels[i]);
        over += !(d <= tol);
        sum += d;
    }
    const double mean = cpu.pixels.empty() ? 0.0 : sum / (double)cpu.pixels.size();
    const bool software = gpu::glBackendFor(device).info().software;
    const bool ok = software ? over == 0 : over * 1000 <= cpu.pixels.size() && mean <= tol / 100;
    if (ok) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << device << (software ? " (software)" : " (hardware)") << ", mean "
                                         << mean << ": " << diffSummary(cpu, gl, tol);
}

} // namespace obscura::test
