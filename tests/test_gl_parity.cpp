// The GL path computes the same numbers as the CPU path: same kernels/ text, same
// hash noise, same sample positions. These run on llvmpipe through OSMesa and
// through Mesa's EGL device; a GL path that silently fell back to the CPU fails.
#include "base/error.h"
#include "core/operator.h"
#include "gpu/gl_backend.h"
#include "gpu/gl_context.h"
#include "gpu/gl_program.h"
#include "io/exr_file.h"
#include "io/frame_job.h"
#include "support/gl_devices.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace obscura;
using namespace obscura::test;

namespace {


// The studio scene through a perspective and an orthographic camera.
std::vector<SceneBuffers> studioViews(int W, int H) {
    std::vector<SceneBuffers> views;
    views.push_back(renderScene(studioScene(), studioCamera(W, H), W, H));
    views.push_back(renderScene(
        studioScene(), lookAtOrthographic(glm::dvec3(3.5, 3.0, 6.5), glm::dvec3(-1.0, 0.6, -1.0), 9.0, W, H), W, H));
    return views;
}

Settings makeSettings(const char* device, Weighting w, Falloff f, int blur) {
    Settings s;
    s.device = device;
    s.radius = 0.8f;
    s.weighting = w;
    s.falloff = f;
    s.blur = blur;
    return s;
}

// Runs `s` on every GL device and expects each one's AO within 1e-3 of the CPU's; `label` says
// which case failed.
void expectGlAoMatchesCpu(const OperatorInputs& in, Settings s, const OperatorOutputs& cpu, const std::string& label) {
    for (const std::string& device : glDevicesUnderTest()) {
        s.device = device;
        const OperatorOutputs gl = runOperator(in, s);
        ASSERT_EQ(gl.stats.device.rfind(device, 0), 0u) << "ran on " << gl.stats.device;
        EXPECT_TRUE(glParity(cpu.ao, gl.ao, 1e-3, device)) << label;
    }
}

} // namespace

TEST(GlParity, AnalyticScenesMatchCpu) {
    const std::vector<SceneBuffers> views = studioViews(160, 120);
    for (const SceneBuffers* scene : {&views[0], &views[1]}) {
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
            for (Falloff f : {Falloff::Linear, Falloff::None}) {
                for (int blur : {0, 3}) {
                    const Settings s = makeSettings("cpu", w, f, blur);
                    const OperatorOutputs cpu = runOperator(scene->inputs(), s);
                    expectGlAoMatchesCpu(scene->inputs(), s, cpu,
                                         std::string(toString(w)) + " " + toString(f) + " blur " + std::to_string(blur));
                }
            }
        }
    }
}

// The visibility bitmask (a finite thickness) is the same kernel text on both devices: a fixed
// thickness and the automatic one (runs of samples), both weightings, both falloffs, both cameras.
TEST(GlParity, ThicknessMatchesCpu) {
    const std::vector<SceneBuffers> views = studioViews(160, 120);
    for (const SceneBuffers* scene : {&views[0], &views[1]})
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
            for (Falloff f : {Falloff::None, Falloff::Linear}) {
                Settings h = makeSettings("cpu", w, f, 0);
                h.thickness = kThicknessInfinite;
                const OperatorOutputs horizon = runOperator(scene->inputs(), h);
                for (float thickness : {0.15f, kThicknessAuto}) {
                    Settings s = makeSettings("cpu", w, f, 0);
                    s.thickness = thickness;
                    const OperatorOutputs cpu = runOperator(scene->inputs(), s);
                    EXPECT_GT(maxAbsDiff(cpu.ao, horizon.ao), 0.05) << "the thickness must change the result to compare";
                    expectGlAoMatchesCpu(scene->inputs(), s, cpu,
                                         std::string(toString(w)) + " " + toString(f) + " T " + std::to_string(thickness));
                }
            }
}

// Deep input's layers reach the GL kernel through the signal-in buffer: the visible layer as a
// slab, a point surface and a span behind it, both weightings, both cameras, and tiles.
TEST(GlParity, DeepLayersMatchCpu) {
    const std::vector<SceneBuffers> views = studioViews(160, 120);
    for (const SceneBuffers* scene : {&views[0], &views[1]}) {
        const Image deep = deepLayersFromDepth(scene->depth, {{0.0f, 0.1f}, {0.4f, 0.4f}, {0.8f, 1.6f}});
        OperatorInputs in = scene->inputs();
        in.deepLayers = deep.view();
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
            const Settings s = makeSettings("cpu", w, Falloff::None, 0);
            const OperatorOutputs cpu = runOperator(in, s);
            EXPECT_GT(maxAbsDiff(cpu.ao, runOperator(scene->inputs(), s).ao), 0.05) << "the layers must change the result";
            expectGlAoMatchesCpu(in, s, cpu, toString(w));
            // Several tiles, each with its apron, read the layers at the right offsets.
            gpu::GlBackend& backend = gpu::glBackendFor(firstGlDevice());
            const KernelParams p = makeKernelParams(in, s);
            Image tiled(160, 120, 1);
            gpu::GlTimings t;
            backend.runHbaoDeep(p, in.depth, in.normal, in.deepLayers, tiled.view(), 0, &t, 110 * 110);
            EXPECT_GT(t.tiles, 1);
            EXPECT_TRUE(glParity(cpu.ao, tiled, 1e-3, firstGlDevice())) << "tiled " << toString(w);
        }
    }
}

