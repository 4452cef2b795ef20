// HBAO through the operator on analytic scenes with known answers.
#include "core/operator.h"
#include "support/closed_forms.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

struct Case {
    Weighting w;
    Falloff f;
};
const Case kCases[] = {{Weighting::Uniform, Falloff::Linear},
                       {Weighting::Uniform, Falloff::None},
                       {Weighting::Cosine, Falloff::Linear},
                       {Weighting::Cosine, Falloff::None}};

bool allFiniteInUnitRange(const Image& ao) {
    for (float v : ao.pixels)
        if (!(v >= 0.0f && v <= 1.0f)) return false;
    return true;
}

} // namespace

// An infinite plane occludes nothing: AO = 1 at every pixel, for every weighting,
// falloff, projection, tilt (up to grazing) and distance - not just on average.
TEST(HbaoAnalytic, PlaneIsUnoccludedAtEveryPixel) {
    const double tilts[] = {0.0, 30.0, 60.0, 80.0, 88.0};
    const double distances[] = {0.5, 5.0, 200.0, 5e4};
    for (bool ortho : {false, true}) {
        for (double tiltDeg : tilts) {
            for (double dist : distances) {
                const dvec3 target(0.0);
                const double t = tiltDeg * M_PI / 180;
                // Camera looks along -Z at the origin; the plane's normal is tilted away from the view axis.
                const dvec3 eye(0, 0, dist);
                const dvec3 n(std::sin(t), 0.0, std::cos(t));
                const dvec3 s = glm::normalize(glm::cross(n, dvec3(0, 1, 0)));
                const dvec3 u = glm::cross(n, s);
                Camera cam = ortho ? lookAtOrthographic(eye, target, dist, 64, 48)
                                   : lookAtPerspective(eye, target, 70.0 * M_PI / 180, 64, 48);
                SceneBuffers sb = renderScene({planeRect(target, s, u, 1e7)}, cam, 64, 48);
                for (const Case& c : kCases) {
                    const float radius = (float)(0.2 * dist);
                    OperatorOutputs out = runOperator(sb.inputs(), hbaoSettings(c.w, c.f, radius));
                    float minAo = 1.0f;
                    int surface = 0;
                    for (int i = 0; i < 64 * 48; ++i) {
                        if (sb.depth.pixels[i] < 1e9f) ++surface;
                        minAo = std::min(minAo, out.ao.pixels[i]);
                    }
                    ASSERT_GT(surface, 64 * 48 / 2);
                    // 2e-4: float rounding of the sample offsets; a missed horizon would cost > 1e-2.
                    EXPECT_GE(minAo, 1.0f - 2e-4f) << "ortho=" << ortho << " tilt=" << tiltDeg << " dist=" << dist
                                                  << " w=" << toString(c.w) << " f=" << toString(c.f);
                }
            }
        }
    }
}

// Floor next to a wall: AO along a line at distance d matches the closed form for each
// weighting and falloff. The estimate is averaged over the pixels of a line parallel to the
// wall (same true AO) to average out the per-pixel rotation noise.
TEST(HbaoAnalytic, CornerMatchesClosedForm) {
    const int W = 320, H = 240;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    const double R = 1.0;
    for (const Case& c : kCases) {
        OperatorOutputs out = runOperator(sb.inputs(), hbaoSettings(c.w, c.f, (float)R, 32, 32));
        for (double d : {0.05, 0.2, 0.4, 0.7}) {
            const double mean = meanOnCornerLine(sb, out.ao, d);
            const double expected = cornerAo(c.w, c.f, d / R);
            // 0.02: 32 slices x 32 steps on a ~3 px/0.1 unit image; the horizon sample nearest R falls
            // short of R by up to one step (R/32), and pixel snapping moves d by up to half a pixel.
            EXPECT_NEAR(mean, expected, 0.02) << "d=" << d << " w=" << toString(c.w) << " f=" << toString(c.f);
        }
    }
}

// A point in the corner itself (d -> 0) sees half of its hemisphere blocked: AO = 1/2 for both
// weightings with binary visibility.
TEST(HbaoAnalytic, CornerEdgeIsHalfOccluded) {
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) EXPECT_NEAR(cornerAo(w, Falloff::None, 0.0), 0.5, 1e-12);
    const int W = 320, H = 240;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
        OperatorOutputs out = runOperator(sb.inputs(), hbaoSettings(w, Falloff::None, 2.0f, 32, 32));
        EXPECT_NEAR(meanOnCornerLine(sb, out.ao, 0.02), cornerAo(w, Falloff::None, 0.01), 0.03) << toString(w);
    }
}

