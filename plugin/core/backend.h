// Where a method's kernels run: one interface with a CPU and an OpenGL implementation, chosen
// once per run (chooseBackend), as OpenColorIO hands out a CPU or a GPU processor from one
// description. The method runs (method_runs.cpp) call it and never branch on the device; each
// call takes the blur radius, so the blur runs once, inside the backend that made the result.
#pragma once
#include "base/image.h"
#include "base/kernel_params.h"
#include "core/operator.h"

#include <memory>
#include <string>
#include <vector>

namespace obscura {

namespace cpu {
struct DiscPyramid;
}

enum class AoKernel { Hbao, Ssao };

// The planes SSDO reads (radiance used when p.bounce; albedo optional; environment: the
// prefiltered lat-long level, or invalid).
struct SsdoPlanesIn {
    ConstPlane depth, normal, radiance, albedo, environment;
};

class Backend {
public:
    virtual ~Backend() = default;
    // "cpu (N threads)" or the GL renderer, for the report.
    virtual std::string description() const = 0;
    // View-space unit normals of the depth's surfaces (kernels/depth_normal.glsl), for inputs
    // without a normal pass.
    virtual void depthNormals(const KernelParams& p, ConstPlane depth, MutablePlane normal, OperatorStats& st) const = 0;
    // HBAO (with deep layers when `deep` is valid) or SSAO into `ao`, then the blur.
    virtual void ao(AoKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
                    MutablePlane ao, int blur, OperatorStats& st) const = 0;
    // HBAO with its indirect light: AO into `ao` and the irradiance from `radiance` (the bounce
    // source, albedo applied, one packed word per texel: core/method_runs.cpp) into `gi`, then the
    // blur of both. With deep layers (`deep` valid), one word per texel and layer. `facing`: the
    // visible surface's normal, one packed word per texel.
    virtual void hbaoGi(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                        ConstPlane facing, MutablePlane ao, MutablePlane gi, int blur, OperatorStats& st) const = 0;
    // One traversal of the disc pyramid (built on the CPU; both devices read it), then the blur.
    virtual void discs(const KernelParams& p, const cpu::DiscPyramid& pyramid, ConstPlane depth, ConstPlane normal,
                       MutablePlane ao, int blur, OperatorStats& st) const = 0;
    // DO, GI (when p.bounce) and AO, then the blur of each.
    virtual void ssdo(const KernelParams& p, const SsdoPlanesIn& in, MutablePlane directional, MutablePlane indirect,
                      MutablePlane ao, int blur, OperatorStats& st) const = 0;
    // Rays against the mesh of the depth pass (rtao), then the blur; the CPU only.
    virtual void rtao(const KernelParams& p, const Settings& s, ConstPlane depth, ConstPlane normal, MutablePlane ao,
                      int blur, OperatorStats& st) const = 0;
};

// The backend settings.device resolves to for `method` (the one place the device is chosen):
// a GL device the method does not run on throws, unless it came from "auto", which falls back
// to the CPU and says so in `notes`.
std::unique_ptr<Backend> chooseBackend(const Settings& settings, bool methodRunsOnGl, int threads,
                                       std::vector<std::string>& notes);

} // namespace obscura
