// Stiff and extreme inputs, through the operator on every device this machine has
// (the CPU and llvmpipe through OSMesa). Each case asserts finite output in [0, 1]
// and a property that a numerical weakness would break.
#include "core/methods.h"
#include "core/operator.h"
#include "support/expect_error.h"
#include "support/gl_devices.h"
#include "support/scenes.h"

#include <Imath/half.h>
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <limits>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

class Stiff : public ::testing::TestWithParam<std::string> {
protected:
    OperatorOutputs run(const SceneBuffers& sb, float radius, Weighting w = Weighting::Cosine,
                        Falloff f = Falloff::None, int dirs = 8, int steps = 8) const {
        Settings s;
        s.device = GetParam();
        s.radius = radius;
        s.weighting = w;
        s.falloff = f;
        s.directions = dirs;
        s.steps = steps;
        s.blur = 0;  // the kernel's own values at each pixel
        OperatorOutputs out = runOperator(sb.inputs(), s);
        EXPECT_EQ(out.stats.device.rfind(GetParam(), 0), 0u) << out.stats.device;
        return out;
    }
};

// Every value finite and in [0, 1]; returns the minimum.
float checkedMin(const Image& ao) {
    float m = 1.0f;
    for (float v : ao.pixels) {
        EXPECT_TRUE(v >= 0.0f && v <= 1.0f) << v;
        m = std::min(m, v);
    }
    return m;
}

std::vector<Rect> ground() { return {planeRect(dvec3(0), dvec3(1, 0, 0), dvec3(0, 0, 1), 1e7)}; }

// The endless floor a millimetre under a camera pitched so that the centre ray of row 2 meets it
// 1e-9 rad below the horizon: depths from 1e-3 to beyond 1e5 in one frame (100 degrees wide).
SceneBuffers nineDecadePlane(int W, int H) {
    const double fovRad = 100.0 * M_PI / 180, f = 0.5 * W / std::tan(0.5 * fovRad);
    const double pitch = std::atan((0.5 * H - 2.5) / f) + 1e-9;
    const dvec3 eye(0, 1e-3, 0);
    return renderScene(ground(), lookAtPerspective(eye, eye + dvec3(0, -std::sin(pitch), -std::cos(pitch)), fovRad, W, H),
                       W, H);
}

std::vector<Rect> corner() {
    const double L = 1e3;
    return {Rect{dvec3(-L, 0, -L), dvec3(L, 0, 0), dvec3(0, 0, 2 * L)},
            Rect{dvec3(0, 0, -L), dvec3(0, L, 0), dvec3(0, 0, 2 * L)}};
}

} // namespace

// One frame spanning depth 1e-3 .. 1e6: a camera a millimetre above an endless floor,
// pitched so that one row's centre ray meets the floor 1e-9 rad below the horizon.
TEST_P(Stiff, DepthRangeOfNineDecadesKeepsThePlaneUnoccluded) {
    const int W = 96, H = 64;
    const double fovRad = 100.0 * M_PI / 180, f = 0.5 * W / std::tan(0.5 * fovRad);
    const double rowAngle = std::atan((0.5 * H - 2.5) / f);  // centre ray of row 2, above the axis
    const double pitch = rowAngle + 1e-9;
    const dvec3 eye(0, 1e-3, 0);
    Camera cam = lookAtPerspective(eye, eye + dvec3(0, -std::sin(pitch), -std::cos(pitch)), fovRad, W, H);
    SceneBuffers sb = renderScene(ground(), cam, W, H);
    float lo = 1e30f, hi = 0;
    for (float d : sb.depth.pixels)
        if (d < 1e9f) lo = std::min(lo, d), hi = std::max(hi, d);
    ASSERT_LT(lo, 2e-3f);
    ASSERT_GT(hi, 1e5f);
    for (float R : {1e-4f, 1e-2f, 10.0f, 1e4f}) EXPECT_GE(checkedMin(run(sb, R).ao), 1.0f - 1e-3f) << "R=" << R;
}

