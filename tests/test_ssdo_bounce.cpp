// SSDO's one bounce against closed forms: the estimator of docs/ssdo.md ("How the bounce is
// estimated") is pi times the mean radiance that cosine-distributed directions meet within r_max,
// so where every bouncing surface is on screen its mean is the reference's, whatever N is.
#include "core/operator.h"
#include "support/closed_forms.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;

namespace {

constexpr float kRadius = 1.0f;

// The wall of cornerScene() (normal -x) radiating 1, red only, and the floor 0.
Image wallRadiance(const SceneBuffers& sb) {
    Image radiance(sb.depth.width, sb.depth.height, 3, 0.0f);
    for (int y = 0; y < sb.depth.height; ++y)
        for (int x = 0; x < sb.depth.width; ++x)
            if (*sb.depth.at(x, y) < 1e9f && sb.normal.at(x, y)[0] < -0.5f) radiance.at(x, y)[0] = 1.0f;
    return radiance;
}

// SSDO's GI (red) of `sb` lit by `radiance`.
Image redGi(const SceneBuffers& sb, const Image& radiance, int samples, int interleave) {
    OperatorInputs in = sb.inputs();
    in.radiance = radiance.view();
    Settings s;
    s.method = "ssdo";
    s.radius = kRadius;
    s.ssdoSamples = samples;
    s.interleave = interleave;
    s.bounce = true;
    s.threads = 2;
    const Image rgb = runOperator(in, s).indirect;
    Image red(rgb.width, rgb.height, 1);
    for (size_t i = 0; i < red.pixels.size(); ++i) red.pixels[i] = rgb.pixels[3 * i];
    return red;
}

// cornerScene() with the wall lit: the floor's GI is the wall's alone.
struct LitCorner {
    SceneBuffers sb;
    Image radiance;
    LitCorner() : sb(renderScene(cornerScene(), cornerCamera(200, 150), 200, 150)), radiance(wallRadiance(sb)) {}
    Image gi(int samples, int interleave) const { return redGi(sb, radiance, samples, interleave); }
};

// Irradiance on the floor at distance d from a wall of radiance 1, from the wall within R: the
// cosine-weighted share of the directions that meet the wall within R (1 - cosine AO, no
// falloff) times pi.
double wallIrradiance(double d) { return M_PI * (1 - cornerAo(Weighting::Cosine, Falloff::None, d / kRadius)); }

} // namespace

// An infinite lit plane at a right angle to the receiver plane, all of it that bounces on screen:
// GI follows the closed form at every distance (within 3%: the noise of 41 pixels at 256 samples).
TEST(SsdoBounce, WallAtRightAngleFollowsTheClosedForm) {
    const LitCorner corner;
    const Image gi = corner.gi(256, 1);
    for (double d : {0.05, 0.1, 0.2, 0.35, 0.5, 0.7}) {
        const double expected = wallIrradiance(d), got = meanOnCornerLine(corner.sb, gi, d);
        EXPECT_NEAR(got / expected, 1.0, 0.03) << "d = " << d;
    }
    EXPECT_EQ(meanOnCornerLine(corner.sb, gi, 1.2), 0.0) << "the wall is beyond R";
}

// The mean does not move with the sample count (the estimator is consistent), and approaches
// the closed form: over a band of floor beside the wall, 64, 256 and 1024 samples agree within
// the noise of the band's mean, with and without interleaving.
TEST(SsdoBounce, MeanIsIndependentOfTheSampleCount) {
    const LitCorner corner;
    for (int interleave : {1, 2}) {
        double means[3], expected = 0;
        const int counts[3] = {64, 256, 1024};
        for (int k = 0; k < 3; ++k) {
            const Image gi = corner.gi(counts[k], interleave);
            means[k] = 0;
            int n = 0;
            for (double d = 0.05; d < 0.95; d += 0.05, ++n) {
                means[k] += meanOnCornerLine(corner.sb, gi, d);
                if (k == 0) expected += wallIrradiance(d);
            }
            means[k] /= n;
            if (k == 0) expected /= n;
        }
        for (int k = 1; k < 3; ++k)
            EXPECT_NEAR(means[k] / means[0], 1.0, 0.03) << counts[k] << " vs 64 samples, interleave " << interleave;
        EXPECT_NEAR(means[2] / expected, 1.0, 0.03) << "interleave " << interleave;
    }
}

// Past the frame's edge the edge texels' surfaces continue (their tangent planes, as HBAO's
// border): where the frame cuts the lit wall, the floor beside the edge still receives the
// wall's light that lies off screen. The corner frame cut to an inner window (no overscan) gives,
// within 8 pixels of the cut, the GI of the whole frame there (the wall is one plane, so its
// continuation is exact), where stopping at the edge loses what lies past it.
TEST(SsdoBounce, LitWallContinuesPastTheFrameEdge) {
    const auto& [full, part, crop] = cornerCrop();
    const Image whole = redGi(full, wallRadiance(full), 256, 1);
    const Image cut = redGi(part, wallRadiance(part), 256, 1);
    double wholeSum = 0, cutSum = 0;
    int n = 0;
    for (int y = crop.y0; y < crop.y1; ++y)
        for (int x = crop.x0; x < crop.x1; ++x) {
            const int edge = std::min(std::min(x - crop.x0, crop.x1 - 1 - x), std::min(y - crop.y0, crop.y1 - 1 - y));
            if (edge >= 8 || *full.depth.at(x, y) >= 1e9f || full.normal.at(x, y)[1] < 0.5f) continue; // floor only
            wholeSum += *whole.at(x, y);
            cutSum += *cut.at(x - crop.x0, y - crop.y0);
            ++n;
        }
    ASSERT_GT(n, 100);
    ASSERT_GT(wholeSum / n, 0.05) << "the band receives the wall's light";
    EXPECT_NEAR(cutSum / wholeSum, 1.0, 0.05) << n << " floor pixels within 8 of the cut";
}

// Reports key the operator's timings by stage name (the report's medians, the farm's timelines):
// DO's blur and GI's wider one are two stages, each named once, and they and the kernel are timed.
TEST(SsdoBounce, EachStageIsTimedUnderItsOwnName) {
    const LitCorner c;
    OperatorInputs in = c.sb.inputs();
    in.radiance = c.radiance.view();
    Settings s;
    s.method = "ssdo";
    s.radius = kRadius;
    s.bounce = true;
    const OperatorStats st = runOperator(in, s).stats;
    std::vector<std::string> names;
    for (const StageTiming& t : st.timings) {
        EXPECT_GE(t.seconds, 0.0) << t.name;
        names.push_back(t.name);
    }
    for (const char* stage : {"ssdo+bounce", "blur", "blur-gi"})
        EXPECT_EQ(std::count(names.begin(), names.end(), stage), 1) << stage;
    std::sort(names.begin(), names.end());
    EXPECT_EQ(std::adjacent_find(names.begin(), names.end()), names.end()) << "a stage named twice";
}
