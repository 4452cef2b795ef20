// HBAO's samples past the buffer's edge (--border): open sky, the edge texel's depth (clamp)
// or its tangent plane continued (tangent), against what an overscan of the same frame shows;
// and the reference renderer's overscan, which the report measures the policies against.
#include "core/operator.h"
#include "cpu/lane_cpu.h"
#include "io/frame_job.h"
#include "support/cli_runner.h"
#include "support/gl_devices.h"
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

// A floor seen from 0.4 above it with R = 1, its horizon 10 degrees above the frame: marches
// from the top rows end above that horizon, where no ray meets the plane. The plane runs to
// infinity before them and, continued towards its horizon, still occludes nothing (it was
// taken at the edge texel's depth there, a wall that darkened the top rows to 0.79).
TEST(HbaoBorder, AFloorContinuedTowardsItsHorizonStaysOpen) {
    const int W = 160, H = 90;
    const double hfov = 40.0 * M_PI / 180;
    const double f = 0.5 * W / std::tan(0.5 * hfov);
    const double pitch = std::atan(0.5 * H / f) + 10.0 * M_PI / 180;
    const dvec3 eye(0, 0.4, 0);
    const Camera cam = lookAtPerspective(eye, eye + dvec3(0, -std::sin(pitch), -std::cos(pitch)), hfov, W, H);
    SceneBuffers sb = renderScene({planeRect(dvec3(0), dvec3(1, 0, 0), dvec3(0, 0, -1), 1e4)}, cam, W, H);
    std::vector<std::string> devices{"cpu"};
    for (const std::string& d : glDevicesUnderTest()) devices.push_back(d);
    for (const std::string& device : devices)
        for (Falloff falloff : {Falloff::None, Falloff::Linear}) {
            Settings st = borderSettings(kBorderTangent);
            st.falloff = falloff;
            st.device = device;
            const OperatorOutputs out = runOperator(sb.inputs(), st);
            const float minAo = *std::min_element(out.ao.pixels.begin(), out.ao.pixels.end());
            EXPECT_GE(minAo, 1.0f - 2e-4f) << device << (falloff == Falloff::Linear ? " linear" : " none");
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
        return loadFramePasses(job, {});
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

// Past the edge nothing is read but edge texels (kernels/hbao.glsl, continuedChord): the same
// frame in a buffer with a guard band of NaN around it (depth and normals, strided views into it)
// gives bit for bit the AO of the frame alone, under every policy, for a floor that runs out of
// the frame and a radius whose sphere spans the frame (the lanes leave early and far).
TEST(HbaoBorder, NothingPastTheEdgeIsRead) {
    const int W = 64, H = 48, pad = 80;
    const Camera cam = lookAtPerspective(dvec3(0.3, 3.0, 4.0), dvec3(0.0, 0.0, -1.0), 1.2, W, H);
    std::vector<Rect> scene = {planeRect(dvec3(0.0), dvec3(1, 0, 0), dvec3(0, 0, 1))};
    addBox(scene, dvec3(-0.5, 0.0, -0.5), dvec3(0.5, 0.6, 0.5));
    const SceneBuffers frame = renderScene(scene, cam, W, H);
    const OperatorInputs in = frame.inputs();
    const int PW = W + 2 * pad, PH = H + 2 * pad;
    std::vector<float> depth((size_t)PW * PH, NAN), normal((size_t)PW * PH * 3, NAN);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            depth[(size_t)(y + pad) * PW + x + pad] = *in.depth.at(x, y);
            for (int c = 0; c < 3; ++c) normal[((size_t)(y + pad) * PW + x + pad) * 3 + c] = in.normal.at(x, y)[c];
        }
    const ConstPlane guardedDepth{depth.data() + (size_t)pad * PW + pad, W, H, 1, 1, PW};
    const ConstPlane guardedNormal{normal.data() + ((size_t)pad * PW + pad) * 3, W, H, 3, 3, 3 * (std::ptrdiff_t)PW};
    for (int border : {kBorderOpen, kBorderClamp, kBorderTangent})
        for (Falloff f : {Falloff::None, Falloff::Linear})
            for (float thickness : {INFINITY, kThicknessAuto}) {
                Settings s = hbaoSettings(Weighting::Cosine, f, 3.0f);
                s.border = border;
                s.thickness = thickness;
                const glsl::KernelParams p = makeKernelParams(in, s);
                Image alone(W, H, 1), guarded(W, H, 1);
                cpu::runHbao(p, in.depth, in.normal, alone.view(), 2);
                cpu::runHbao(p, guardedDepth, guardedNormal, guarded.view(), 2);
                double darkest = 1.0;
                for (int i = 0; i < W * H; ++i) {
                    ASSERT_EQ(alone.pixels[i], guarded.pixels[i]) << "border " << border << " texel " << i;
                    darkest = std::min(darkest, (double)alone.pixels[i]);
                }
                EXPECT_LT(darkest, 0.9) << "the box must occlude the floor";
            }
}

// The edge texels the CPU tables once per frame for the continued border: every texel on the
// buffer's edge, in the documented order (top row, bottom row, left column, right column), with
// its depth and normal as read in place from strided planes.
TEST(HbaoBorder, EdgeTexelsAreTheBuffersEdge) {
    const int W = 7, H = 5;
    std::vector<float> depth((size_t)W * H), normal((size_t)W * H * 4);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            depth[(size_t)y * W + x] = float(1 + x + 100 * y);
            for (int c = 0; c < 3; ++c) normal[((size_t)y * W + x) * 4 + c] = float(c + 10 * x + 1000 * y);
        }
    // Normals in a 4-channel plane, as an RGBA layer arrives.
    const ConstPlane d{depth.data(), W, H, 1, 1, W};
    const ConstPlane n{normal.data(), W, H, 4, 4, 4 * (std::ptrdiff_t)W};
    const Image edges = cpu::hbaoEdgeTexels(d, n);
    ASSERT_EQ(edges.width, 2 * (W + H));
    ASSERT_EQ(edges.channels, 4);
    int i = 0;
    const auto expectRecord = [&](int x, int y) {
        const float* r = edges.at(i++, 0);
        EXPECT_EQ(r[0], *d.at(x, y)) << "record " << i - 1;
        for (int c = 0; c < 3; ++c) EXPECT_EQ(r[1 + c], n.at(x, y)[c]) << "record " << i - 1 << " channel " << c;
    };
    for (int x = 0; x < W; ++x) expectRecord(x, 0);
    for (int x = 0; x < W; ++x) expectRecord(x, H - 1);
    for (int y = 0; y < H; ++y) expectRecord(0, y);
    for (int y = 0; y < H; ++y) expectRecord(W - 1, y);
}
