// The CPU kernels (HBAO, SSAO, SSDO, the blur, discs, depth normals) instantiated once per instruction set, and the
// one place that picks among them. cpu/isa_kernels.cpp and cpu/isa_lane_kernels.cpp are compiled
// once per ISA, each in its own namespace (scalar, baseline, x86_64_v3, x86_64_v4); everything
// there except the `kernels` table and the entry points it names (all in that namespace) has
// internal linkage, so no out-of-line copy compiled for one ISA can be picked by the linker for
// another.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"

#include <glm/glm.hpp>
#include <initializer_list>
#include <string>
#include <vector>

namespace obscura::cpu {

struct SsdoPlanes;

// The blur's signal: one plane, or two blurred with one set of weights (AO beside GI).
struct BlurSource {
    ConstPlane first, second;
};
struct BlurTarget {
    MutablePlane first, second;
};

// Entry points each ISA provides; each runs its kernel over every texel of `tile`.
struct IsaKernels {
    // HBAO; `edges` holds the buffer's edge texels (cpu/lane_cpu.h, hbaoEdgeTexels) where
    // p.hbaoBorder continues the surface past the edge.
    void (*hbaoTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane edges,
                     MutablePlane ao, const Box2i& tile);
    void (*ssaoTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                     const Box2i& tile);
    void (*ssdoTile)(const glsl::KernelParams& p, const SsdoPlanes& in, MutablePlane directional,
                     MutablePlane indirect, MutablePlane ao, const Box2i& tile);
    // One pass of the blur along `axis`, from `src` to `dst` (same channel counts): the second
    // plane of each (invalid: none) is blurred with the first's weights, their channels 4 at most.
    void (*blurTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, const BlurSource& src,
                     const BlurTarget& dst, glm::ivec2 axis, int radius, const Box2i& tile);
    // Disc AO (kernels/discs.glsl): level 0 of the pyramid (kDiscChannels planes p.discStride
    // apart, p.width texels per row) over `tile`, returning the largest reach on the screen of its surface
    // texels (discReachPixels); and the traversal of a whole pyramid for the receivers in `tile`
    // (their hemispheres about `normal`).
    float (*discsBaseTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, float* base,
                           const Box2i& tile);
    void (*discsTile)(const glsl::KernelParams& p, const float* pyramid, ConstPlane normal, MutablePlane ao,
                      const Box2i& tile);
    // View-space normals from the depth alone (kernels/depth_normal.glsl), 3 channels.
    void (*depthNormalTile)(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, const Box2i& tile);
    // HBAO with deep input: `deep` holds p.deepLayers (front, back) depth pairs per texel (kernels/hbao.glsl).
    void (*hbaoDeepTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
                         ConstPlane edges, MutablePlane ao, const Box2i& tile);
    // HBAO with its indirect light (kernels/hbao_gi.glsl): `radiance` the bounce source (one
    // packed RGB word per texel and layer), `facing` the visible surface's normal (one packed word
    // per texel), `gi` the irradiance (3 channels); `deep` as hbaoDeepTile's with HBAO_DEEP, else invalid.
    void (*hbaoGiTile)(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
                       ConstPlane radiance, ConstPlane facing, ConstPlane edges, MutablePlane ao, MutablePlane gi,
                       const Box2i& tile);
    // HBAO's bounce source (kernels/shared_exponent.glsl): channel `channel` of `words` over
    // `tile`, the packed word of `rgb`'s colour, times `albedo`'s where it is valid; where `normal`
    // is valid, `facing` its word in view space, facing the eye (p's camera; kernels/normal_word.glsl).
    void (*packSourceTile)(ConstPlane rgb, ConstPlane albedo, ConstPlane normal, const glsl::KernelParams& p,
                           MutablePlane words, int channel, MutablePlane facing, const Box2i& tile);
};

#define OBSCURA_DECLARE_ISA(isa) \
    namespace isa {              \
    extern const IsaKernels kernels; \
    }
OBSCURA_DECLARE_ISA(scalar)    // one pixel at a time: the reference the lane builds are tested against
OBSCURA_DECLARE_ISA(baseline)  // x86-64 (SSE2), 4 pixels per register
OBSCURA_DECLARE_ISA(x86_64_v3) // AVX2 + FMA, 8 pixels
OBSCURA_DECLARE_ISA(x86_64_v4) // AVX-512, 16 pixels
#undef OBSCURA_DECLARE_ISA

// Tiles 64 wide (four AVX-512 registers of pixels) and 16 high: cache-friendly, and small
// enough that sky and non-sky work balance across threads.
constexpr int kLaneTileWidth = 64, kLaneTileHeight = 16;

// The widest instantiation this CPU runs, or the one OBSCURA_CPU_ISA=scalar|baseline|
// x86-64-v3|x86-64-v4 names (if this CPU can run it).
const IsaKernels& cpuKernels();
const char* cpuIsa(); // its name, for reports

// The kernels for these planes: the scalar build where an offset would not fit the lane
// builds' 32-bit gather indices.
const IsaKernels& cpuKernelsFor(std::initializer_list<ConstPlane> planes);

// Every instantiation this CPU runs, from "scalar" (a pixel at a time, the reference) to
// the widest, and one of them by name (std::invalid_argument for another), with the same
// fallback for planes as cpuKernelsFor: for tests and benchmarks.
std::vector<std::string> cpuIsas();
const IsaKernels& cpuKernelsNamed(const std::string& name, std::initializer_list<ConstPlane> planes = {});

// Tests and benchmarks: use the named instantiation from now on (not thread-safe; call
// between runs). "" returns to the automatic choice. False if this CPU cannot run it.
bool forceCpuIsa(const std::string& name);

} // namespace obscura::cpu
