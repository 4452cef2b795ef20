// The CPU backend: the lane kernels over tiles on every core, then the geometry-aware blur.
#include "core/backend_cpu.h"

#include "core/devices.h"
#include "core/method_runs.h"
#include "cpu/blur_cpu.h"
#include "cpu/depth_normal_cpu.h"
#include "cpu/discs_cpu.h"
#include "cpu/lane_cpu.h"
#include "cpu/rtao_cpu.h"
#include "cpu/ssdo_cpu.h"

namespace obscura {

namespace {

class CpuBackend final : public Backend {
public:
    explicit CpuBackend(int threads) : threads_(threads) {}

    std::string description() const override { return deviceDescription(nullptr, threads_); }

    void depthNormals(const KernelParams& p, ConstPlane depth, MutablePlane normal, OperatorStats& st) const override {
        const auto t0 = Clock::now();
        cpu::runDepthNormals(p, depth, normal, threads_);
        st.timings.push_back({"depth-normals", secondsSince(t0)});
    }

    void ao(AoKernel kernel, const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep,
            MutablePlane ao, int blur, OperatorStats& st) const override {
        const auto t0 = Clock::now();
        const bool hbao = kernel == AoKernel::Hbao;
        if (deep.valid()) cpu::runHbaoDeep(p, depth, normal, deep, ao, threads_);
        else cpu::runLaneKernel(hbao ? cpu::LaneKernel::Hbao : cpu::LaneKernel::Ssao, p, depth, normal, ao, threads_);
        st.timings.push_back({hbao ? "hbao" : "ssao", secondsSince(t0)});
        this->blur(p, depth, normal, {ao}, blur, st);
    }

    void hbaoGi(const KernelParams& p, ConstPlane depth, ConstPlane normal, ConstPlane deep, ConstPlane radiance,
                ConstPlane facing, MutablePlane ao, MutablePlane gi, int blur, OperatorStats& st) const override {
        const auto t0 = Clock::now();
        cpu::runHbaoGi(p, depth, normal, deep, radiance, facing, ao, gi, threads_);
        st.timings.push_back({"hbao+gi", secondsSince(t0)});
        this->blur(p, depth, normal, {gi, ao}, blur, st);
    }

    void discs(const KernelParams& p, const cpu::DiscPyramid& pyramid, ConstPlane depth, ConstPlane normal,
               MutablePlane ao, int blur, OperatorStats& st) const override {
        const auto t0 = Clock::now();
        cpu::runDiscs(p, pyramid, normal, ao, threads_);
        st.timings.push_back({"discs", secondsSince(t0)});
        this->blur(p, depth, normal, {ao}, blur, st);
    }

    void ssdo(const KernelParams& p, const SsdoPlanesIn& in, MutablePlane directional, MutablePlane indirect,
              MutablePlane ao, int blur, OperatorStats& st) const override {
        const auto t0 = Clock::now();
        cpu::runSsdo(p, {in.depth, in.normal, in.radiance, in.albedo, in.environment}, directional, indirect, ao,
                     threads_);
        st.timings.push_back({p.bounce ? "ssdo+bounce" : "ssdo", secondsSince(t0)});
        this->blur(p, in.depth, in.normal, {directional, ao}, blur, st);
        // GI's blur: wider (kernel_params.glsl).
        if (p.bounce) this->blur(p, in.depth, in.normal, {indirect}, glsl::SSDO_GI_BLUR_SCALE * blur, st, "blur-gi");
    }

    void rtao(const KernelParams& p, const Settings& s, ConstPlane depth, ConstPlane normal, MutablePlane ao, int blur,
              OperatorStats& st) const override {
        cpu::RtaoStats rs;
        cpu::runRtao(p, depth, normal, ao, {s.rtaoRays, resolvedThickness(s), s.rtaoGrid}, threads_, &rs);
        st.timings.push_back({"rtao-mesh", rs.meshSeconds});
        st.timings.push_back({"rtao-bvh", rs.bvhSeconds});
        st.timings.push_back({"rtao-trace", rs.traceSeconds});
        this->blur(p, depth, normal, {ao}, blur, st);
    }

private:
    // The geometry-aware blur of the planes, timed as one stage (`stage`: a name no other stage of
    // the run has, as reports key the timings by name). Two planes in a row whose channels fit the
    // blur's four (GI or DO beside AO) share its weights: one pass over the geometry for both.
    void blur(const KernelParams& p, ConstPlane depth, ConstPlane normal, std::initializer_list<MutablePlane> planes,
              int radius, OperatorStats& st, const char* stage = "blur") const {
        if (radius <= 0) return;
        const auto t0 = Clock::now();
        for (auto plane = planes.begin(); plane != planes.end(); ++plane) {
            const auto next = plane + 1;
            const bool pair = next != planes.end() && plane->channels + next->channels <= 4;
            cpu::runBlur(p, depth, normal, *plane, pair ? *next : MutablePlane{}, radius, threads_);
            if (pair) ++plane;
        }
        st.timings.push_back({stage, secondsSince(t0)});
    }

    int threads_;
};

} // namespace

std::unique_ptr<Backend> makeCpuBackend(int threads) { return std::make_unique<CpuBackend>(threads); }

} // namespace obscura
