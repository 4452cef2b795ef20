// HBAO's indirect light with deep input (docs/deep.md, kernels/hbao_deep_step.glsl):
// a hidden lit solid lights the floor beside it as the corner's closed form says, deep input of
// one surface per pixel gives the flat input's light, OpenGL gives the CPU's, and the colours
// come out of deep files (read with --flat, and merged from elements rendered apart).
#include "core/operator.h"
#include "cpu/lane_cpu.h"
#include "gpu/gl_backend.h"
#include "io/deep_file.h"
#include "support/gl_devices.h"
#include "support/cli_runner.h"
#include "support/closed_forms.h"
#include "support/deep_elements.h"
#include "support/read_back.h"
#include "support/roof_scene.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

Settings deepGiSettings(float radius, float thickness, int dirs = 32, int steps = 32) {
    Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, radius, dirs, steps);
    s.thickness = thickness;
    s.bounce = true;
    return s;
}

// The roof scene lit: the roof (the visible layer over the right half) radiates `roofL` and the
// block under it (layer 1) `blockL`, grey; the floor radiates nothing.
struct LitRoof {
    RoofScene scene{3.0f, 1.5f};
    Image source{RoofScene::W, RoofScene::H, 3, 0.0f}, colour{RoofScene::W, RoofScene::H, 6, 0.0f};
    LitRoof(float roofL, float blockL) {
        for (int y = 0; y < RoofScene::H; ++y)
            for (int x = RoofScene::W / 2; x < RoofScene::W; ++x)
                for (int c = 0; c < 3; ++c) {
                    source.at(x, y)[c] = roofL;
                    colour.at(x, y)[3 + c] = blockL;
                }
    }
    OperatorOutputs run(bool deep, bool coloured, const Settings& s) const {
        OperatorInputs in = scene.inputs(deep);
        in.radiance = source.view();
        if (coloured) in.deepColour = colour.view();
        return runOperator(in, s);
    }
};

} // namespace

// A lit block hidden under a roof beyond R: the flat input's floor beside it gets no light (the
// roof is out of reach); with deep input the block is a wall of height >= R radiating L, whose
// light within R is pi L times the corner's cosine occlusion (tests/test_hbao_gi.cpp's closed
// form). Without the deep file's colour the block still hides, and sends nothing.
TEST(HbaoDeepGi, HiddenLitBlockMatchesTheCornerClosedForm) {
    const float R = 1.0f, L = 2.0f;
    const LitRoof lit(50.0f, L);
    for (float T : {kThicknessInfinite, 0.5f}) {
        const Settings s = deepGiSettings(R, T);
        const OperatorOutputs flat = lit.run(false, false, s), deep = lit.run(true, true, s),
                              dark = lit.run(true, false, s);
        EXPECT_EQ(deep.ao.pixels, dark.ao.pixels) << "the colour changes no AO";
        for (double d : {0.1, 0.25, 0.5, 0.75}) {
            const double at = (std::lround(d * RoofScene::kPixelsPerUnit - 0.5) + 0.5) / RoofScene::kPixelsPerUnit;
            const double expected = M_PI * L * (1.0 - cornerAo(Weighting::Cosine, Falloff::None, at / R));
            EXPECT_LE(RoofScene::columnMean(flat.indirect, d), 1e-4) << "d=" << d << " T=" << T;
            EXPECT_LE(RoofScene::columnMean(dark.indirect, d), 1e-4) << "d=" << d << " T=" << T;
            // AO's tolerance in the same scene (0.02, tests/test_deep.cpp) times pi L.
            EXPECT_NEAR(RoofScene::columnMean(deep.indirect, d), expected, 0.02 * M_PI * L) << "d=" << d << " T=" << T;
        }
    }
}