// Surfaces within half a degree of the view ray still see no occlusion from themselves.
TEST_P(Stiff, GrazingPlaneStaysUnoccluded) {
    const int W = 96, H = 64;
    for (double grazeDeg : {0.5, 2.0}) {
        // A plane through the target, tilted so its normal is 90 - grazeDeg from the view axis.
        const double t = (90.0 - grazeDeg) * M_PI / 180;
        const dvec3 n(std::sin(t), 0.0, std::cos(t));
        const dvec3 s = glm::normalize(glm::cross(n, dvec3(0, 1, 0)));
        Camera cam = lookAtPerspective(dvec3(0, 0, 5), dvec3(0), 20.0 * M_PI / 180, W, H);
        SceneBuffers sb = renderScene({planeRect(dvec3(0), s, glm::cross(n, s), 1e7)}, cam, W, H);
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
            for (Falloff f : {Falloff::Linear, Falloff::None})
                EXPECT_GE(checkedMin(run(sb, 0.5f, w, f).ao), 1.0f - 1e-3f) << grazeDeg << " deg";
    }
}

// Radius far below a pixel gives exactly 1; far beyond the frame stays bounded and still
// sees the corner. In between, AO rises monotonically as R shrinks (continuity to 1).
TEST_P(Stiff, ExtremeRadii) {
    const int W = 80, H = 60;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(corner(), cam, W, H);
    EXPECT_EQ(checkedMin(run(sb, 1e-6f).ao), 1.0f);
    const float huge = checkedMin(run(sb, 1e6f).ao);
    EXPECT_LT(huge, 0.7f);  // the wall is inside R from every floor pixel
    double previous = 0;
    for (float R : {3.0f, 1.0f, 0.3f, 0.1f, 0.03f, 0.01f, 0.003f}) {
        const Image ao = run(sb, R).ao;
        double mean = 0;
        for (float v : ao.pixels) mean += v;
        mean /= ao.pixels.size();
        EXPECT_GE(mean, previous - 1e-4) << "R=" << R;
        previous = mean;
    }
    EXPECT_GT(previous, 0.999);
}

// Fields of view from 1 to 170 degrees and orthographic: a plane stays at 1, and the
// corner's edge at d = R/2 keeps its closed form (cosine weighting, no falloff).
TEST_P(Stiff, FieldsOfViewAndOrthographic) {
    const int W = 96, H = 72;
    for (double fovDeg : {1.0, 30.0, 90.0, 170.0, 0.0 /* orthographic */}) {
        const dvec3 target(-0.5, 0, 0);
        const dvec3 dir = glm::normalize(dvec3(-1.0, 0.9, 0.55));
        // Keep the corner's neighbourhood in frame: distance from the field of view.
        const double dist = fovDeg > 0 ? 2.5 / std::tan(0.5 * fovDeg * M_PI / 180) : 10.0;
        Camera cam = fovDeg > 0 ? lookAtPerspective(target + dist * dir, target, fovDeg * M_PI / 180, W, H)
                                : lookAtOrthographic(target + dist * dir, target, 5.0, W, H);
        SceneBuffers plane = renderScene(ground(), cam, W, H);
        EXPECT_GE(checkedMin(run(plane, 0.4f).ao), 1.0f - 1e-3f) << "fov " << fovDeg;
        SceneBuffers sb = renderScene(corner(), cam, W, H);
        const Image ao = run(sb, 1.0f, Weighting::Cosine, Falloff::None, 16, 16).ao;
        double sum = 0;
        int n = 0;
        for (double z = -0.6; z <= 0.6; z += 0.05) {
            int x, y;
            if (!sb.pixelOf(dvec3(-0.5, 0, z), x, y)) continue;
            sum += *ao.at(x, y);
            ++n;
        }
        ASSERT_GT(n, 5) << "fov " << fovDeg;
        const double c = 0.5;
        const double expected = 0.5 + (c * std::sqrt(1 - c * c) + std::asin(c)) / M_PI;
        // 0.06: 16 slices x 16 steps on a coarse 96 px frame, where the strip at d = 0.5 spans only a
        // few pixels at the widest field of view; a lost horizon would be off by more than 0.15.
        EXPECT_NEAR(sum / n, expected, 0.06) << "fov " << fovDeg;
    }
}

// Degenerate frame shapes, including one wider than 16384 (a common texture limit).
TEST_P(Stiff, DegenerateFrameShapes) {
    for (auto [W, H] : {std::pair{1, 1}, {1, 37}, {37, 1}, {16385, 3}}) {
        Camera cam = lookAtPerspective(dvec3(0, 2, 3), dvec3(0, 0, 0), 60.0 * M_PI / 180, W, H);
        SceneBuffers sb = renderScene(corner(), cam, W, H);
        const Image ao = run(sb, 0.5f).ao;
        ASSERT_EQ((int)ao.pixels.size(), W * H);
        checkedMin(ao);
        SceneBuffers plane = renderScene(ground(), cam, W, H);
        EXPECT_GE(checkedMin(run(plane, 0.5f).ao), 1.0f - 1e-3f) << W << "x" << H;
    }
}

