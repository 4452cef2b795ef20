// The GPU backend: the same kernels/ text as the CPU backend, compiled as GLSL
// compute shaders, run in tiles (with an apron) sized to the context's limits.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"
#include "gpu/device_info.h"

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace obscura::gpu {

class GlContext;
enum class ContextKind;

// The calling thread's EGL state (current context and surfaces, bound client API) as the thread's
// owner left it, put back when the scope ends. A host application lends its threads to a render
// and may draw on them with its own GL: obscura's context must not stay current there (under
// libglvnd a thread with an EGL context current cannot make a GLX one current). Where nothing was
// current, obscura's context is released. OSMesa keeps a state of its own, outside EGL's.
class ThreadGlState {
public:
    ThreadGlState();
    ~ThreadGlState();
    ThreadGlState(const ThreadGlState&) = delete;
    ThreadGlState& operator=(const ThreadGlState&) = delete;

private:
    bool eglLoaded_ = false;  // libEGL was in the process when the scope began
    void *display_ = nullptr, *draw_ = nullptr, *read_ = nullptr, *context_ = nullptr;
    unsigned api_ = 0;
};

struct GlTimings {
    double upload = 0, compute = 0, readback = 0;  // seconds
    int tiles = 0;
};

class GlBackend {
public:
    // Makes the context and compiles every registered kernel that has no defines (the others on
    // their first use); throws obscura::Error.
    GlBackend(ContextKind kind, bool hardwareOnly);
    ~GlBackend();

    const ContextInfo& info() const;

    // AO (then `blur` passes of the geometry-aware blur) for the buffers p describes;
    // p.maxRadiusPixels bounds how far a pixel reads, which sizes the tile apron.
    // maxTexels (0 = from the context's limits) caps a tile, for tests of tiling.
    void runHbao(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao, int blur,
                 GlTimings* timings = nullptr, long long maxTexels = 0) {
        runAo("hbao", p, depth, normal, ao, blur, timings, maxTexels);
    }
    // The same for any AO kernel reading depth and normals only ("hbao", "ssao").
    void runAo(const char* program, const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, MutablePlane ao,
               int blur, GlTimings* timings = nullptr, long long maxTexels = 0) {
        runAoWith(program, p, depth, normal, ConstPlane{}, ao, blur, timings, maxTexels);
    }
    // HBAO with deep input: `deep` holds p.deepLayers (front, back) depth pairs per texel.
    void runHbaoDeep(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, MutablePlane ao,
                     int blur, GlTimings* timings = nullptr, long long maxTexels = 0) {
        runAoWith("hbao", p, depth, normal, deep, ao, blur, timings, maxTexels);
    }

    // HBAO with its indirect light (kernels/hbao_gi.glsl): AO and the irradiance `gi` (RGB) from
    // `radiance`, the bounce source (albedo applied, one packed RGB word per texel), then `blur` passes on each.
    // With deep input (`deep` valid, as runHbaoDeep's), `radiance` holds p.deepLayers words per texel.
    // `facing`: the visible surface's normal, one packed word per texel.
    void runHbaoGi(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                   ConstPlane facing, MutablePlane ao, MutablePlane gi, int blur, GlTimings* timings = nullptr,
                   long long maxTexels = 0);

    // View-space unit normals from the depth alone (kernels/depth_normal.glsl), 3 channels.
    void runDepthNormals(const glsl::KernelParams& p, ConstPlane depth, MutablePlane normal, GlTimings* timings = nullptr);

    // One pass of disc AO (kernels/discs.glsl) over the whole frame from the host's pyramid
    // (cpu/discs_cpu.h; p's disc fields describe it), then `blur` passes.
    void runDiscs(const glsl::KernelParams& p, const float* pyramid, size_t pyramidFloats, ConstPlane depth, ConstPlane normal,
                  MutablePlane ao, int blur, GlTimings* timings = nullptr);

    struct SsdoInputs {
        ConstPlane depth, normal, radiance, albedo;  // radiance used when p.bounce; albedo optional
        ConstPlane environment;                      // the prefiltered lat-long level, or invalid
    };
    // Directional occlusion (RGB), indirect (RGB, when p.bounce) and AO, then `blur` passes on each.
    void runSsdo(const glsl::KernelParams& p, const SsdoInputs& in, MutablePlane directional, MutablePlane indirect,
                 MutablePlane ao, int blur, GlTimings* timings = nullptr);

private:
    // Throws unless the context offers every storage binding the light's programs use (`what` needs them).
    void requireEveryBinding(const char* what) const;
    void runAoWith(const char* program, const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal,
                   ConstPlane deep, MutablePlane ao, int blur, GlTimings* timings, long long maxTexels);
    // `deep` (when valid) holds HBAO's deep pairs, which also size the tiles.
    void runTiled(const glsl::KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, int blur,
                  long long maxTexels, GlTimings& t, const std::function<void(const Box2i& buf, const glsl::KernelParams& q)>& upload,
                  const std::function<void(const glsl::KernelParams& q)>& run,
                  const std::function<void(const Box2i& inner, const Box2i& buf)>& readback);
    void uploadBuffer(int binding, unsigned target, const void* data, size_t bytes);
    // `channels` floats a texel of `plane` over `box` into storage buffer `binding`.
    void uploadPlane(int binding, ConstPlane plane, const Box2i& box, int channels);
    // ... or, where `plane` is not used, a 16-byte stand-in, as every binding a program declares
    // must hold a buffer.
    void uploadPlaneOrStub(int binding, ConstPlane plane, bool use, const Box2i& box, int channels);
    void dispatch(const char* program, const glsl::KernelParams& q);
    unsigned program(const char* name, const glsl::KernelParams& q); // compiled on first use
    void blurBuffer(int binding, int channels, int radius, const glsl::KernelParams& q);
    void readInner(int binding, int channels, const Box2i& inner, const Box2i& buf, MutablePlane out);

    static constexpr int kScratch = 10;      // blur ping-pong buffer, after the 10 binding points
    static constexpr int kBufferCount = 11;
    std::unique_ptr<GlContext> context_;
    std::map<std::string, unsigned> programs_;  // GL program names, by kernel name and defines
    unsigned buffers_[kBufferCount] = {};
    // Kept across calls: a frame's inputs and outputs are the same size from one call to the next.
    std::vector<float> packed_;    // an upload's rows gathered from a plane they are not contiguous in
    std::vector<float> readback_;  // a readback's rows, when they are not copied straight into the output
};

// The backend for a GL device name ("gl", "gl-egl", "gl-osmesa", or "gl-egl-hardware": an EGL
// device that is not a software renderer), made once per thread and reused.
// "gl" tries EGL then OSMesa. Throws obscura::Error saying why it cannot be made.
GlBackend& glBackendFor(const std::string& device);

} // namespace obscura::gpu
