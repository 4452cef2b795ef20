#include "core/method_runs.h"

#include "core/environment.h"
#include "core/light_inputs.h"
#include "base/error.h"
#include "base/kernel_params.h"
#include "core/backend.h"
#include "cpu/big_buffer.h"
#include "cpu/discs_cpu.h"
#include "cpu/isa.h"
#include "cpu/parallel.h"

#include <algorithm>
#include <string>
#include <utility>

namespace obscura {

namespace {
// `plane` with no NaN, infinity, huge or negative value (core/light_inputs.h), copied only where
// it holds one; a note says how many pixels held one of the first three. `checked`: the host
// already saw to it (OperatorInputs::lightChecked).
ConstPlane physicalLight(ConstPlane plane, Image& storage, const char* what, bool checked, OperatorStats& st) {
    if (checked) return plane;
    long long nonFinite = 0;
    const ConstPlane clean = physical(plane, storage, nonFinite);
    if (nonFinite > 0) {
        st.notes.push_back(unphysicalNote(what, nonFinite));
        st.unphysicalLight.push_back(what);
    }
    return clean;
}

// HBAO with --bounce: the indirect light from the same march (kernels/hbao_gi.glsl), from the
// bounce source times the albedo where one is given (SSDO's senders), packed once here. With deep
// layers, a word per texel and layer: the visible layer's bounce source, then each hidden layer's
// colour from the deep file (black where it has none). Beside it, where the light follows the
// AO's occluder runs (the only light that reads it), the visible surface's normal, a word per
// texel, for the light to tell the faces a receiver sees.
void runHbaoGi(const MethodRun& r) {
    const OperatorInputs& in = r.in;
    if (!in.radiance.valid()) throw Error("the bounce (GI) needs a radiance source: a direct-diffuse or beauty pass");
    checkPlane(in.radiance, 3, in.dataWindow, "bounce source");
    const bool albedo = r.params.senderAlbedo != 0 && in.albedo.valid();
    if (albedo) checkPlane(in.albedo, 3, in.dataWindow, "albedo");
    Image ownRadiance, ownAlbedo, ownDeepColour;
    const ConstPlane radiance = physicalLight(in.radiance, ownRadiance, "the bounce source", in.lightChecked, r.out.stats);
    const ConstPlane senderAlbedo = physicalLight(in.albedo, ownAlbedo, "the albedo", in.lightChecked, r.out.stats);
    const ConstPlane deepColour = physicalLight(in.deepColour, ownDeepColour, "the deep colour", false, r.out.stats);
    const ConstPlane deep = r.params.deepLayers > 0 ? in.deepLayers : ConstPlane{};
    const int layers = std::max(r.params.deepLayers, 1);
    const int coloured = deep.valid() && deepColour.valid() ? std::min(layers, deepColour.channels / 3) : 1;
    const int w = in.dataWindow.width(), h = in.dataWindow.height();
    const Clock::time_point t0 = Clock::now();
    // Scratch kept for the next frame (cpu/big_buffer.h): fresh pages cost as much as the packing.
    // The packing writes every word but those of hidden layers without colour.
    const size_t texels = (size_t)w * h;
    const bool faces = r.params.hbaoRuns != 0;
    const cpu::BigFloats scratch = cpu::allocateBigFloats(texels * (layers + (faces ? 1 : 0)));
    if (coloured < layers) std::fill(scratch.get(), scratch.get() + texels * layers, 0.0f);
    const MutablePlane words{scratch.get(), w, h, layers, layers, (std::ptrdiff_t)w * layers};
    const MutablePlane facing = faces ? MutablePlane{scratch.get() + texels * layers, w, h, 1, 1, w} : MutablePlane{};
    // Bands of rows on every thread: one pass over the colour and normal planes, as costly as a
    // copy of them.
    const auto pack = cpu::cpuKernelsFor({radiance, senderAlbedo, deepColour, in.normal}).packSourceTile;
    cpu::parallelForTiles(Box2i{0, 0, w, h}, w, 16, r.threads, [&](const Box2i& band) {
        pack(radiance, albedo ? senderAlbedo : ConstPlane{}, faces ? in.normal : ConstPlane{}, r.params, words, 0, facing,
             band);
        for (int k = 1; k < coloured; ++k) {
            const ConstPlane layer{deepColour.data + 3 * k, w, h, 3, deepColour.xStride, deepColour.yStride};
            pack(layer, ConstPlane{}, ConstPlane{}, r.params, words, k, MutablePlane{}, band);
        }
    });
    r.out.stats.timings.push_back({"gi-source", secondsSince(t0)});
    r.out.indirect = Image(w, h, 3, 0.0f);
    r.backend.hbaoGi(r.params, in.depth, in.normal, deep, ConstPlane(words), ConstPlane(facing), r.out.ao.view(),
                     r.out.indirect.view(), resolvedBlur(r.settings), r.out.stats);
}
} // namespace

void runHbaoMethod(const MethodRun& r) {
    if (r.settings.bounce) return runHbaoGi(r);
    const ConstPlane deep = r.params.deepLayers > 0 ? r.in.deepLayers : ConstPlane{};
    r.backend.ao(AoKernel::Hbao, r.params, r.in.depth, r.in.normal, deep, r.out.ao.view(), resolvedBlur(r.settings),
                 r.out.stats);
}

void runSsaoMethod(const MethodRun& r) {
    r.backend.ao(AoKernel::Ssao, r.params, r.in.depth, r.in.normal, ConstPlane{}, r.out.ao.view(),
                 resolvedBlur(r.settings), r.out.stats);
}

void runRtaoMethod(const MethodRun& r) {
    r.backend.rtao(r.params, r.settings, r.in.depth, r.in.normal, r.out.ao.view(), resolvedBlur(r.settings), r.out.stats);
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
        r.backend.discs(p, pyramid, r.in.depth, r.in.normal, r.out.ao.view(), blur, st);
    }
}

