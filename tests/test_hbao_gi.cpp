// HBAO's indirect light (--method hbao --bounce, kernels/hbao_gi.glsl) against closed forms, and
// the same numbers on OpenGL. docs/hbao.md "Indirect light" derives the closed forms.
#include "core/operator.h"
#include "support/gl_devices.h"
#include "support/closed_forms.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

Settings giSettings(float radius, float thickness, Weighting w = Weighting::Cosine, int dirs = 32, int steps = 32) {
    Settings s = hbaoSettings(w, Falloff::None, radius, dirs, steps);
    s.thickness = thickness;
    s.bounce = true;
    return s;
}

OperatorOutputs runGi(const SceneBuffers& sb, const Image& radiance, const Settings& s) {
    OperatorInputs in = sb.inputs();
    in.radiance = radiance.view();
    return runOperator(in, s);
}

// Channel c of an RGB image as a plane.
Image channel(const Image& rgb, int c) {
    Image out(rgb.width, rgb.height, 1);
    for (size_t i = 0; i < out.pixels.size(); ++i) out.pixels[i] = rgb.pixels[3 * i + c];
    return out;
}

// Irradiance at a floor point at distance d from the corner's wall, which radiates L, counting
// the wall within R only: pi L times the wall's share of the cosine-weighted hemisphere, which is
// what cosine-weighted binary AO leaves out (c = d / R; 2 L (pi/4) = pi L / 2 when R -> inf).
double cornerIrradiance(double L, double c) { return M_PI * L * (1.0 - cornerAo(Weighting::Cosine, Falloff::None, c)); }

// The largest |E - pi L (1 - AO)| over the pixels: 0 where the light's coverage is the cosine AO's.
double mostFromOccluded(const OperatorOutputs& out, float L) {
    double most = 0;
    for (size_t i = 0; i < out.ao.pixels.size(); ++i) {
        double d = std::abs(out.indirect.pixels[3 * i] - M_PI * L * (1.0 - out.ao.pixels[i]));
        most = std::max(most, d);
    }
    return most;
}

} // namespace

// An open plane has nothing above its tangent: no indirect light at any pixel, at any tilt,
// whatever the source's radiance.
TEST(HbaoGi, OpenPlaneReceivesNothing) {
    const int W = 64, H = 48;
    for (double tiltDeg : {0.0, 45.0, 80.0}) {
        const double t = tiltDeg * M_PI / 180;
        const dvec3 n(std::sin(t), 0.0, std::cos(t));
        const dvec3 s = glm::normalize(glm::cross(n, dvec3(0, 1, 0)));
        SceneBuffers sb = renderScene({planeRect(dvec3(0), s, glm::cross(n, s), 1e7)},
                                      lookAtPerspective(dvec3(0, 0, 5), dvec3(0), 70.0 * M_PI / 180, W, H), W, H);
        const Image radiance = uniformRadiance(sb, 100.0f);
        for (float T : {kThicknessInfinite, kThicknessAuto, 0.3f}) {
            const OperatorOutputs out = runGi(sb, radiance, giSettings(1.0f, T, Weighting::Cosine, 8, 8));
            ASSERT_EQ(out.indirect.pixels.size(), (size_t)W * H * 3);
            float most = 0.0f;
            for (float v : out.indirect.pixels) most = std::max(most, v);
            // The plane's own texels lie on the tangent up to float rounding (AO's test allows 2e-4
            // of occlusion); E = 100 pi x that would be 0.06.
            EXPECT_LE(most, 100.0f * M_PI * 2e-4f) << "tilt " << tiltDeg << " T " << T;
        }
    }
}