// Shrinking R to nothing makes AO tend continuously to 1 (no jump, no NaN).
TEST(HbaoAnalytic, VanishingRadiusTendsToUnoccluded) {
    const int W = 160, H = 120;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    double previous = 0;
    for (float R : {1.0f, 0.3f, 0.1f, 0.03f, 0.01f, 1e-4f, 1e-8f}) {
        OperatorOutputs out = runOperator(sb.inputs(), hbaoSettings(Weighting::Cosine, Falloff::Linear, R));
        ASSERT_TRUE(allFiniteInUnitRange(out.ao));
        double mean = 0;
        for (float v : out.ao.pixels) mean += v;
        mean /= out.ao.pixels.size();
        EXPECT_GE(mean, previous - 1e-6) << "R=" << R;
        previous = mean;
    }
    EXPECT_NEAR(previous, 1.0, 1e-6);
}

// Results depend on the pixel, not on how the work was split: thread counts and crops agree
// bit for bit wherever the crop keeps the whole sampling footprint.
TEST(HbaoAnalytic, ThreadsAndCropsAgreeExactly) {
    const int W = 200, H = 150;
    Camera cam = cornerCamera(W, H);
    SceneBuffers full = renderScene(cornerScene(), cam, W, H);
    Settings s = hbaoSettings(Weighting::Uniform, Falloff::Linear, 0.5f);
    s.threads = 1;
    OperatorOutputs one = runOperator(full.inputs(), s);
    s.threads = 2;
    OperatorOutputs two = runOperator(full.inputs(), s);
    ASSERT_EQ(one.ao.pixels, two.ao.pixels);

    const Box2i crop{50, 40, 170, 130};
    SceneBuffers part = renderScene(cornerScene(), cam, Box2i{0, 0, W, H}, crop);
    OperatorOutputs cropped = runOperator(part.inputs(), s);
    int compared = 0;
    for (int y = crop.y0 + 30; y < crop.y1 - 30; ++y)
        for (int x = crop.x0 + 30; x < crop.x1 - 30; ++x) {
            ASSERT_EQ(*one.ao.at(x, y), *cropped.ao.at(x - crop.x0, y - crop.y0)) << x << "," << y;
            ++compared;
        }
    EXPECT_GT(compared, 1000);
}

// Garbage in the passes never becomes garbage out.
TEST(HbaoAnalytic, NonFiniteInputsGiveFiniteOutput) {
    const int W = 96, H = 72;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    const float depths[] = {nan, inf, -inf, -1.0f, 0.0f, 1e-42f, 1e30f};
    for (int i = 0; i < W * H; i += 7) sb.depth.pixels[i] = depths[(i / 7) % 7];
    const float normals[][3] = {{0, 0, 0}, {nan, 0, 1}, {inf, 0, 0}, {0, 5, 0}, {0, -1, 0}};
    for (int i = 3; i < W * H; i += 11)
        for (int c = 0; c < 3; ++c) sb.normal.pixels[i * 3 + c] = normals[(i / 11) % 5][c];
    for (const Case& c : kCases) {
        Settings s = hbaoSettings(c.w, c.f, 0.7f);
        s.blur = 2;
        OperatorOutputs out = runOperator(sb.inputs(), s);
        EXPECT_TRUE(allFiniteInUnitRange(out.ao));
        EXPECT_GT(out.stats.invalidDepthPixels, 0);
    }
}

// Where R spans a few pixels (distant geometry) a blur keeps the AO's shape: its weights fall within
// BLUR_REACH R across the surface, so low's blur (2 px) on a far corner changes the floor's AO
// near the crease little, where a blur of pixels alone averages over most of R.
TEST(HbaoAnalytic, BlurKeepsACornerWhoseRadiusSpansFewPixels) {
    const int W = 80, H = 60; // R = 0.25 spans about 3 pixels across the floor
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, 0.25f, 32, 32);
    const Image sharp = runOperator(sb.inputs(), s).ao;
    s.blur = 2;
    const Image blurred = runOperator(sb.inputs(), s).ao;
    double change = 0, occlusion = 0;
    int n = 0;
    for (int i = 0; i < W * H; ++i)
        if (sharp.pixels[i] < 0.95f && sb.depth.pixels[i] < 1e9f) { // the floor and wall near the crease
            change += std::abs(blurred.pixels[i] - sharp.pixels[i]);
            occlusion += 1 - sharp.pixels[i];
            ++n;
        }
    ASSERT_GT(n, 100);
    // With the reach the blur moves it by 0.19 of its occlusion there; by pixels alone, 0.42.
    EXPECT_LT(change, 0.25 * occlusion) << n << " pixels near the crease";
}