// Depth stored as float16 (as many pipelines do) gives nearly the float32 result.
TEST_P(Stiff, HalfDepthMatchesFloatDepth) {
    const int W = 160, H = 120;
    SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image full = run(sb, 0.8f, Weighting::Cosine, Falloff::Linear).ao;
    for (float& d : sb.depth.pixels)
        if (d < 1e9f) d = (float)Imath::half(d);
    const Image halfDepth = run(sb, 0.8f, Weighting::Cosine, Falloff::Linear).ao;
    double sum = 0, worst = 0;
    for (size_t i = 0; i < full.pixels.size(); ++i) {
        const double e = std::abs(full.pixels[i] - halfDepth.pixels[i]);
        sum += e;
        worst = std::max(worst, e);
    }
    // float16 keeps 11 bits: depth moves by up to 2.4e-4 relative, i.e. ~1.5 mm at 6 units,
    // well under the 10 cm the AO varies over; the mean stays at the noise level.
    EXPECT_LT(sum / full.pixels.size(), 2e-3);
    EXPECT_LT(worst, 0.05);
}

// Every sky convention (0, +inf, 1e10, NaN) is background: AO 1 there, and the
// surrounding pixels get the same AO whichever convention marks the sky.
TEST_P(Stiff, SkyConventionsAreEquivalent) {
    const int W = 96, H = 72;
    SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image reference = run(sb, 0.8f).ao;
    std::vector<size_t> sky;
    for (size_t i = 0; i < sb.depth.pixels.size(); ++i)
        if (sb.depth.pixels[i] >= 1e9f) sky.push_back(i);
    ASSERT_GT(sky.size(), 50u);
    for (float convention : {0.0f, std::numeric_limits<float>::infinity(), 1e10f, std::numeric_limits<float>::quiet_NaN()}) {
        for (size_t i : sky) {
            sb.depth.pixels[i] = convention;
            for (int c = 0; c < 3; ++c) sb.normal.pixels[3 * i + c] = 0.0f;
        }
        const Image ao = run(sb, 0.8f).ao;
        EXPECT_EQ(ao.pixels, reference.pixels) << "sky depth " << convention;
    }
}

// The CPU and one GL device (gl-osmesa unless OBSCURA_TEST_GL_DEVICES says otherwise).
INSTANTIATE_TEST_SUITE_P(Devices, Stiff, ::testing::Values(std::string("cpu"), firstGlDevice()), [](const auto& info) {
    std::string name = info.param;
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
});

// SSAO through the same frames: the hemisphere form keeps planes (endless, grazing) exactly
// unoccluded; both forms stay in [0, 1] at extreme radii and see the corner.
TEST_P(Stiff, SsaoPlanesAndCorner) {
    const int W = 96, H = 64;
    Settings s;
    s.device = GetParam();
    s.method = "ssao";
    s.ssaoHemisphere = true;
    s.weighting = Weighting::Cosine;
    s.falloff = Falloff::None;
    for (double grazeDeg : {0.5, 2.0, 30.0}) {
        const double t = (90.0 - grazeDeg) * M_PI / 180;
        const dvec3 n(std::sin(t), 0.0, std::cos(t));
        const dvec3 side = glm::normalize(glm::cross(n, dvec3(0, 1, 0)));
        Camera cam = lookAtPerspective(dvec3(0, 0, 5), dvec3(0), 20.0 * M_PI / 180, W, H);
        SceneBuffers sb = renderScene({planeRect(dvec3(0), side, glm::cross(n, side), 1e7)}, cam, W, H);
        for (float R : {1e-3f, 0.5f, 1e4f}) {
            s.radius = R;
            EXPECT_GE(checkedMin(runOperator(sb.inputs(), s).ao), 1.0f) << grazeDeg << " deg, R " << R;
        }
    }
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(corner(), cam, W, H);
    for (bool hemisphere : {false, true})
        for (float R : {1e-4f, 1.0f, 1e6f}) {
            s.ssaoHemisphere = hemisphere;
            s.radius = R;
            const float lo = checkedMin(runOperator(sb.inputs(), s).ao);
            if (R == 1.0f) {
                EXPECT_LT(lo, 0.9f) << "the corner occludes";
            }
        }
}

