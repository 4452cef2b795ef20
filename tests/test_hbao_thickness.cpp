// HBAO with a finite thickness (the visibility bitmask, kernels/hbao.glsl): planes stay exact,
// a thickness too large to matter is the horizon bit for bit, closed forms still hold where
// the occluder really is solid, and thin poles get closer to a ray-traced reference, with a
// fixed thickness and with auto's per-occluder one.
#include "core/operator.h"
#include "support/closed_forms.h"
#include "support/reference_runs.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;
namespace fs = std::filesystem;

namespace {

Settings binarySettings(Weighting w, float radius, float thickness, int dirs = 8, int steps = 8,
                        Falloff f = Falloff::None) {
    Settings s = hbaoSettings(w, f, radius, dirs, steps);
    s.thickness = thickness;
    return s;
}

} // namespace

// A plane occludes nothing whatever thickness its samples are given: every sample lies on the
// tangent plane, so neither the horizon nor any sector moves.
TEST(HbaoThickness, PlaneIsUnoccludedAtEveryPixel) {
    for (bool ortho : {false, true})
        for (double tiltDeg : {0.0, 45.0, 80.0, 88.0})
            for (double dist : {0.5, 200.0, 5e4}) {
                SceneBuffers sb = tiltedPlaneView(tiltDeg, dist, ortho, 64, 48);
                const float radius = (float)(0.2 * dist);
                for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
                    for (float thickness : {kThicknessAuto, 0.01f * radius, radius}) {
                        OperatorOutputs out = runOperator(sb.inputs(), binarySettings(w, radius, thickness));
                        const float minAo = *std::min_element(out.ao.pixels.begin(), out.ao.pixels.end());
                        EXPECT_GE(minAo, 1.0f - 2e-4f) << "ortho=" << ortho << " tilt=" << tiltDeg << " dist=" << dist
                                                      << " w=" << toString(w) << " T=" << thickness;
                    }
            }
}

// Pushed back far enough, every sample's back lies below the tangent plane, its interval joins
// the horizon's, and the bitmask path computes what the horizon path computes (to float
// rounding: the two are separate instantiations, contracted into FMAs differently); with linear
// falloff too, where each run's weighted rises add up to the horizon's.
TEST(HbaoThickness, LargeThicknessIsTheHorizonExactly) {
    const int W = 160, H = 120;
    for (bool ortho : {false, true}) {
        const Camera cam = ortho ? lookAtOrthographic(dvec3(4, 5, 9), dvec3(-1, 0.6, -3), 12.0, W, H)
                                 : studioCamera(W, H);
        const SceneBuffers sb = renderScene(studioScene(), cam, W, H);
        for (Weighting w : {Weighting::Uniform, Weighting::Cosine})
          for (Falloff f : {Falloff::None, Falloff::Linear}) {
            const OperatorOutputs horizon = runOperator(sb.inputs(), binarySettings(w, 1.0f, kThicknessInfinite, 8, 8, f));
            const OperatorOutputs bitmask = runOperator(sb.inputs(), binarySettings(w, 1.0f, 1e6f, 8, 8, f));
            float minAo = 1.0f;
            for (size_t i = 0; i < horizon.ao.pixels.size(); ++i) {
                ASSERT_NEAR(horizon.ao.pixels[i], bitmask.ao.pixels[i], 1e-6f)
                    << "pixel " << i << " ortho " << ortho << " " << toString(f);
                minAo = std::min(minAo, horizon.ao.pixels[i]);
            }
            EXPECT_LT(minAo, 0.8f) << "the scene must have occlusion to compare";
        }
    }
}

// The floor beside a wall: the wall's samples, each pushed back by the automatic thickness,
// overlap and cover the angles up to the horizon, so the closed form still holds.
TEST(HbaoThickness, CornerMatchesClosedFormWithAutoThickness) {
    const int W = 320, H = 240;
    Camera cam = cornerCamera(W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
        OperatorOutputs out = runOperator(sb.inputs(), binarySettings(w, 1.0f, kThicknessAuto, 32, 32));
        for (double d : {0.05, 0.2, 0.4, 0.7}) {
            const double mean = meanOnCornerLine(sb, out.ao, d);
            // The tolerance of HbaoAnalytic.CornerMatchesClosedForm.
            EXPECT_NEAR(mean, cornerAo(w, Falloff::None, d), 0.02) << "d=" << d << " w=" << toString(w);
        }
    }
}

// Thin poles in front of a floor and a wall (reference_render's `poles`): the horizon darkens
// everything behind a pole as if it were a wall; a thickness of the poles' size does not, and
// neither does auto, which measures each pole's width across the slice.
TEST(HbaoThickness, ThinPolesGetCloserToTheReference) {
    const fs::path dir = fs::path(OBSCURA_TEST_TMP) / ("hbao-thick-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string ref = (dir / "poles.exr").string();
    const CliResult r = renderReferenceScene("poles", ref, 200, 150);
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto psnr = [&](const std::string& thickness) {
        return psnrAgainstCosineReference(ref, dir, 0.5f, {"--quality", "high", "--thickness", thickness});
    };
    const double horizon = psnr("inf"), thin = psnr("0.1"), automatic = psnr("auto");
    std::printf("poles 200x150: hbao high, thickness inf %.2f dB, 0.1 %.2f dB, auto %.2f dB\n", horizon, thin, automatic);
    EXPECT_GT(thin, horizon + 4.0);
    EXPECT_GT(automatic, horizon + 6.0);  // measured +8.4 dB (a fixed 0.85 R: +1.3 dB)
    EXPECT_GT(automatic, thin - 4.0);     // measured 2.4 dB below the poles' own size, given by hand
    fs::remove_all(dir);
}

// The flag takes a number of world units, auto or inf; anything else is a usage error.
TEST(HbaoThickness, FlagValues) {
    const std::string in = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";
    const std::string out = std::string(OBSCURA_TEST_TMP) + "/hbao-thickness.exr";
    for (const char* ok : {"0.3", "auto", "inf"}) {
        const CliResult c = runProgram(OBSCURA_CLI_PATH, {in, "-o", out, "--thickness", ok, "--quality", "low", "--quiet"});
        EXPECT_EQ(c.exitCode, 0) << ok << ": " << c.err;
    }
    for (const char* bad : {"-2", "automatic", "nan"}) {
        const CliResult c = runProgram(OBSCURA_CLI_PATH, {in, "-o", out, "--thickness", bad});
        EXPECT_EQ(c.exitCode, 2) << bad << ": " << c.err;
        EXPECT_NE(c.err.find("--thickness"), std::string::npos) << c.err;
    }
}