// Deep input of one surface per pixel (the visible one, point samples) lights as flat input does:
// the light takes each texel's point, not its footprint, so the same intervals get the same light.
TEST(HbaoDeepGi, OneLayerPerPixelGivesTheFlatLight) {
    const int W = 160, H = 120;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.0f}});
    Image source(W, H, 3, 1.0f);
    for (size_t i = 0; i < source.pixels.size(); i += 3) source.pixels[i] = 0.25f;  // coloured
    for (float T : {kThicknessInfinite, 0.3f}) {
        OperatorInputs in = sb.inputs();
        in.radiance = source.view();
        const Settings s = deepGiSettings(0.8f, T, 8, 8);
        const OperatorOutputs flat = runOperator(in, s);
        in.deepLayers = deep.view();
        const OperatorOutputs withDeep = runOperator(in, s);
        double most = 0;
        for (float v : flat.indirect.pixels) most = std::max(most, (double)v);
        ASSERT_GT(most, 0.1) << "the studio's walls light its floor";
        EXPECT_LE(maxAbsDiff(flat.indirect, withDeep.indirect), 1e-5 * M_PI) << "T " << T;
    }
}

// One kernel text on both devices: deep input's light within 1e-3 of the CPU's, with and without
// a thickness and the blur, on the roof scene and on the studio with layers behind its surfaces.
TEST(HbaoDeepGi, OpenGlMatchesCpu) {
    const LitRoof lit(0.5f, 2.0f);
    const int W = 160, H = 120;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.0f}, {0.05f, 0.3f}, {0.5f, 0.5f}});
    Image source(W, H, 3, 1.0f), colour(W, H, 9, 0.5f);
    for (size_t i = 0; i < source.pixels.size(); i += 3) source.pixels[i] = 0.25f;
    for (float T : {kThicknessInfinite, 0.5f})
        for (int blur : {0, 1})
            for (bool studio : {false, true}) {
                Settings s = deepGiSettings(1.0f, T, 8, 8);
                s.blur = blur;
                OperatorInputs in = sb.inputs();
                in.deepLayers = deep.view();
                in.radiance = source.view();
                in.deepColour = colour.view();
                const OperatorOutputs cpu = studio ? runOperator(in, s) : lit.run(true, true, s);
                for (const std::string& device : glDevicesUnderTest()) {
                    s.device = device;
                    const OperatorOutputs gl = studio ? runOperator(in, s) : lit.run(true, true, s);
                    ASSERT_EQ(gl.stats.device.rfind(device, 0), 0u) << gl.stats.device;
                    const std::string what = device + (studio ? " studio" : " roof") + " T " +
                                             std::to_string(T) + " blur " + std::to_string(blur);
                    EXPECT_TRUE(glParity(cpu.ao, gl.ao, 1e-3, device)) << what;
                    EXPECT_TRUE(glParity(cpu.indirect, gl.indirect, 1e-3 * M_PI, device)) << what;
                }
            }
}

// Several GL tiles, each with its apron, read the layers and each layer's radiance word at the
// right offsets: the backends called directly, on words of grey 0.25, 0.5 and 0.75 for layers 0..2
// (and no normals' words: the light per sample does not read them).
TEST(HbaoDeepGi, GlTilesReadEachLayersWord) {
    const int W = 160, H = 120;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.0f}, {0.05f, 0.3f}, {0.5f, 0.5f}});
    OperatorInputs in = sb.inputs();
    in.deepLayers = deep.view();
    const KernelParams p = makeKernelParams(in, deepGiSettings(1.0f, 0.5f, 8, 8));
    ASSERT_EQ(p.deepLayers, 3);
    Image words(W, H, 3), facing(W, H, 1, 0.0f);
    for (size_t i = 0; i < words.pixels.size(); ++i) {
        const uint32_t m = 64u * (uint32_t)(i % 3 + 1), bits = 16u << 27 | m | m << 9 | m << 18;  // m 2^(16 - 24)
        std::memcpy(&words.pixels[i], &bits, sizeof bits);
    }
    Image ao(W, H, 1), gi(W, H, 3, 0.0f), glAo(W, H, 1), glGi(W, H, 3, 0.0f);
    cpu::runHbaoGi(p, in.depth, in.normal, in.deepLayers, words.view(), facing.view(), ao.view(), gi.view(), 0);
    gpu::GlTimings t;
    gpu::glBackendFor(firstGlDevice())
        .runHbaoGi(p, in.depth, in.normal, in.deepLayers, words.view(), facing.view(), glAo.view(), glGi.view(), 0, &t,
                   110 * 110);
    EXPECT_GT(t.tiles, 1);
    double most = 0;
    for (float v : gi.pixels) most = std::max(most, (double)v);
    EXPECT_GT(most, 0.1);
    EXPECT_TRUE(glParity(ao, glAo, 1e-3, firstGlDevice()));
    EXPECT_TRUE(glParity(gi, glGi, 1e-3 * M_PI, firstGlDevice()));
}