// SSAO's sphere form on a plane facing the camera hides the points below the plane and no
// others, so AO is exactly 1 whatever the points' weights (linear falloff) or number (odd N:
// the halves differ by a point); and where R spans less than a pixel (1e-30: R^2 underflows), 1.
TEST_P(Stiff, SsaoSphereKeepsAFacingPlane) {
    const int W = 96, H = 64;
    Camera cam = lookAtPerspective(dvec3(0, 0, 5), dvec3(0), 40.0 * M_PI / 180, W, H);
    SceneBuffers sb = renderScene({planeRect(dvec3(0), dvec3(1, 0, 0), dvec3(0, 1, 0), 1e3)}, cam, W, H);
    Settings s;
    s.device = GetParam();
    s.method = "ssao";
    s.ssaoHemisphere = false;
    for (Falloff f : {Falloff::None, Falloff::Linear})
        for (int n : {15, 16})
            for (float R : {0.5f, 2.0f, 1e-30f}) {
                s.falloff = f;
                s.ssaoSamples = n;
                s.radius = R;
                EXPECT_GE(checkedMin(runOperator(sb.inputs(), s).ao), 1.0f)
                    << (f == Falloff::Linear ? "linear" : "none") << ", N " << n << ", R " << R;
            }
}

// Every method of the method table, on every device it runs on: the nine-decade plane stays
// unoccluded (ssao in its hemisphere form; ssdo's AO counts samples the pixel grid can hide,
// so it is held to the range only), and the corner at extreme radii stays finite in [0, 1].
TEST_P(Stiff, EveryMethodStaysInRange) {
    const int W = 96, H = 64;
    SceneBuffers plane = nineDecadePlane(W, H);
    SceneBuffers edge = renderScene(corner(), cornerCamera(W, H), W, H);
    for (const MethodInfo& m : methods()) {
        if (GetParam() != "cpu" && !m.gl) continue;
        Settings s;
        s.device = GetParam();
        s.method = m.name;
        s.weighting = Weighting::Cosine;
        s.ssaoHemisphere = true;
        s.thickness = 0.1f;
        s.rtaoRays = 8;
        for (float R : {1e-4f, 1e-2f, 10.0f, 1e4f}) {
            s.radius = R;
            const float lo = checkedMin(runOperator(plane.inputs(), s).ao);
            if (std::string(m.name) != "ssdo") {
                EXPECT_GE(lo, 1.0f - 1e-3f) << m.name << " R=" << R;
            }
            checkedMin(runOperator(edge.inputs(), s).ao);
        }
    }
}

// The blur at the smallest positive depths (denormals, FLT_MIN), which a renderer's bad pixels
// can hold and --bad-pixels skip lets through: its depth tolerance must not overflow into NaN
// (a whole row of it, found by tests/fuzz once the default blur was 1).
TEST_P(Stiff, BlurAtTinyDepthsStaysFinite) {
    const int W = 48, H = 32;
    SceneBuffers sb = renderScene(corner(), cornerCamera(W, H), W, H);
    for (int x = 0; x < W; x += 3) *sb.depth.at(x, H / 2) = x % 2 ? 1e-45f : 1.17549435e-38f;
    *sb.depth.at(W / 2 + 1, H / 2) = *sb.depth.at(W / 2, H / 2);  // a neighbour at the same tiny depth
    Settings s;
    s.device = GetParam();
    s.radius = 0.5f;
    for (int blur : {1, 3}) {
        s.blur = blur;
        checkedMin(runOperator(sb.inputs(), s).ao);
    }
}

// HBAO's indirect light (--method hbao --bounce) on the same stiff frames: the nine-decade plane
// receives nothing, the corner at extreme radii and through holes (NaN, negative and infinite
// depths, a NaN in the source) stays finite, non-negative and below the furnace's pi L.
TEST_P(Stiff, HbaoBounceStaysFiniteAndBounded) {
    const int W = 96, H = 64;
    SceneBuffers plane = nineDecadePlane(W, H);
    SceneBuffers edge = renderScene(corner(), cornerCamera(W, H), W, H);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float holes[] = {nan, -1.0f, std::numeric_limits<float>::infinity(), 1e-45f};
    for (int i = 0; i < 4; ++i) *edge.depth.at(10 + 7 * i, H / 2) = holes[i];
    const float L = 3.0f;
    Image source(W, H, 3, L);
    source.at(W / 2, H / 3)[1] = nan; // a bad source texel (a renderer's NaN) sends no light
    Settings s;
    s.device = GetParam();
    s.method = "hbao";
    s.bounce = true;
    s.blur = 0;
    for (float T : {kThicknessInfinite, kThicknessAuto, 0.1f})
        for (float R : {1e-4f, 1e-2f, 10.0f, 1e4f}) {
            s.thickness = T;
            s.radius = R;
            OperatorInputs in = plane.inputs();
            in.radiance = source.view();
            const OperatorOutputs open = runOperator(in, s);
            checkedMin(open.ao);
            for (float v : open.indirect.pixels) EXPECT_LE(v, L * M_PI * 1e-3f) << "plane R=" << R << " T=" << T;
            in = edge.inputs();
            in.radiance = source.view();
            const OperatorOutputs out = runOperator(in, s);
            checkedMin(out.ao);
            int lit = 0;
            for (size_t i = 0; i < out.indirect.pixels.size(); ++i) {
                const float v = out.indirect.pixels[i];
                EXPECT_TRUE(v >= 0.0f && v <= L * M_PI * 1.001f) << v << " R=" << R << " T=" << T;
                lit += v > 0.0f;
            }
            if (R >= 10.0f) {
                EXPECT_GT(lit, W * H / 4) << "the wall lights the floor, R=" << R << " T=" << T;
            }
        }
}

