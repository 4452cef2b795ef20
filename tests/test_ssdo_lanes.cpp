// The lane builds of SSDO and the blur (16/8/4 pixels per register) against the
// pixel-at-a-time scalar build of the same kernel text, on an analytic scene, over
// several tilings; and the lane acos/exp those kernels use against the C library.
#include "core/operator.h"
#include "cpu/blur_cpu.h"
#include "cpu/isa.h"
#include "cpu/ssdo_cpu.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;

namespace {

// The studio scene with overscan (so buffer and display origins differ), a width that
// leaves a partial register at each row's end, a sun-lit bounce source, albedo, a
// lat-long environment and a directional light.
struct Frame {
    SceneBuffers sb;
    Image radiance, albedo, env;
    glsl::KernelParams p;

    Frame() {
        const int W = 157, H = 93;
        sb = renderScene(studioScene(), studioCamera(W, H), Box2i{0, 0, W, H}, Box2i{-7, -5, W + 3, H + 6});
        const int w = sb.depth.width, h = sb.depth.height;
        radiance = Image(w, h, 3);
        albedo = Image(w, h, 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) {
                    const float n = sb.normal.at(x, y)[c];
                    albedo.at(x, y)[c] = 0.4f + 0.5f * std::abs(n);
                    radiance.at(x, y)[c] = std::max(n, 0.0f) * 2.0f + 0.1f * c;
                }
        env = Image(32, 16, 3);
        for (int y = 0; y < env.height; ++y)
            for (int x = 0; x < env.width; ++x)
                for (int c = 0; c < 3; ++c) env.at(x, y)[c] = 0.2f + 0.05f * ((x * 7 + y * 3 + c * 5) % 11);
        Settings s;
        s.method = "ssdo";
        s.radius = 0.8f;
        s.bounce = true;
        s.lights.push_back({{0.3f, 1.0f, 0.2f}, {2.0f, 1.8f, 1.5f}});
        OperatorInputs in = sb.inputs();
        p = makeKernelParams(in, s);
        p.bounce = 1;
        p.senderAlbedo = 1;
        p.envWidth = env.width;
        p.envHeight = env.height;
    }
    cpu::SsdoPlanes planes() const { return {sb.depth.view(), sb.normal.view(), radiance.view(), albedo.view(), env.view()}; }
};

struct Ssdo {
    Image directional, indirect, ao;
};

// One ISA's SSDO over the buffer, in tiles of tw x th.
Ssdo runSsdoTiles(const Frame& f, const cpu::IsaKernels& k, int tw, int th) {
    const int w = f.p.width, h = f.p.height;
    Ssdo r{Image(w, h, 3, -1.0f), Image(w, h, 3, -1.0f), Image(w, h, 1, -1.0f)};
    for (int y = 0; y < h; y += th)
        for (int x = 0; x < w; x += tw)
            k.ssdoTile(f.p, f.planes(), r.directional.view(), r.indirect.view(), r.ao.view(),
                       Box2i{x, y, std::min(x + tw, w), std::min(y + th, h)});
    return r;
}

// Largest |a - b| / max(1, |b|), and whether every value is finite.
double worstDifference(const Image& a, const Image& b, bool& finite) {
    double worst = 0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        finite = finite && std::isfinite(a.pixels[i]) && std::isfinite(b.pixels[i]);
        worst = std::max(worst, std::abs((double)a.pixels[i] - b.pixels[i]) / std::max(1.0, std::abs((double)b.pixels[i])));
    }
    return worst;
}

// Scalar first: the reference, then the others; restores the automatic choice.
std::vector<std::string> lanesBuildsHere() {
    std::vector<std::string> found;
    for (const char* isa : {"baseline", "x86-64-v3", "x86-64-v4"})
        if (cpu::forceCpuIsa(isa)) found.push_back(isa);
    cpu::forceCpuIsa("");
    return found;
}

const cpu::IsaKernels& kernelsOf(const std::string& isa) {
    EXPECT_TRUE(cpu::forceCpuIsa(isa));
    const cpu::IsaKernels& k = cpu::cpuKernels();
    cpu::forceCpuIsa("");
    return k;
}

} // namespace

