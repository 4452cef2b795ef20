// Normals reconstructed from the depth and the camera (kernels/depth_normal.glsl), for inputs
// without a normal pass: the surface's own normal wherever a side continues it, never a blend
// across a depth step or a crease; a plane stays exactly unoccluded with them for every method
// on every device; the GL text gives the CPU's normals and AO.
#include "core/methods.h"
#include "core/operator.h"
#include "cpu/depth_normal_cpu.h"
#include "gpu/gl_backend.h"
#include "support/gl_devices.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;

namespace {


// The scene's normals as the operator would reconstruct them, view space, on `device`.
Image depthNormals(const SceneBuffers& sb, const std::string& device) {
    OperatorInputs in = sb.inputs();
    in.normalSpace = NormalSpace::Depth;
    const KernelParams p = makeKernelParams(in, Settings());
    Image n(sb.depth.width, sb.depth.height, 3, 0.0f);
    if (device == "cpu") cpu::runDepthNormals(p, in.depth, n.view(), 2);
    else gpu::glBackendFor(device).runDepthNormals(p, in.depth, n.view());
    return n;
}

// The scene's true normals (its world normals) in view space.
glm::dvec3 trueViewNormal(const SceneBuffers& sb, int x, int y) {
    const float* n = sb.normal.at(x, y);
    const glm::dmat3 toView = glm::transpose(glm::dmat3(sb.camera.cameraToWorld));
    return glm::normalize(toView * glm::dvec3(n[0], n[1], n[2]));
}

bool surface(const SceneBuffers& sb, int x, int y) {
    if (x < 0 || y < 0 || x >= sb.depth.width || y >= sb.depth.height) return false;
    const float d = *sb.depth.at(x, y);
    return d > 0.0f && d < 1e9f;
}

// Whether the texel (x + k sx, y + k sy) lies on the plane of texel (x, y) (its world position
// on that plane, to 1e-5 of the distance), for k = 1 and 2: a side that continues the surface.
bool sideContinues(const SceneBuffers& sb, int x, int y, int sx, int sy) {
    const float* p0 = sb.position.at(x, y);
    const float* n0 = sb.normal.at(x, y);
    const double scale = 1e-5 * std::max(1.0, (double)*sb.depth.at(x, y));
    for (int k = 1; k <= 2; ++k) {
        if (!surface(sb, x + k * sx, y + k * sy)) return false;
        const float* p = sb.position.at(x + k * sx, y + k * sy);
        const double off = (p[0] - p0[0]) * n0[0] + (p[1] - p0[1]) * n0[1] + (p[2] - p0[2]) * n0[2];
        if (std::abs(off) > scale) return false;
    }
    return true;
}

double angleDeg(glm::dvec3 a, glm::dvec3 b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0, 1.0)) * 180.0 / M_PI;
}

} // namespace

// Every surface texel with a side that continues its plane along each axis gets that plane's
// normal, next to creases and silhouettes included: the studio scene's boxes, walls and floor
// through a perspective and an orthographic camera.
TEST(DepthNormals, EachTexelGetsItsOwnSurfacesNormal) {
    const int W = 160, H = 120;
    const std::vector<SceneBuffers> views = {
        renderScene(studioScene(), studioCamera(W, H), W, H),
        renderScene(studioScene(),
                    lookAtOrthographic(glm::dvec3(3.5, 3.0, 6.5), glm::dvec3(-1.0, 0.6, -1.0), 9.0, W, H), W, H)};
    for (const SceneBuffers& sb : views) {
        const Image n = depthNormals(sb, "cpu");
        int checked = 0, nearEdge = 0;
        double worst = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W; ++x) {
                if (!surface(sb, x, y)) {
                    EXPECT_EQ(n.at(x, y)[0] * n.at(x, y)[0] + n.at(x, y)[2] * n.at(x, y)[2], 0.0f);
                    continue;
                }
                const bool alongX = sideContinues(sb, x, y, 1, 0) || sideContinues(sb, x, y, -1, 0);
                const bool alongY = sideContinues(sb, x, y, 0, 1) || sideContinues(sb, x, y, 0, -1);
                if (!alongX || !alongY) continue;
                ++checked;
                const bool interior = sideContinues(sb, x, y, 1, 0) && sideContinues(sb, x, y, -1, 0) &&
                                      sideContinues(sb, x, y, 0, 1) && sideContinues(sb, x, y, 0, -1);
                nearEdge += !interior;
                const float* v = n.at(x, y);
                const double a = angleDeg(glm::dvec3(v[0], v[1], v[2]), trueViewNormal(sb, x, y));
                worst = std::max(worst, a);
                ASSERT_LT(a, 0.05) << "texel " << x << "," << y << (interior ? "" : " (beside an edge)");
            }
        EXPECT_GT(checked, W * H / 2);
        EXPECT_GT(nearEdge, 300) << "the edges are what this tests";
        std::printf("%d texels, %d beside an edge: worst %.2e degrees\n", checked, nearEdge, worst);
    }
}