// The same with deep input (docs/deep.md): three layers behind every surface, the hidden ones
// radiating the deep file's colour, some of it bad (NaN, infinite, negative). The plane's
// layers lie below its tangent and light nothing; elsewhere no interval is lit twice, so the light
// stays under the furnace's pi times the brightest radiance (bad colours send none).
TEST_P(Stiff, HbaoDeepBounceStaysFiniteAndBounded) {
    const int W = 96, H = 64;
    SceneBuffers plane = nineDecadePlane(W, H);
    SceneBuffers edge = renderScene(corner(), cornerCamera(W, H), W, H);
    const std::vector<std::pair<float, float>> behind = {{0.0f, 0.0f}, {0.05f, 0.3f}, {1.0f, 1.0f}, {2.0f, 1e30f}};
    const Image planeDeep = deepLayersFromDepth(plane.depth, behind), edgeDeep = deepLayersFromDepth(edge.depth, behind);
    const float inf = std::numeric_limits<float>::infinity();
    const float L = 3.0f, bad[] = {std::numeric_limits<float>::quiet_NaN(), inf, -inf, -5.0f};
    Image source(W, H, 3, L), colour(W, H, 12, L);
    for (int i = 0; i < 4; ++i) colour.at(5 + 11 * i, H / 2)[3 + 3 * (i % 3) + i % 3] = bad[i];
    Settings s;
    s.device = GetParam();
    s.method = "hbao";
    s.bounce = true;
    s.blur = 0;
    for (float T : {kThicknessInfinite, 0.1f})
        for (float R : {1e-4f, 1e-2f, 10.0f, 1e4f}) {
            s.thickness = T;
            s.radius = R;
            for (bool open : {true, false}) {
                OperatorInputs in = open ? plane.inputs() : edge.inputs();
                in.deepLayers = open ? planeDeep.view() : edgeDeep.view();
                in.radiance = source.view();
                in.deepColour = colour.view();
                const OperatorOutputs out = runOperator(in, s);
                checkedMin(out.ao);
                const float most = open ? L * M_PI * 1e-3f : L * M_PI * 1.001f;
                for (float v : out.indirect.pixels)
                    EXPECT_TRUE(v >= 0.0f && v <= most) << v << (open ? " plane" : " corner") << " R=" << R << " T=" << T;
            }
        }
}

// Pixel positions are floats on both devices and a pixel's centre is half a pixel in: a window
// past pixel 2^23 from the origin (where float has no halves) is refused with a line, not
// computed wrong (discs read a plane at 8.4e6 as 0.37, at 1e8 as 0.625); a plane in a window far
// inside it stays open.
TEST(StiffWindows, FarWindowsAreRefusedNearOnesCompute) {
    const int W = 32, H = 24;
    SceneBuffers sb = tiltedPlaneView(45.0, 10.0, false, W, H);
    for (const char* method : {"hbao", "discs"})
        for (int offset : {1 << 20, 9000000, 100000000}) {
            Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, 3.0f);
            s.method = method;
            OperatorInputs in = sb.inputs();
            in.dataWindow = Box2i{offset, offset, offset + W, offset + H};
            in.displayWindow = in.dataWindow;
            in.camera.cx += offset;
            in.camera.cy += offset;
            if (offset > (1 << 23))
                expectError([&] { runOperator(in, s); }, {"beyond 8388608", std::to_string(offset)});
            else
                EXPECT_GE(checkedMin(runOperator(in, s).ao), 1.0f - 2e-4f) << method << " at " << offset;
        }
}
