#include "cpu/ssdo_cpu.h"

#include "cpu/lanes_scalar.h"
#include "cpu/parallel.h"

#include <vector>

namespace obscura::glsl {

struct SsdoCpuKernel {
    KernelParams P;
    cpu::SsdoPlanes in;

    float loadDepth(ivec2 t) const { return *in.depth.at(t.x, t.y); }
    vec3 loadNormal(ivec2 t) const { return load3(in.normal, t); }
    vec3 loadRadiance(ivec2 t) const { return in.radiance.valid() ? load3(in.radiance, t) : vec3(0.0f); }
    vec3 loadAlbedo(ivec2 t) const { return in.albedo.valid() ? load3(in.albedo, t) : vec3(1.0f); }
    vec3 loadEnv(ivec2 t) const { return load3(in.environment, t); }
    static vec3 load3(const ConstPlane& p, ivec2 t) {
        const float* v = p.at(t.x, t.y);
        return vec3(v[0], v[1], v[2]);
    }

#include "kernels/common.glsl"
#include "kernels/ssdo.glsl"
};

} // namespace obscura::glsl

namespace obscura::cpu {

namespace {
constexpr int kTile = 32;
}

void runSsdo(const glsl::KernelParams& p, const SsdoPlanes& in, MutablePlane directional, MutablePlane indirect,
             MutablePlane ao, int threads) {
    parallelForTiles(Box2i{0, 0, p.width, p.height}, kTile, threads, [&](const Box2i& tile) {
        glsl::SsdoCpuKernel k;
        k.P = p;
        k.in = in;
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x) {
                glm::vec3 d, g;
                float a;
                k.ssdoPixel(glm::ivec2(x, y), d, g, a);
                float* dp = directional.at(x, y);
                float* gp = indirect.at(x, y);
                for (int c = 0; c < 3; ++c) {
                    dp[c] = d[c];
                    gp[c] = g[c];
                }
                *ao.at(x, y) = a;
            }
    });
}

} // namespace obscura::cpu
