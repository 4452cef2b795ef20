// A 16384 x 16384 frame on the CPU and on every GL device (tiled with aprons to fit
// the context's buffer limits), timed, and compared with each other. Not a ctest:
// it needs ~10 GB of memory and minutes. Usage: bench_big_frame [size]
#include "core/operator.h"
#include "support/scenes.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>

using namespace obscura;
using namespace obscura::test;

int main(int argc, char** argv) {
    const int size = argc > 1 ? std::atoi(argv[1]) : 16384;
    std::printf("rendering a %dx%d analytic scene...\n", size, size);
    SceneBuffers sb = renderScene(studioScene(), studioCamera(size, size), size, size);
    sb.position = Image();  // not needed: keep memory down
    Settings s;
    s.radius = 0.05f;  // a few pixels at this resolution: the point is the frame size, not the radius
    s.directions = 4;
    s.steps = 4;
    s.blur = 0;  // the kernel alone
    Image reference;
    for (const char* device : {"cpu", "gl-osmesa", "gl-egl"}) {
        s.device = device;
        try {
            const auto t0 = std::chrono::steady_clock::now();
            OperatorOutputs out = runOperator(sb.inputs(), s);
            const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            double maxDiff = 0;
            if (reference.empty()) reference = out.ao;
            for (size_t i = 0; i < out.ao.pixels.size(); ++i)
                maxDiff = std::max(maxDiff, (double)std::abs(out.ao.pixels[i] - reference.pixels[i]));
            std::printf("%-10s %8.2f s  %6.2f MP/s  max |diff| vs cpu %.2e  (%s)\n", device, secs,
                        (double)size * size / secs * 1e-6, maxDiff, out.stats.device.c_str());
        } catch (const std::exception& e) {
            std::printf("%-10s failed: %s\n", device, e.what());
        }
    }
    return 0;
}
