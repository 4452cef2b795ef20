// The OpenGL backend: each call one tiled dispatch chain on the context (kernel, then the
// blur on the GPU), timed as upload, compute and readback.
#include "core/backend_gl.h"

#include "base/error.h"
#include "core/devices.h"
#include "cpu/discs_cpu.h"
#include "gpu/gl_backend.h"

namespace obscura {

namespace {

void record(OperatorStats& st, const gpu::GlTimings& t) {
    st.timings.push_back({"gl-upload", t.upload});
    st.timings.push_back({"gl-compute", t.compute});
    st.timings.push_back({"gl-readback", t.readback});
}

class GlBackendAdapter final : public Backend {
public:
    explicit GlBackendAdapter(gpu::GlBackend& gl) : gl_(gl) {}

    std::string description() const override { return deviceDescription(&gl_, 0); }

    void depthNormals(const KernelParams& p, ConstPlane depth, MutablePlane normal, OperatorStats& st) const override {
        gpu::GlTimings t;
        gl_.runDepthNormals(p, depth, normal, &t);
        record(st, t);
    }

    void ao(AoKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
            MutablePlane ao, int blur, OperatorStats& st) const override {
        gpu::GlTimings t;
        if (deep.valid()) gl_.runHbaoDeep(p, depth, normal, deep, ao, blur, &t);
        else gl_.runAo(kernel == AoKernel::Hbao ? "hbao" : "ssao", p, depth, normal, ao, blur, &t);
        record(st, t);
    }

    void hbaoGi(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                ConstPlane facing, MutablePlane ao, MutablePlane gi, int blur, OperatorStats& st) const override {
        gpu::GlTimings t;
        gl_.runHbaoGi(p, depth, normal, deep, radiance, facing, ao, gi, blur, &t);
        record(st, t);
    }

    void discs(const KernelParams& p, const cpu::DiscPyramid& pyramid, ConstPlane depth, ConstPlane normal,
               MutablePlane ao, int blur, OperatorStats& st) const override {
        gpu::GlTimings t;
        gl_.runDiscs(p, pyramid.data.get(), pyramid.floats, depth, normal, ao, blur, &t);
        record(st, t);
    }

    void ssdo(const KernelParams& p, const SsdoPlanesIn& in, MutablePlane directional, MutablePlane indirect,
              MutablePlane ao, int blur, OperatorStats& st) const override {
        gpu::GlTimings t;
        gl_.runSsdo(p, {in.depth, in.normal, in.radiance, in.albedo, in.environment}, directional, indirect, ao, blur, &t);
        record(st, t);
    }

    void rtao(const KernelParams&, const Settings&, ConstPlane, ConstPlane, MutablePlane, int,
              OperatorStats&) const override {
        throw Error("--method rtao runs on the CPU only; use --device cpu");  // chooseBackend keeps it off GL
    }

private:
    gpu::GlBackend& gl_;
};

} // namespace

std::unique_ptr<Backend> makeGlBackend(gpu::GlBackend& gl) { return std::make_unique<GlBackendAdapter>(gl); }

} // namespace obscura