// A deep file's colour per surface: the samples of one surface composited front to back, then
// un-premultiplied; none read unless asked.
TEST(HbaoDeepGi, DeepFileColourIsEachSurfacesUnpremultipliedRgb) {
    const std::string path = (testDir("deep_gi") / "colour.exr").string();
    // One pixel: a half-transparent red surface continued by a touching blue one, then a green solid.
    writeDeepElement(
        path,
        [](const double*) {
            return std::vector<DeepSample>{{2.0f, 2.5f, 0.5f, 0.0f, 0.0f, 0.5f},
                                           {2.5f, 3.0f, 0.0f, 0.0f, 1.0f, 1.0f},
                                           {5.0f, 6.0f, 0.0f, 0.8f, 0.0f, 1.0f}};
        },
        1, 1);
    EXPECT_TRUE(readDeepLayers(path, 4).colour.empty());
    const DeepLayers d = readDeepLayers(path, 4, {}, kDefaultMaxPixels, true);
    ASSERT_EQ(d.layers, 2);
    ASSERT_EQ(d.colour.channels, 6);
    // Over: (0.5, 0, 0, 0.5) + 0.5 (0, 0, 1, 1) = (0.5, 0, 0.5, 1).
    const float* c = d.colour.at(0, 0);
    EXPECT_FLOAT_EQ(c[0], 0.5f);
    EXPECT_FLOAT_EQ(c[1], 0.0f);
    EXPECT_FLOAT_EQ(c[2], 0.5f);
    EXPECT_FLOAT_EQ(c[4], 0.8f);
}

namespace {

// Deep elements rendered apart: the ground, a red wall and a blue board in front of it that hides
// it from the camera, not from the ground beside it.
std::vector<DeepSample> redWall(const double d[3]) {
    const double lo[3] = {0.3, -1, -8.3}, hi[3] = {2.0, 0.2, -7.7};
    return deepBox(d, lo, hi, 1, 0, 0);
}
std::vector<DeepSample> blueBoard(const double d[3]) {
    const double lo[3] = {0.14, -0.7, -4.05}, hi[3] = {1.5, 0.4, -3.95};
    return deepBox(d, lo, hi, 0, 0, 1);
}

// The ground pixels beside the wall, where the camera sees the ground.
std::vector<bool> groundBesideWall(int W, int H) {
    const DeepHit groundAlone = [](const double* ray) {
        std::vector<DeepSample> g = deepGround(ray);
        const bool seen = !g.empty() && redWall(ray).empty() && blueBoard(ray).empty();
        return seen && g[0].z > 7.7f && g[0].z < 8.3f ? g : std::vector<DeepSample>{};
    };
    return deepCoverage(groundAlone, W, H, [](double x) { return x > -0.4 && x < 0.25; });
}

} // namespace