// A pole one or two pixels wide, its front face square to the view, in front of a wall: no
// side of a pixel continues its plane along x, and both neighbours of the one-pixel pole lie far
// behind it. Its normals face the eye across the pole (within the pixel's angle off the axis),
// never tilted towards the wall; the two-pixel pole's come from the step across its face. On
// every device, as the GL text gives the CPU's normals.
TEST(DepthNormals, PolesAPixelOrTwoWideFaceTheEye) {
    const int W = 64, H = 48;
    const Camera cam = lookAtPerspective(glm::dvec3(0.0), glm::dvec3(0, 0, -1), 50.0 * M_PI / 180, W, H);
    for (int widthPx : {1, 2}) {
        const double front = 6.0, width = widthPx * front / cam.fx;  // columns W/2 .. W/2 + widthPx - 1
        std::vector<Rect> scene = {planeRect(glm::dvec3(0, 0, -9), glm::dvec3(1, 0, 0), glm::dvec3(0, 1, 0))};
        addBox(scene, glm::dvec3(1e-9, -3, -front - width), glm::dvec3(width - 1e-9, 3, -front));
        const SceneBuffers sb = renderScene(scene, cam, W, H);
        for (const std::string& device : cpuAndGlDevices()) {
            const Image n = depthNormals(sb, device);
            int checked = 0;
            for (int y = 4; y < H - 4; ++y)
                for (int x = W / 2; x < W / 2 + widthPx; ++x) {
                    ASSERT_NEAR(*sb.depth.at(x, y), front, 1e-3) << "the pole covers column " << x;
                    const float* v = n.at(x, y);
                    const double a = angleDeg(glm::dvec3(v[0], v[1], v[2]), glm::dvec3(0, 0, 1));
                    EXPECT_LT(a, 2.0) << widthPx << " px pole, texel " << x << "," << y << " on " << device;
                    ++checked;
                }
            EXPECT_EQ(checked, (H - 8) * widthPx);
            EXPECT_GT(*sb.depth.at(W / 2 - 1, H / 2), 8.9f);  // the wall beside it
            EXPECT_GT(*sb.depth.at(W / 2 + widthPx, H / 2), 8.9f);
        }
    }
}

// The GL text gives the CPU's normals (to float rounding), and every GL method the CPU's AO with them.
TEST(DepthNormals, GlMatchesCpu) {
    const int W = 160, H = 120;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image cpu = depthNormals(sb, "cpu");
    for (const std::string& device : glDevicesUnderTest()) {
        const Image gl = depthNormals(sb, device);
        // Continuous maths, no thresholds: within 1e-5 in IEEE single precision, and within 1e-4
        // on a GPU whose square root and division are approximate (an H200 gave 2.2e-5).
        const double tol = gpu::glBackendFor(device).info().software ? 1e-5 : 1e-4;
        EXPECT_LE(maxAbsDiff(cpu, gl), tol) << device;
    }
    OperatorInputs in = sb.inputs();
    in.normal = ConstPlane{};
    in.normalSpace = NormalSpace::Depth;
    for (const MethodInfo& m : methods()) {
        if (!m.gl) continue;
        Settings s;
        s.method = m.name;
        s.radius = 0.8f;
        s.ssdoSamples = 16;
        const OperatorOutputs c = runOperator(in, s);
        EXPECT_TRUE(c.stats.normalsFromDepth);
        for (const std::string& device : glDevicesUnderTest()) {
            s.device = device;
            const OperatorOutputs g = runOperator(in, s);
            ASSERT_EQ(g.stats.device.rfind(device, 0), 0u) << "ran on " << g.stats.device;
            EXPECT_TRUE(glParity(c.ao, g.ao, 1e-3, device)) << m.name;
        }
    }
}

// A plane's reconstructed normals are its normal: every method leaves it unoccluded on every
// device it runs on (ssao in its hemisphere form, as tests/test_stiff.cpp holds it; ssdo's AO
// counts samples the pixel grid can hide, so it is held to its AO with the plane's true normals).
TEST(DepthNormals, PlanesStayUnoccludedForEveryMethodOnEveryDevice) {
    for (bool ortho : {false, true})
        for (double tiltDeg : {0.0, 45.0, 80.0})
            for (double dist : {0.5, 200.0}) {
                const SceneBuffers sb = tiltedPlaneView(tiltDeg, dist, ortho, 64, 48);
                OperatorInputs in = sb.inputs();
                in.normal = ConstPlane{};
                in.normalSpace = NormalSpace::Depth;
                for (const MethodInfo& m : methods())
                    for (const std::string& device : cpuAndGlDevices()) {
                        if (device != "cpu" && !m.gl) continue;
                        Settings s;
                        s.method = m.name;
                        s.device = device;
                        s.radius = (float)(0.2 * dist);
                        s.weighting = Weighting::Cosine;
                        s.ssaoHemisphere = true;
                        s.rtaoRays = 8;
                        s.ssdoSamples = 16;
                        const Image ao = runOperator(in, s).ao;
                        const float lo = *std::min_element(ao.pixels.begin(), ao.pixels.end());
                        float floor = 1.0f;
                        if (std::string(m.name) == "ssdo") {
                            const Image given = runOperator(sb.inputs(), s).ao;
                            floor = *std::min_element(given.pixels.begin(), given.pixels.end());
                        }
                        // 2e-4: float rounding of the sample offsets (tests/test_hbao_analytic.cpp's bound).
                        EXPECT_GE(lo, floor - 2e-4f) << m.name << " on " << device << " ortho=" << ortho
                                                     << " tilt=" << tiltDeg << " dist=" << dist;
                    }
            }
}

