// HBAO's samples past the buffer's edge (--border): open sky, the edge texel's depth (clamp)
// or its tangent plane continued (tangent), against what an overscan of the same frame shows;
// and the reference renderer's overscan, which the report measures the policies against.
#include "core/operator.h"
#include "cpu/hbao_border.h"
#include "io/frame_job.h"
#include "support/cli_runner.h"
#include "support/reference_runs.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

namespace fs = std::filesystem;

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

Settings borderSettings(int border, Weighting w = Weighting::Cosine) {
    Settings s = hbaoSettings(w, Falloff::None, 1.0f);
    s.border = border;
    return s;
}

} // namespace

// The tangent plane of a plane is the plane: continued past the edge it occludes nothing, so a
// plane stays exactly unoccluded up to the frame's edge (open sky trivially does too).
TEST(HbaoBorder, TangentKeepsPlanesExactAtTheEdge) {
    for (bool ortho : {false, true})
        for (double tiltDeg : {0.0, 45.0, 80.0})
            for (double dist : {0.5, 200.0}) {
                SceneBuffers sb = tiltedPlaneView(tiltDeg, dist, ortho, 64, 48);
                for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
                    Settings st = borderSettings(kBorderTangent, w);
                    st.radius = (float)(0.3 * dist);
                    OperatorOutputs out = runOperator(sb.inputs(), st);
                    const float minAo = *std::min_element(out.ao.pixels.begin(), out.ao.pixels.end());
                    EXPECT_GE(minAo, 1.0f - 2e-4f) << "ortho=" << ortho << " tilt=" << tiltDeg << " dist=" << dist
                                                  << " w=" << toString(w);
                }
            }
}

// A frame whose buffer stops at the display window's edge, against the same frame with the
// surroundings in the buffer (what overscan gives): in the band within reach of the edge,
// continuing the edge's tangent plane (floor and wall of the corner scene are planes) comes
// closer to the overscan result than open sky, and the edge's depth alone lies in between.
TEST(HbaoBorder, TangentRecoversMostOfWhatOverscanShows) {
    const auto& [full, part, crop] = cornerCrop();
    const Settings open = borderSettings(kBorderOpen);
    const OperatorOutputs whole = runOperator(full.inputs(), open);
    double error[3] = {0, 0, 0};
    int pixels = 0;
    for (int border : {kBorderOpen, kBorderClamp, kBorderTangent}) {
        const OperatorOutputs cropped = runOperator(part.inputs(), borderSettings(border));
        // 12 px: the band the edge's policy reaches
        error[border] = meanEdgeBandError(full, whole.ao, crop, cropped.ao, 12, &pixels);
    }
    std::printf("mean |AO - overscan AO| within 12 px of the edge: open %.4f, clamp %.4f, tangent %.4f (%d px)\n",
                error[kBorderOpen], error[kBorderClamp], error[kBorderTangent], pixels);
    ASSERT_GT(pixels, 1000);
    EXPECT_GT(error[kBorderOpen], 0.005) << "the edge must matter to compare";  // measured 0.0089
    EXPECT_LT(error[kBorderTangent], 0.5 * error[kBorderOpen]);
    EXPECT_LT(error[kBorderClamp], error[kBorderOpen]);
}

// Overscan comes first: where the data window reaches past every sample, the policy is never asked.
TEST(HbaoBorder, PolicyOnlyActsPastTheBuffer) {
    const int W = 120, H = 90;
    const Camera cam = cornerCamera(W, H);
    const SceneBuffers overscan = renderScene(cornerScene(), cam, Box2i{0, 0, W, H}, Box2i{-60, -60, W + 60, H + 60});
    Settings s = borderSettings(kBorderOpen);
    s.maxRadiusPixels = 50;  // every sample of a display pixel then lies in the data window
    const OperatorOutputs open = runOperator(overscan.inputs(), s);
    s.border = kBorderTangent;
    const OperatorOutputs tangent = runOperator(overscan.inputs(), s);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) ASSERT_EQ(*open.ao.at(x + 60, y + 60), *tangent.ao.at(x + 60, y + 60)) << x << "," << y;
}

// The flag takes one of its three words; a number outside them or any other word is a usage
// error that lists the words.
TEST(HbaoBorder, FlagValues) {
    const std::string in = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";
    const std::string out = std::string(OBSCURA_TEST_TMP) + "/hbao-border.exr";
    for (const char* ok : {"open", "clamp", "tangent"}) {
        const CliResult c = runProgram(OBSCURA_CLI_PATH, {in, "-o", out, "--border", ok, "--quality", "low", "--quiet"});
        EXPECT_EQ(c.exitCode, 0) << ok << ": " << c.err;
    }
    for (const char* bad : {"wide", "", "7"}) {
        const CliResult c = runProgram(OBSCURA_CLI_PATH, {in, "-o", out, "--border", bad});
        EXPECT_EQ(c.exitCode, 2) << bad << ": " << c.err;
        EXPECT_NE(c.err.find("--border"), std::string::npos) << c.err;
        EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
    }
    const CliResult word = runProgram(OBSCURA_CLI_PATH, {in, "-o", out, "--border", "wide"});
    EXPECT_NE(word.err.find("open|clamp|tangent"), std::string::npos) << word.err;
}