// The merge's layers carry each element's colour: the red wall, hidden behind the board, lights
// the ground beside it red; the flattened frame (its visible surfaces alone, as a flat render)
// lights nothing there. A deep file without colour sends nothing from behind.
TEST(HbaoDeepGi, MergedElementsLightWithTheHiddenWallsColour) {
    const int W = 160, H = 96;
    const fs::path dir = testDir("deep_gi");
    const std::string ground = (dir / "ground.exr").string(), wall = (dir / "wall.exr").string(),
                      board = (dir / "board.exr").string(), out = (dir / "lit.exr").string(),
                      flat = (dir / "flat.exr").string();
    writeDeepElement(ground, deepGround, W, H);
    writeDeepElement(wall, redWall, W, H);
    writeDeepElement(board, blueBoard, W, H);
    const std::vector<std::string> args = {"--fov-deg", "40", "--radius", "1", "--blur", "0", "--falloff", "none",
                                           "--method", "hbao", "--bounce-source", "beauty",
                                           "--out-layer", "gi=GI", "--quiet"};
    std::vector<std::string> merged = {ground, wall, board, "-o", out}, alone = {ground, wall, board, "-o", flat,
                                                                                   "--deep-layers", "1"};
    merged.insert(merged.end(), args.begin(), args.end());
    alone.insert(alone.end(), args.begin(), args.end());
    CliResult r = runObscura(merged);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    r = runObscura(alone);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    const std::vector<bool> beside = groundBesideWall(W, H);
    ASSERT_GT(std::count(beside.begin(), beside.end(), true), 20);
    const double red = meanOver(partChannel(out, 0, "GI.R"), beside), blue = meanOver(partChannel(out, 0, "GI.B"), beside);
    const double flatRed = meanOver(partChannel(flat, 0, "GI.R"), beside);
    EXPECT_GT(red, 0.1) << "the hidden wall's red light";
    EXPECT_LT(flatRed, 0.01 * red) << "one layer: the wall stays hidden";
    EXPECT_LT(blue, 0.01 * red) << "the board is out of reach";
}

namespace {

// A deep ground element alone (R, G, B, A, Z: no flat passes) as `name`.exr, and the command
// line that lights it with hbao into `name`_out.exr, which does not exist yet.
struct GroundElement {
    std::string in, out;
    std::vector<std::string> args;
    explicit GroundElement(const std::string& name) {
        const fs::path dir = testDir("deep_gi");
        in = (dir / (name + ".exr")).string();
        out = (dir / (name + "_out.exr")).string();
        writeDeepElement(in, deepGround, 32, 24);
        fs::remove(out);
        args = {in, "-o", out, "--fov-deg", "40", "--falloff", "none", "--method", "hbao"};
    }
    // The command with `more` flags: a refusal in one line naming the input, nothing written.
    CliResult refused(const std::vector<std::string>& more) const {
        std::vector<std::string> all = args;
        all.insert(all.end(), more.begin(), more.end());
        const CliResult r = runObscura(all);
        EXPECT_NE(r.exitCode, 0);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(in), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
        return r;
    }
};

} // namespace

// A --bounce-source pass the flat passes lack is one line naming the file, and nothing is written.
TEST(HbaoDeepGi, MissingBounceSourceIsOneLine) {
    const GroundElement ground("bad_ground");
    const CliResult r = ground.refused({"--bounce-source", "direct_diffuse", "--out-layer", "gi=GI"});
    EXPECT_NE(r.err.find("direct_diffuse"), std::string::npos) << r.err;
}

// --bounce on deep elements alone (RGBA, no direct-diffuse or albedo pass): one line naming both
// flags to add, nothing written; the line's own advice then runs.
TEST(HbaoDeepGi, BounceOnDeepElementsSaysWhatToAdd) {
    const GroundElement ground("rgba_ground");
    const CliResult r = ground.refused({"--bounce"});
    EXPECT_NE(r.err.find("--bounce-source beauty"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--out-layer gi=NAME"), std::string::npos) << r.err;
    std::vector<std::string> advised = ground.args;
    advised.insert(advised.end(), {"--bounce-source", "beauty", "--out-layer", "gi=GI", "--quiet"});
    const CliResult ok = runObscura(advised);
    EXPECT_EQ(ok.exitCode, 0) << outcome(ok);
    EXPECT_TRUE(fs::exists(ground.out));
}