TEST(SsdoLanes, LaneBuildsEqualTheScalarBuildOverTilings) {
    const Frame f;
    const Ssdo reference = runSsdoTiles(f, kernelsOf("scalar"), f.p.width, f.p.height);
    float aoMin = 1;
    for (float a : reference.ao.pixels) aoMin = std::min(aoMin, a);
    EXPECT_LT(aoMin, 0.6f); // the scene occludes: the comparison is not of constants
    for (const std::string& isa : lanesBuildsHere()) {
        const Ssdo whole = runSsdoTiles(f, kernelsOf(isa), f.p.width, f.p.height);
        for (auto [tw, th] : {std::pair{64, 16}, {17, 5}, {5, 31}, {1, 1}}) {
            const Ssdo tiled = runSsdoTiles(f, kernelsOf(isa), tw, th);
            EXPECT_EQ(tiled.directional.pixels, whole.directional.pixels) << isa << " tiles " << tw << "x" << th;
            EXPECT_EQ(tiled.indirect.pixels, whole.indirect.pixels) << isa << " tiles " << tw << "x" << th;
            EXPECT_EQ(tiled.ao.pixels, whole.ao.pixels) << isa << " tiles " << tw << "x" << th;
        }
        bool finite = true;
        EXPECT_LT(worstDifference(whole.directional, reference.directional, finite), 1e-5) << isa << " DO";
        EXPECT_LT(worstDifference(whole.indirect, reference.indirect, finite), 1e-5) << isa << " GI";
        EXPECT_LT(worstDifference(whole.ao, reference.ao, finite), 1e-5) << isa << " AO";
        EXPECT_TRUE(finite) << isa;
    }
}

TEST(SsdoLanes, BlurLaneBuildsEqualTheScalarBuild) {
    const Frame f;
    for (int channels : {1, 3, 4}) {
        Image signal(f.p.width, f.p.height, channels);
        for (size_t i = 0; i < signal.pixels.size(); ++i) signal.pixels[i] = (float)((i * 2654435761u) % 997) * 1e-3f;
        auto blurWith = [&](const std::string& isa, int radius) {
            Image out = signal;
            EXPECT_TRUE(cpu::forceCpuIsa(isa));
            cpu::runBlur(f.p, f.sb.depth.view(), f.sb.normal.view(), out.view(), radius, 2);
            cpu::forceCpuIsa("");
            return out;
        };
        for (int radius : {1, 2, 5}) {
            const Image reference = blurWith("scalar", radius);
            for (const std::string& isa : lanesBuildsHere()) {
                bool finite = true;
                EXPECT_LT(worstDifference(blurWith(isa, radius), reference, finite), 1e-5)
                    << isa << ", " << channels << " channels, radius " << radius;
                EXPECT_TRUE(finite);
            }
        }
    }
}

// runOperator with 1 and 2 threads (the operator's own tiling): identical SSDO and blur.
TEST(SsdoLanes, ThreadCountsAgree) {
    const Frame f;
    OperatorInputs in = f.sb.inputs();
    in.radiance = f.radiance.view();
    in.albedo = f.albedo.view();
    in.environment = &f.env;
    Settings s;
    s.method = "ssdo";
    s.radius = 0.8f;
    s.bounce = true;
    s.threads = 1;
    const OperatorOutputs one = runOperator(in, s);
    s.threads = 2;
    const OperatorOutputs two = runOperator(in, s);
    EXPECT_EQ(one.directional.pixels, two.directional.pixels);
    EXPECT_EQ(one.indirect.pixels, two.indirect.pixels);
    EXPECT_EQ(one.ao.pixels, two.ao.pixels);
}

// The lane acos and exp (cpu/lanes.h, here at 4 lanes) against double-precision libm.
#define OBSCURA_LANES 4
#include "cpu/lanes.h"

TEST(SsdoLanes, LaneAcosAndExpMatchTheCLibrary) {
    namespace L = obscura::cpu::lanes;
    double worstAcos = 0, worstExp = 0;
    for (int i = 0; i <= 400000; i += 4) {
        L::lfloat x, e;
        for (int j = 0; j < 4; ++j) {
            x.v[j] = std::min(-1.0f + (float)(i + j) * 5e-6f, 1.0f);
            e.v[j] = -100.0f + (float)(i + j) * 2.7e-4f; // [-100, 8]
        }
        const L::lfloat a = L::acos(x), ex = L::exp(e);
        for (int j = 0; j < 4; ++j) {
            worstAcos = std::max(worstAcos, std::abs(a[j] - std::acos((double)x[j])));
            const double want = std::exp((double)e[j]);
            if (want > 1.3e-38) worstExp = std::max(worstExp, std::abs(ex[j] - want) / want);
            else EXPECT_GE(ex[j], 0.0f);
        }
    }
    EXPECT_LT(worstAcos, 1e-6);
    EXPECT_LT(worstExp, 5e-7);
    const L::lfloat edge = L::exp(L::lfloat(-1000.0f));
    EXPECT_EQ(edge[0], 0.0f);
    EXPECT_TRUE(std::isinf(L::exp(L::lfloat(100.0f))[0]));
    EXPECT_TRUE(std::isnan(L::exp(L::lfloat(NAN))[0]));
    EXPECT_FLOAT_EQ(L::acos(L::lfloat(1.0f))[0], 0.0f);
    EXPECT_FLOAT_EQ(L::acos(L::lfloat(-1.0f))[0], (float)M_PI);
}