// The border policies read the edge texel's depth and normal past the buffer on both devices.
TEST(GlParity, BorderPoliciesMatchCpu) {
    const std::vector<SceneBuffers> views = studioViews(160, 120);
    for (const SceneBuffers* scene : {&views[0], &views[1]})
        for (int border : {kBorderOpen, kBorderClamp, kBorderTangent}) {
            Settings s = makeSettings("cpu", Weighting::Cosine, Falloff::None, 0);
            s.border = border;
            const OperatorOutputs cpu = runOperator(scene->inputs(), s);
            expectGlAoMatchesCpu(scene->inputs(), s, cpu, "border " + std::to_string(border));
        }
}

// A frame cut into many tiles with aprons gives exactly the one-tile result.
TEST(GlParity, TilesEqualOneTile) {
    const int W = 200, H = 150;
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(W, H), W, H);
    const KernelParams p = makeKernelParams(scene.inputs(), makeSettings("cpu", Weighting::Cosine, Falloff::Linear, 2));
    gpu::GlBackend& gl = gpu::glBackendFor(firstGlDevice());
    Image whole(W, H, 1), tiled(W, H, 1);
    gpu::GlTimings oneTile, manyTiles;
    gl.runHbao(p, scene.depth.view(), scene.normal.view(), whole.view(), 2, &oneTile);
    gl.runHbao(p, scene.depth.view(), scene.normal.view(), tiled.view(), 2, &manyTiles, 110 * 110);
    EXPECT_EQ(oneTile.tiles, 1);
    EXPECT_GT(manyTiles.tiles, 4);
    EXPECT_EQ(whole.pixels, tiled.pixels);
}

// Through the file layer: a multipart, tiled, half-float file with overscan.
TEST(GlParity, MultilayerFileMatchesCpu) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(OBSCURA_TEST_TMP) / ("gl-parity-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const int W = 128, H = 96, over = 8;
    const Box2i display{0, 0, W, H}, data{-over, -over, W + over, H + over};
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(W, H), display, data);
    auto plane = [&](const Image& img, int c) {
        return [&img, c, data](int x, int y) { return img.at(x - data.x0, y - data.y0)[c]; };
    };
    fixtures::FixturePart beauty, passes;
    beauty.name = "rgba";
    for (const char* c : {"R", "G", "B"}) {
        fixtures::FixtureChannel ch;
        ch.name = c;
        beauty.channels.push_back(ch);
    }
    passes.name = "passes";
    passes.tiled = true;
    passes.tileWidth = passes.tileHeight = 32;
    auto channel = [](std::string name, std::function<float(int, int)> value) {
        fixtures::FixtureChannel c;
        c.name = std::move(name);
        c.type = Imf::HALF;
        c.value = std::move(value);
        return c;
    };
    passes.channels = {channel("Z", plane(scene.depth, 0))};
    for (int c = 0; c < 3; ++c) passes.channels.push_back(channel(std::string("N.") + "XYZ"[c], plane(scene.normal, c)));
    for (fixtures::FixturePart* part : {&beauty, &passes}) {
        part->displayWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(W - 1, H - 1));
        part->dataWindow = Imath::Box2i(Imath::V2i(-over, -over), Imath::V2i(W + over - 1, H + over - 1));
    }
    const std::string input = (dir / "scene.exr").string();
    fixtures::writeFixture(input, {beauty, passes});

    const glm::dmat4& m = scene.camera.cameraToWorld;
    std::array<double, 16> rows{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) rows[r * 4 + c] = m[c][r];
    std::vector<Image> results;
    for (const std::string& device : cpuAndGlDevices()) {
        FrameJob job;
        job.input = input;
        job.output = (dir / (device + ".exr")).string();
        job.camera.fovDeg = 65.0;
        job.camera.cameraToWorld = rows;
        job.settings = makeSettings(device.c_str(), Weighting::Cosine, Falloff::None, 0);
        job.aoFloat = true;
        const FrameReport report = runFrameJob(job);
        ASSERT_EQ(report.stats.device.rfind(device, 0), 0u) << report.stats.device;
        const ExrInfo info = readExrInfo(job.output);
        results.push_back(std::move(readExrChannels(job.output, info, {{1, "obscura.AO.Y"}}, false, nullptr)[0]));
    }
    ASSERT_EQ(results[0].width, W + 2 * over);
    double minAo = 1;
    for (float v : results[0].pixels) minAo = std::min(minAo, (double)v);
    EXPECT_LT(minAo, 0.6);  // the scene really is occluded somewhere
    for (size_t d = 1; d < results.size(); ++d) EXPECT_TRUE(glParity(results[0], results[d], 1e-3, cpuAndGlDevices()[d]));
    fs::remove_all(dir);
}

