// The frame loop: every pixel through the integrator, rows shared among threads,
// then the convergence summary over non-sky pixels.
#pragma once
#include "integrators.h"

#include <functional>
#include <vector>

namespace reference {

struct Frame {
    int width = 0, height = 0;        // of the data window
    int originX = 0, originY = 0;     // display coordinates of pixel (0, 0): -overscan
    std::vector<PixelResult> pixels;  // row-major, y down
    const PixelResult& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
};

struct Convergence {
    size_t surfacePixels = 0;
    std::array<double, kAoLayers> aoMean{}, aoStdErrMean{}, aoStdErrMax{};
    double indirectMean = 0, indirectStdErrMean = 0, indirectStdErrMax = 0;  // luminance
    double giNearMean = 0, giFullMean = 0, directionalMean = 0;              // luminance of GI, GI_unlimited, DO
};

// row(y) for every y in [0, height), rows handed out one at a time to `threads` threads (0 =
// all cores; the caller is one of them): rows cost unevenly, so none is assigned in advance.
void forEachRow(int height, int threads, const std::function<void(int y)>& row);

Frame render(const Integrator& integrator, const RenderSettings& settings);
Convergence summarise(const Frame& frame);

} // namespace reference