// reference_render --overscan N renders a data window N pixels larger each way around the same
// display window: the display window's pixels (each seeded by its display coordinates) are
// those of the render without overscan, bit for bit, and the margin is real geometry.
TEST(HbaoBorder, ReferenceOverscanWidensTheDataWindowOnly) {
    const fs::path dir = fs::path(OBSCURA_TEST_TMP) / ("ref-overscan-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const int W = 48, H = 36, N = 6;
    auto render = [&](const std::string& name, int overscan) {
        const std::string path = (dir / name).string();
        const CliResult r = runProgram(referenceRenderPath(),
                                       {"--scene", "corner", "-o", path, "--width", std::to_string(W), "--height",
                                        std::to_string(H), "--ao-rays", "8", "--gi-rays", "1", "--overscan",
                                        std::to_string(overscan), "--quiet"});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        FrameJob job;
        job.input = path;
        job.preset = "blender";
        job.referenceLayer = "Reference.AO_cosine_none";
        return loadFramePasses(job, false);
    };
    const FramePasses plain = render("plain.exr", 0), wide = render("wide.exr", N);
    EXPECT_EQ(wide.display, plain.display);
    EXPECT_EQ(plain.data, plain.display);
    EXPECT_EQ(wide.data, (Box2i{-N, -N, W + N, H + N}));
    int surfaceInMargin = 0;
    for (int y = -N; y < H + N; ++y)
        for (int x = -N; x < W + N; ++x) {
            const float d = *wide.depth.at(x + N, y + N);
            if (x < 0 || y < 0 || x >= W || y >= H) {
                surfaceInMargin += d > 0.0f && d < 1e9f;
                continue;
            }
            ASSERT_EQ(d, *plain.depth.at(x, y)) << x << "," << y;
            ASSERT_EQ(*wide.reference.at(x + N, y + N), *plain.reference.at(x, y)) << x << "," << y;
        }
    EXPECT_GT(surfaceInMargin, N * (W + H)) << "the margin must see the floor and the wall";
    fs::remove_all(dir);
}

// The border is written once around the depth plane (cpu/hbao_border.h). A floor's tangent plane
// is the floor: past the frame's edge the written depths are the floor's, as an overscan render
// of the same view shows them (sky stays sky); clamp writes the nearest edge texel's depth;
// open writes nothing. The written box reaches past each edge by at most the sphere's largest
// screen radius (plus rounding), not by the whole frame.
TEST(HbaoBorder, BorderIsWrittenOnceAroundTheDepthPlane) {
    const int W = 64, H = 48, over = 100;
    const Camera cam = lookAtPerspective(dvec3(0.3, 3.0, 4.0), dvec3(0.0, 0.0, -1.0), 1.2, W, H);
    const std::vector<Rect> floor = {planeRect(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 0, 1))};
    const SceneBuffers frame = renderScene(floor, cam, W, H);
    const SceneBuffers wide = renderScene(floor, cam, Box2i{0, 0, W, H}, Box2i{-over, -over, W + over, H + over});
    const OperatorInputs in = frame.inputs();
    const cpu::IsaKernels& k = cpu::cpuKernelsFor({in.depth, in.normal});

    const glsl::KernelParams open = makeKernelParams(in, borderSettings(kBorderOpen));
    const cpu::BorderedDepth none = cpu::continueBorder(open, in.depth, in.normal, 2, k);
    EXPECT_FALSE(none.box.valid());
    EXPECT_EQ(cpu::depthBoxOf(none.params), (Box2i{0, 0, W, H}));

    const glsl::KernelParams p = makeKernelParams(in, borderSettings(kBorderTangent));
    const cpu::BorderedDepth tangent = cpu::continueBorder(p, in.depth, in.normal, 2, k);
    const Box2i box = cpu::depthBoxOf(tangent.params);
    const int reach = (int)std::ceil(cpu::hbaoReachPixels(p, in.depth)) + 2;
    EXPECT_GT(reach, 3);
    EXPECT_TRUE(box.x0 < 0 && box.y0 < 0 && box.x1 > W && box.y1 > H);
    EXPECT_TRUE(box.x0 >= -reach && box.y0 >= -reach && box.x1 <= W + reach && box.y1 <= H + reach);
    ASSERT_LE(reach, over);
    int floorTexels = 0;
    for (int y = box.y0; y < box.y1; ++y)
        for (int x = box.x0; x < box.x1; ++x) {
            const float written = *tangent.depth.at(x, y);
            if (x >= 0 && y >= 0 && x < W && y < H) {
                ASSERT_EQ(written, *in.depth.at(x, y)) << x << "," << y;
                continue;
            }
            const float truth = *wide.depth.at(x + over, y + over);
            const int ex = std::clamp(x, 0, W - 1), ey = std::clamp(y, 0, H - 1);
            if (!(*in.depth.at(ex, ey) < 1e9f)) {
                EXPECT_EQ(written, *in.depth.at(ex, ey)) << "sky continues as sky at " << x << "," << y;
                continue;
            }
            if (!(truth < 1e9f)) continue;  // the floor's plane met beyond the horizon: the edge's depth stands
            EXPECT_NEAR(written, truth, 1e-4 * truth) << x << "," << y;
            ++floorTexels;
        }
    EXPECT_GT(floorTexels, 2 * (W + H));

    const glsl::KernelParams c = makeKernelParams(in, borderSettings(kBorderClamp));
    const cpu::BorderedDepth clamp = cpu::continueBorder(c, in.depth, in.normal, 2, k);
    const Box2i cbox = cpu::depthBoxOf(clamp.params);
    EXPECT_EQ(cbox, box);
    for (int y = cbox.y0; y < cbox.y1; ++y)
        for (int x = cbox.x0; x < cbox.x1; ++x)
            ASSERT_EQ(*clamp.depth.at(x, y), *in.depth.at(std::clamp(x, 0, W - 1), std::clamp(y, 0, H - 1)))
                << x << "," << y;
}
