#include "core/method_runs.h"

#include "core/environment.h"
#include "base/error.h"
#include "cpu/blur_cpu.h"
#include "cpu/discs_cpu.h"
#include "cpu/lane_cpu.h"
#include "cpu/rtao_cpu.h"
#include "cpu/ssdo_cpu.h"
#include "gpu/gl_backend.h"

#include <algorithm>

namespace obscura {

namespace {

void recordGl(OperatorStats& st, const gpu::GlTimings& t) {
    st.timings.push_back({"gl-upload", t.upload});
    st.timings.push_back({"gl-compute", t.compute});
    st.timings.push_back({"gl-readback", t.readback});
}

// A lane kernel that reads depth and normals and writes AO (hbao, ssao), then the blur.
void runLaneAo(const MethodRun& r, cpu::LaneKernel kernel, const char* name) {
    OperatorStats& st = r.out.stats;
    const int blur = resolvedBlur(r.settings);
    const bool deep = kernel == cpu::LaneKernel::Hbao && r.params.deepLayers > 0;
    if (r.gl) {
        gpu::GlTimings t;
        if (deep) r.gl->runHbaoDeep(r.params, r.in.depth, r.in.normal, r.in.deepLayers, r.out.ao.view(), blur, &t);
        else r.gl->runAo(name, r.params, r.in.depth, r.in.normal, r.out.ao.view(), blur, &t);
        recordGl(st, t);
        return;
    }
    auto t0 = Clock::now();
    if (deep) cpu::runHbaoDeep(r.params, r.in.depth, r.in.normal, r.in.deepLayers, r.out.ao.view(), r.threads);
    else cpu::runLaneKernel(kernel, r.params, r.in.depth, r.in.normal, r.out.ao.view(), r.threads);
    st.timings.push_back({name, secondsSince(t0)});
    if (blur > 0) {
        t0 = Clock::now();
        cpu::runBlur(r.params, r.in.depth, r.in.normal, r.out.ao.view(), blur, r.threads);
        st.timings.push_back({"blur", secondsSince(t0)});
    }
}

} // namespace

void runHbaoMethod(const MethodRun& r) { runLaneAo(r, cpu::LaneKernel::Hbao, "hbao"); }

void runSsaoMethod(const MethodRun& r) { runLaneAo(r, cpu::LaneKernel::Ssao, "ssao"); }

void runRtaoMethod(const MethodRun& r) {
    const Settings& s = r.settings;
    OperatorStats& st = r.out.stats;
    cpu::RtaoStats rs;
    cpu::runRtao(r.params, r.in.depth, r.in.normal, r.out.ao.view(), {s.rtaoRays, resolvedThickness(s), s.rtaoGrid},
                 r.threads, &rs);
    st.timings.push_back({"rtao-mesh", rs.meshSeconds});
    st.timings.push_back({"rtao-bvh", rs.bvhSeconds});
    st.timings.push_back({"rtao-trace", rs.traceSeconds});
    if (const int blur = resolvedBlur(s); blur > 0) {
        const auto t0 = Clock::now();
        cpu::runBlur(r.params, r.in.depth, r.in.normal, r.out.ao.view(), blur, r.threads);
        st.timings.push_back({"blur", secondsSince(t0)});
    }
}

// Discs: one pyramid on the CPU (both devices read it), then one traversal per pass; the
// second weights each element by its own first-pass AO.
void runDiscsMethod(const MethodRun& r) {
    OperatorStats& st = r.out.stats;
    KernelParams p = r.params;
    auto t0 = Clock::now();
    cpu::DiscPyramid pyramid = cpu::buildDiscPyramid(p, r.in.depth, r.in.normal, r.threads);
    st.timings.push_back({"discs-pyramid", secondsSince(t0)});
    const int passes = r.settings.discsPasses;
    for (int pass = 0; pass < passes; ++pass) {
        if (pass > 0) {
            t0 = Clock::now();
            cpu::setDiscVisibility(pyramid, r.out.ao.view(), r.threads);
            p.discVisibility = 1;
            st.timings.push_back({"discs-visibility", secondsSince(t0)});
        }
        const int blur = pass + 1 == passes ? resolvedBlur(r.settings) : 0;
        if (r.gl) {
            gpu::GlTimings t;
            r.gl->runDiscs(p, pyramid.data.get(), pyramid.floats, r.in.depth, r.in.normal, r.out.ao.view(), blur, &t);
            recordGl(st, t);
            continue;
        }
        t0 = Clock::now();
        cpu::runDiscs(p, pyramid, r.in.normal, r.out.ao.view(), r.threads);
        st.timings.push_back({"discs", secondsSince(t0)});
        if (blur > 0) {
            t0 = Clock::now();
            cpu::runBlur(p, r.in.depth, r.in.normal, r.out.ao.view(), blur, r.threads);
            st.timings.push_back({"blur", secondsSince(t0)});
        }
    }
}

// SSDO: plan what is needed (no bounce without a source, no map when none is given),
// prefilter the environment to the per-pixel sample count, run, and blur over the
// interleaving block.
void runSsdoMethod(const MethodRun& r) {
    const OperatorInputs& in = r.in;
    const Settings& s = r.settings;
    KernelParams p = r.params;
    gpu::GlBackend* gl = r.gl;
    const int threads = r.threads;
    OperatorOutputs& out = r.out;
    if (s.bounce && !in.radiance.valid())
        throw Error("the bounce (GI) needs a radiance source: a direct-diffuse or beauty pass");
    if (in.radiance.valid()) checkPlane(in.radiance, 3, in.dataWindow, "bounce source");
    if (in.albedo.valid()) checkPlane(in.albedo, 3, in.dataWindow, "albedo");
    OperatorStats& st = out.stats;
    auto t0 = Clock::now();
    Image level;
    if (in.environment && !in.environment->empty()) {
        if (in.environment->channels < 3) throw Error("the environment map needs 3 channels");
        level = prefilterLatLong(*in.environment, std::max(1, s.ssdoSamples / (s.interleave * s.interleave)));
        p.envWidth = level.width;
        p.envHeight = level.height;
        st.timings.push_back({"environment", secondsSince(t0)});
    }
    const int w = in.dataWindow.width(), h = in.dataWindow.height();
    out.directional = Image(w, h, 3, 0.0f);
    if (p.bounce) out.indirect = Image(w, h, 3, 0.0f);
    Image unusedIndirect = p.bounce ? Image() : Image(w, h, 3, 0.0f);
    Image& indirect = p.bounce ? out.indirect : unusedIndirect;
    const ConstPlane environment = level.empty() ? ConstPlane{} : ConstPlane(level.view());
    // The interleaved subsets are gathered back by a blur as wide as the block (or --blur).
    const int blur = resolvedBlur(s);
    if (gl) {
        gpu::GlTimings t;
        gl->runSsdo(p, {in.depth, in.normal, in.radiance, in.albedo, environment}, out.directional.view(),
                    indirect.view(), out.ao.view(), blur, &t);
        recordGl(st, t);
        return;
    }
    cpu::SsdoPlanes planes{in.depth, in.normal, in.radiance, in.albedo, environment};
    t0 = Clock::now();
    cpu::runSsdo(p, planes, out.directional.view(), indirect.view(), out.ao.view(), threads);
    st.timings.push_back({p.bounce ? "ssdo+bounce" : "ssdo", secondsSince(t0)});
    if (blur > 0) {
        t0 = Clock::now();
        cpu::runBlur(p, in.depth, in.normal, out.directional.view(), blur, threads);
        if (p.bounce) cpu::runBlur(p, in.depth, in.normal, out.indirect.view(), blur, threads);
        cpu::runBlur(p, in.depth, in.normal, out.ao.view(), blur, threads);
        st.timings.push_back({"blur", secondsSince(t0)});
    }
}


} // namespace obscura