// The floor beside a lit wall at a right angle: the closed form of the irradiance within R, at
// several distances and radii (d / R -> 0: the infinite wall's pi L / 2), with and without a
// thickness. The AO's weighting does not enter the light: the same irradiance for both.
TEST(HbaoGi, RightAngleWallMatchesClosedForm) {
    const int W = 320, H = 240;
    SceneBuffers sb = renderScene(cornerScene(), cornerCamera(W, H), W, H);
    const float L = 2.0f;
    const Image radiance = uniformRadiance(sb, L);
    for (float R : {1.0f, 4.0f})
        for (float T : {kThicknessInfinite, kThicknessAuto}) {
            const OperatorOutputs cosine = runGi(sb, radiance, giSettings(R, T, Weighting::Cosine));
            const OperatorOutputs uniform = runGi(sb, radiance, giSettings(R, T, Weighting::Uniform));
            EXPECT_EQ(cosine.indirect.pixels, uniform.indirect.pixels) << "R " << R << " T " << T;
            // Without a thickness, and with the measured one (the light applies each occluder's
            // run when the AO does), the light covers what the cosine AO occludes, angle for angle:
            // under a uniform source E = pi L (1 - AO) at every pixel, the border's continued wall
            // included.
            EXPECT_LE(mostFromOccluded(cosine, L), 1e-4 * M_PI * L) << "R " << R << " T " << T;
            const Image red = channel(cosine.indirect, 0);
            for (double d : {0.05, 0.2, 0.4, 0.7}) {
                const double expected = cornerIrradiance(L, d / R);
                // AO's tolerance (0.02, tests/test_hbao_analytic.cpp) times pi L: the same march.
                EXPECT_NEAR(meanOnCornerLine(sb, red, d), expected, 0.02 * M_PI * L)
                    << "d " << d << " R " << R << " T " << T;
            }
        }
}

// With the measured thickness the light takes each occluder's run as the AO does, as one interval
// when it ends, lit by the faces the receiver sees: spheres, boxes and their shadows under a
// uniform source never receive more than E = pi L (1 - AO), at any pixel, whatever the runs'
// radiance weights, and most of it where occluders are in reach.
TEST(HbaoGi, MeasuredThicknessLightNeverExceedsWhatTheAoOccludes) {
    const int W = 160, H = 120;
    SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const float L = 1.5f;
    const Image radiance = uniformRadiance(sb, L);
    for (float R : {0.3f, 0.8f, 3.0f}) {
        const OperatorOutputs out = runGi(sb, radiance, giSettings(R, kThicknessAuto, Weighting::Cosine, 8, 8));
        double lit = 0, occluded = 0, most = 0;
        for (size_t i = 0; i < out.ao.pixels.size(); ++i) {
            const double fromOccluded = M_PI * L * (1.0 - out.ao.pixels[i]);
            lit += out.indirect.pixels[3 * i];
            occluded += fromOccluded;
            most = std::max(most, out.indirect.pixels[3 * i] - fromOccluded);
        }
        EXPECT_LE(most, 1e-4 * M_PI * L) << "R " << R;
        // The faces the camera sees face most receivers too (a box's far side is a small share).
        EXPECT_GT(lit, 0.7 * occluded) << "R " << R;
    }
}

// A wall-like box on a floor, the camera in front of it and above, the light per occluder run
// (the measured thickness): the floor in front sees the box's front face, which the buffer holds,
// and receives pi L (1 - AO) under a uniform source; the floor behind sees only the box's back,
// which the buffer does not hold (its front and top face away from it), so it receives nothing,
// though the box occludes it.
TEST(HbaoGi, FloorBehindABoxSeesNoneOfTheFacesTheBufferHolds) {
    const int W = 200, H = 160;
    std::vector<Rect> rects = {Rect{dvec3(-8, 0, -8), dvec3(16, 0, 0), dvec3(0, 0, 16)}};
    addBox(rects, dvec3(-3.0, 0.0, -0.5), dvec3(3.0, 2.0, 0.5));
    const Camera cam = lookAtPerspective(dvec3(0.0, 8.0, 4.0), dvec3(0.0, 0.0, -1.5), 60.0 * M_PI / 180, W, H);
    SceneBuffers sb = renderScene(rects, cam, W, H);
    const float L = 1.0f;
    const Image radiance = uniformRadiance(sb, L);
    const OperatorOutputs out = runGi(sb, radiance, giSettings(3.0f, kThicknessAuto));
    for (double x : {-0.6, 0.0, 0.6}) {
        int px, py;
        // Behind: visible from 1.5 behind the box's back face (the box hides what is nearer).
        for (double z : {-2.2, -2.4, -2.6}) {
            ASSERT_TRUE(sb.pixelOf(dvec3(x, 0, z), px, py));
            EXPECT_LT(out.ao.at(px, py)[0], 0.95f) << "x " << x << " z " << z;
            EXPECT_LE(out.indirect.at(px, py)[1], 1e-3 * M_PI * L) << "x " << x << " z " << z;
        }
        // In front: exactly what the AO occludes, lit.
        for (double z : {0.7, 1.0, 1.5}) {
            ASSERT_TRUE(sb.pixelOf(dvec3(x, 0, z), px, py));
            const double fromOccluded = M_PI * L * (1.0 - out.ao.at(px, py)[0]);
            EXPECT_GT(fromOccluded, 0.05 * M_PI * L) << "x " << x << " z " << z;
            EXPECT_NEAR(out.indirect.at(px, py)[1], fromOccluded, 1e-4 * M_PI * L) << "x " << x << " z " << z;
        }
    }
}

