// Body of ssdoTile for one instruction set (see cpu/lane_kernel.h, cpu/isa_kernels.cpp):
// kernels/ssdo.glsl on a row of OBSCURA_LANES pixels at a time.
#include "cpu/lane_kernel.h"
#include "cpu/ssdo_cpu.h"

namespace obscura::glsl {
namespace {

struct SsdoCpuKernel {
    KernelParams P;
    LanePlane depth, normal, radiance, albedo, env;
    bool hasRadiance = false, hasAlbedo = false;

    lfloat gatherDepth(lint x, lint y, lbool use) const { return depth.gather1(x, y, use); }
    lvec3 gatherNormal(lint x, lint y, lbool use) const { return normal.gather3(x, y, use); }
    lvec3 gatherRadiance(lint x, lint y, lbool use) const {
        return hasRadiance ? radiance.gather3(x, y, use) : lvec3(vec3(0.0f));
    }
    lvec3 gatherAlbedo(lint x, lint y, lbool use) const {
        return hasAlbedo ? albedo.gather3(x, y, use) : lvec3(vec3(1.0f));
    }
    lvec3 gatherEnv(lint x, lint y, lbool use) const { return env.gather3(x, y, use); }

#include "kernels/common.glsl"
#include "kernels/ssdo.glsl"
};

} // namespace
} // namespace obscura::glsl

namespace obscura::cpu::OBSCURA_ISA {
namespace {

void ssdoTile(const glsl::KernelParams& p, const SsdoPlanes& in, MutablePlane directional, MutablePlane indirect,
              MutablePlane ao, const Box2i& tile) {
    glsl::SsdoCpuKernel k;
    k.P = p;
    k.depth = glsl::LanePlane(in.depth);
    k.normal = glsl::LanePlane(in.normal);
    k.radiance = glsl::LanePlane(in.radiance);
    k.albedo = glsl::LanePlane(in.albedo);
    k.env = glsl::LanePlane(in.environment);
    k.hasRadiance = in.radiance.valid();
    k.hasAlbedo = in.albedo.valid();
    const auto lane = glsl::laneIndex();
    for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; x += OBSCURA_LANES) {
            glsl::lvec3 d, g;
            glsl::lfloat a;
            k.ssdoLanes(lane + x, y, d, g, a);
            // Lanes past the tile compute a neighbour (or, past the buffer, nothing) and are not stored.
            const int count = tile.x1 - x < OBSCURA_LANES ? tile.x1 - x : OBSCURA_LANES;
            for (int i = 0; i < count; ++i) {
                float* dp = directional.at(x + i, y);
                float* gp = indirect.at(x + i, y);
                dp[0] = glsl::laneValue(d.x, i);
                dp[1] = glsl::laneValue(d.y, i);
                dp[2] = glsl::laneValue(d.z, i);
                gp[0] = glsl::laneValue(g.x, i);
                gp[1] = glsl::laneValue(g.y, i);
                gp[2] = glsl::laneValue(g.z, i);
                *ao.at(x + i, y) = glsl::laneValue(a, i);
            }
        }
}

} // namespace
} // namespace obscura::cpu::OBSCURA_ISA
