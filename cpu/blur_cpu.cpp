#include "cpu/blur_cpu.h"

#include "cpu/lanes_scalar.h"
#include "cpu/parallel.h"

#include <vector>

namespace obscura::glsl {

struct BlurCpuKernel {
    KernelParams P;
    ConstPlane depthPlane, normalPlane, signalPlane;

    float loadDepth(ivec2 t) const { return *depthPlane.at(t.x, t.y); }
    vec3 loadNormal(ivec2 t) const {
        const float* n = normalPlane.at(t.x, t.y);
        return vec3(n[0], n[1], n[2]);
    }
    vec4 loadSignal(ivec2 t) const {
        const float* s = signalPlane.at(t.x, t.y);
        vec4 v(0.0f);
        for (int c = 0; c < signalPlane.channels; ++c) v[c] = s[c];
        return v;
    }

#include "kernels/common.glsl"
#include "kernels/blur.glsl"
};

} // namespace obscura::glsl

namespace obscura::cpu {

namespace {
constexpr int kTile = 32;
}

void runBlur(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane signal, int radius,
              int threads) {
    if (radius <= 0) return;
    const int n = signal.channels;
    std::vector<float> scratch((size_t)p.width * p.height * n);
    MutablePlane tmp{scratch.data(), p.width, p.height, n, n, (std::ptrdiff_t)p.width * n};
    auto pass = [&](ConstPlane src, MutablePlane dst, glm::ivec2 axis) {
        parallelForTiles(Box2i{0, 0, p.width, p.height}, kTile, threads, [&](const Box2i& tile) {
            glsl::BlurCpuKernel k;
            k.P = p;
            k.depthPlane = depth;
            k.normalPlane = normal;
            k.signalPlane = src;
            for (int y = tile.y0; y < tile.y1; ++y)
                for (int x = tile.x0; x < tile.x1; ++x) {
                    const glm::vec4 v = k.blurPixel4(glm::ivec2(x, y), axis, radius);
                    float* o = dst.at(x, y);
                    for (int c = 0; c < n; ++c) o[c] = v[c];
                }
        });
    };
    pass(signal, tmp, glm::ivec2(1, 0));
    pass(tmp, signal, glm::ivec2(0, 1));
}

} // namespace obscura::cpu