namespace {

using obscura::test::CliResult;

CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

// The studio scene as a generic-named file: Z and R, G, B, and N.X, N.Y, N.Z `withNormals`.
std::string writeStudio(const std::filesystem::path& dir, const SceneBuffers& sb, bool withNormals) {
    using namespace fixtures;
    FixturePart part;
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(sb.depth.width - 1, sb.depth.height - 1));
    auto channel = [](const std::string& name, const Image& img, int c) {
        return FixtureChannel{name, Imf::FLOAT, 1, 1, [&img, c](int x, int y) { return img.at(x, y)[c]; }};
    };
    part.channels.push_back(channel("Z", sb.depth, 0));
    for (int c = 0; c < 3; ++c) {
        part.channels.push_back({std::string(1, "RGB"[c]), Imf::HALF, 1, 1, [](int, int) { return 0.5f; }});
        if (withNormals) part.channels.push_back(channel(std::string("N.") + "XYZ"[c], sb.normal, c));
    }
    const std::string path = (dir / (withNormals ? "with_normals.exr" : "depth_only.exr")).string();
    writeFixture(path, {part});
    return path;
}

std::vector<float> aoOf(const std::string& path) { return obscura::test::partChannel(path, 0, "obscura.AO.Y"); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

} // namespace

// A plate with depth and no normal pass, and only a field of view: obscura reconstructs the
// normals, says so in the log, the report and --inspect, and writes the AO that --normals depth
// gives for the same frame with a normal pass.
TEST(DepthNormalsCli, AFileWithoutNormalsGetsTheAoOfNormalsDepth) {
    const auto dir = obscura::test::testDir("depth-normals");
    const int W = 64, H = 48;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const std::string bare = writeStudio(dir, sb, false), full = writeStudio(dir, sb, true);
    const std::string fov = std::to_string(sb.camera.horizontalFovRad(W) * 180.0 / M_PI);
    const std::string a = (dir / "a.exr").string(), b = (dir / "b.exr").string(), report = (dir / "a.json").string();
    const CliResult ra = cli({bare, "-o", a, "--fov-deg", fov, "--out-type", "float", "--report", report});
    ASSERT_EQ(ra.exitCode, 0) << ra.err;
    EXPECT_TRUE(contains(ra.err, "normals reconstructed from depth")) << ra.err;
    const CliResult rb = cli({full, "-o", b, "--fov-deg", fov, "--out-type", "float", "--normals", "depth", "--quiet"});
    ASSERT_EQ(rb.exitCode, 0) << rb.err;
    EXPECT_EQ(aoOf(a), aoOf(b));

    std::ifstream in(report);
    const nlohmann::json j = nlohmann::json::parse(in);
    EXPECT_EQ(j["conventions"]["normals"], "depth");
    EXPECT_EQ(j["plan"][0], "normals: reconstructed from depth (no normal layer)");

    const CliResult inspect = cli({bare, "--inspect"});
    ASSERT_EQ(inspect.exitCode, 0) << inspect.err;
    EXPECT_TRUE(contains(inspect.out, "\nnormals: reconstructed from depth (no normal layer)\n")) << inspect.out;
    const CliResult asked = cli({full, "--inspect", "--json", "--normals", "depth"});
    ASSERT_EQ(asked.exitCode, 0) << asked.err;
    const nlohmann::json conventions = nlohmann::json::parse(asked.out)["conventions"];
    EXPECT_EQ(conventions["normals"], "depth");
    EXPECT_EQ(conventions["normals_source"], "normals: reconstructed from depth (--normals depth)");
    const CliResult given = cli({full, "--inspect"});
    EXPECT_TRUE(contains(given.out, "\nnormals: layer 'N', world space\n")) << given.out;

    const CliResult bad = cli({full, "-o", a, "--normals", "sideways"});
    EXPECT_EQ(bad.exitCode, 2);
    EXPECT_TRUE(contains(bad.err, "world, camera or depth")) << bad.err;
}