// An explicit GL device that cannot be made fails with one line; auto falls back and says why.
TEST(GlParity, DeviceChoiceIsExplicit) {
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(32, 24), 32, 24);
    Settings s = makeSettings("auto", Weighting::Uniform, Falloff::Linear, 0);
    const OperatorOutputs out = runOperator(scene.inputs(), s);
    if (out.stats.device.rfind("cpu", 0) == 0) {
        ASSERT_EQ(out.stats.notes.size(), 1u);
        EXPECT_NE(out.stats.notes[0].find("--device auto"), std::string::npos);
    } else {
        EXPECT_EQ(out.stats.device.rfind("gl-egl", 0), 0u);  // a hardware EGL device is present
    }
    s.device = "vulkan";
    EXPECT_THROW(runOperator(scene.inputs(), s), Error);
}

// SSDO (DO, GI and AO, with its interleaving blur) matches the CPU on both GL paths.
TEST(GlParity, SsdoMatchesCpu) {
    const int W = 128, H = 96;
    const SceneBuffers scene = renderScene(studioScene(), studioCamera(W, H), W, H);
    Image radiance(W, H, 3), albedo(W, H, 3), env(64, 32, 3);
    for (int i = 0; i < W * H; ++i)
        for (int c = 0; c < 3; ++c) {
            radiance.pixels[3 * i + c] = 0.2f + 0.3f * c + 0.5f * scene.normal.pixels[3 * i + 1];
            albedo.pixels[3 * i + c] = 0.8f - 0.2f * c;
        }
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) env.at(x, y)[c] = 0.5f + 0.5f * std::sin(0.2f * x + c) * std::cos(0.3f * y);
    OperatorInputs in = scene.inputs();
    in.radiance = radiance.view();
    in.albedo = albedo.view();
    in.environment = &env;
    Settings s;
    s.method = "ssdo";
    s.radius = 0.8f;
    s.bounce = true;
    s.lights.push_back({{0.3f, 0.9f, 0.2f}, {1.0f, 0.9f, 0.8f}});
    const OperatorOutputs cpu = runOperator(in, s);
    for (const std::string& device : glDevicesUnderTest()) {
        s.device = device;
        const OperatorOutputs gl = runOperator(in, s);
        ASSERT_EQ(gl.stats.device.rfind(device, 0), 0u) << gl.stats.device;
        EXPECT_TRUE(glParity(cpu.ao, gl.ao, 1e-3, device));
        EXPECT_TRUE(glParity(cpu.directional, gl.directional, 1e-3, device));
        EXPECT_TRUE(glParity(cpu.indirect, gl.indirect, 1e-3, device));
    }
}

// SSAO (kernels/ssao.glsl) on both GL paths equals the CPU's lane build, in the sphere and
// the hemisphere, for both weightings and falloffs, perspective and orthographic.
TEST(GlParity, SsaoMatchesCpu) {
    const std::vector<SceneBuffers> views = studioViews(128, 96);
    for (const SceneBuffers* scene : {&views[0], &views[1]})
        for (bool hemisphere : {false, true})
            for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
                for (Falloff f : {Falloff::Linear, Falloff::None}) {
                    Settings s = makeSettings("cpu", w, f, 0);
                    s.method = "ssao";
                    s.ssaoHemisphere = hemisphere;
                    const OperatorOutputs cpu = runOperator(scene->inputs(), s);
                    ASSERT_LT(*std::min_element(cpu.ao.pixels.begin(), cpu.ao.pixels.end()), 0.9f)
                        << "the scene must have occlusion to compare";
                    expectGlAoMatchesCpu(scene->inputs(), s, cpu,
                                         std::string(hemisphere ? "hemisphere " : "sphere ") + toString(w) + " " +
                                             toString(f));
                }
}

// Disc AO: the GL program reads the CPU's pyramid and runs the same kernels/discs.glsl, so it
// equals the CPU within 1e-3 with every correction switched off in turn, the second pass and
// the blur, the plain sum and uniform weighting, through a pinhole and an orthographic camera.
TEST(GlParity, DiscsMatchCpu) {
    const std::vector<SceneBuffers> views = studioViews(128, 96);
    for (const SceneBuffers* scene : {&views[0], &views[1]})
        for (int variant = 0; variant < 7; ++variant) {
            Settings s = makeSettings("cpu", variant == 6 ? Weighting::Uniform : Weighting::Cosine,
                                      variant == 4 ? Falloff::Linear : Falloff::None, variant == 4 ? 2 : 0);
            s.method = "discs";
            s.discsPasses = variant == 1 ? 2 : 1;
            s.discsNoPolygon = variant == 2;
            s.discsBlendLevels = variant == 3;
            s.discsSum = variant == 5;
            const OperatorOutputs cpu = runOperator(scene->inputs(), s);
            ASSERT_LT(*std::min_element(cpu.ao.pixels.begin(), cpu.ao.pixels.end()), 0.9f)
                << "the scene must have occlusion to compare (variant " << variant << ", view " << (scene - &views[0]) << ")";
            expectGlAoMatchesCpu(scene->inputs(), s, cpu, "variant " + std::to_string(variant));
        }
}