// SSDO: plan what is needed (no bounce without a source, no map when none is given),
// prefilter the environment to the per-pixel sample count, run, and blur over the
// interleaving block.
void runSsdoMethod(const MethodRun& r) {
    const OperatorInputs& in = r.in;
    const Settings& s = r.settings;
    KernelParams p = r.params;
    OperatorOutputs& out = r.out;
    if (s.bounce && !in.radiance.valid())
        throw Error("the bounce (GI) needs a radiance source: a direct-diffuse or beauty pass");
    if (in.radiance.valid()) checkPlane(in.radiance, 3, in.dataWindow, "bounce source");
    if (in.albedo.valid()) checkPlane(in.albedo, 3, in.dataWindow, "albedo");
    OperatorStats& st = out.stats;
    const int blockPixels = s.interleave * s.interleave;
    const int runs = std::max(s.ssdoSamples / glsl::SSDO_STEPS, blockPixels) * glsl::SSDO_STEPS;
    if (runs != s.ssdoSamples)
        st.notes.push_back("--samples " + std::to_string(s.ssdoSamples) + " runs as " + std::to_string(runs) + " (" +
                           std::to_string(glsl::SSDO_STEPS) + " samples a direction, and a direction at least for "
                           "each pixel of the " + std::to_string(s.interleave) + " x " + std::to_string(s.interleave) +
                           " --interleave block)");
    Image ownRadiance, ownAlbedo, ownMap;
    const ConstPlane radiance = physicalLight(in.radiance, ownRadiance, "the bounce source", in.lightChecked, st);
    const ConstPlane albedo = physicalLight(in.albedo, ownAlbedo, "the albedo", in.lightChecked, st);
    auto t0 = Clock::now();
    Image level;
    if (in.environment && !in.environment->empty()) {
        if (in.environment->channels < 3) throw Error("the environment map needs 3 channels");
        physicalLight(in.environment->view(), ownMap, "the environment map", false, st);  // a copy where it mends
        level = prefilterLatLong(ownMap.empty() ? *in.environment : ownMap,
                                 std::max(1, s.ssdoSamples / (s.interleave * s.interleave)));
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
    r.backend.ssdo(p, {in.depth, in.normal, radiance, albedo, environment}, out.directional.view(),
                   indirect.view(), out.ao.view(), resolvedBlur(s), st);
}

} // namespace obscura