// Furnace: a receiver at the bottom centre of a square well whose walls all radiate L receives
// pi L less the opening's share, pi L (1 - 4 F), F the form factor of a quarter of the opening.
TEST(HbaoGi, ReceiverInALitWellMatchesClosedForm) {
    const int W = 240, H = 240;
    const double a = 1.0, h = 1.5;
    const Camera cam = lookAtPerspective(dvec3(0.0, 6.0, 0.2), dvec3(0.0), 60.0 * M_PI / 180, W, H);
    SceneBuffers sb = renderScene(wellScene(a, h), cam, W, H);
    const float L = 1.0f;
    const Image radiance = uniformRadiance(sb, L);
    const double expected = wellIrradiance(L, a, h);
    for (float T : {kThicknessInfinite, kThicknessAuto}) {
        const OperatorOutputs out = runGi(sb, radiance, giSettings(2.5f, T));
        double sum = 0;
        int n = 0;
        for (double x = -0.06; x <= 0.061; x += 0.03)
            for (double z = -0.06; z <= 0.061; z += 0.03) {
                int px, py;
                ASSERT_TRUE(sb.pixelOf(dvec3(x, 0, z), px, py));
                sum += out.indirect.at(px, py)[1];
                ++n;
            }
        // 3%: 32 slices through a square opening, whose rim a slice samples to within a step.
        EXPECT_NEAR(sum / n, expected, 0.03 * expected) << "T " << T;
    }
}

// One kernel text on both devices: the light, like the AO, within 1e-3 of the CPU's (relative to
// the furnace's pi L where the light is large), with each model and the blur.
TEST(HbaoGi, OpenGlMatchesCpu) {
    const int W = 160, H = 120;
    SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    Image radiance = uniformRadiance(sb, 1.0f);
    for (size_t i = 0; i < radiance.pixels.size(); i += 3) radiance.pixels[i] *= 0.25f; // coloured
    for (float T : {kThicknessInfinite, 0.3f, kThicknessAuto})
        for (int blur : {0, 1}) {
            Settings s = giSettings(0.8f, T, Weighting::Uniform, 8, 8);
            s.falloff = Falloff::Linear;
            s.blur = blur;
            const OperatorOutputs cpu = runGi(sb, radiance, s);
            for (const std::string& device : glDevicesUnderTest()) {
                s.device = device;
                const OperatorOutputs gl = runGi(sb, radiance, s);
                ASSERT_EQ(gl.stats.device.rfind(device, 0), 0u) << gl.stats.device;
                EXPECT_TRUE(glParity(cpu.ao, gl.ao, 1e-3, device)) << "T " << T << " blur " << blur;
                EXPECT_TRUE(glParity(cpu.indirect, gl.indirect, 1e-3 * M_PI, device)) << "T " << T << " blur " << blur;
            }
            s.device = "cpu";
        }
}
