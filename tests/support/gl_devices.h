#pragma once
// The GL devices the parity tests compare with the CPU. Both offscreen paths by default; the
// environment variable OBSCURA_TEST_GL_DEVICES (comma-separated, e.g. "gl-egl") narrows the list,
// so that a machine with a GPU driver but no Mesa runs the same tests on its EGL device.
#include "base/image.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace obscura::test {

inline std::vector<std::string> glDevicesUnderTest() {
    const char* env = std::getenv("OBSCURA_TEST_GL_DEVICES");
    if (!env || !*env) return {"gl-osmesa", "gl-egl"};
    std::vector<std::string> devices;
    std::stringstream list(env);
    for (std::string d; std::getline(list, d, ',');)
        if (!d.empty()) devices.push_back(d);
    if (devices.empty()) return {"gl-osmesa", "gl-egl"};  // "," names none: the default
    return devices;
}

// The one GL device for tests that call a backend directly or run one GL path only.
inline std::string firstGlDevice() { return glDevicesUnderTest().front(); }

// "cpu" followed by every GL device under test.
inline std::vector<std::string> cpuAndGlDevices() {
    std::vector<std::string> all = {"cpu"};
    for (const std::string& d : glDevicesUnderTest()) all.push_back(d);
    return all;
}

// `gl` against the CPU's `cpu`, value by value. On a software device (llvmpipe computes in IEEE
// single precision, as the CPU does) every value lies within `tol`. A hardware GPU's division is
// correct to 2.5 ulp and its trigonometry to no stated bound (ARB_shader_precision), so a sample
// whose test sits that close to its threshold can go the other way there. Such knife edges stay
// isolated, so at most one value in 1000 may lie beyond `tol` there (an NVIDIA H200 gave at most
// 13 in 57,600: one texel, spread by the blur).
::testing::AssertionResult glParity(const Image& cpu, const Image& gl, double tol, const std::string& device);

} // namespace obscura::test
