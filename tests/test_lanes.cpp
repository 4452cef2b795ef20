// The lane build of the kernels (cpu/lanes.h: several pixels per SIMD register) against
// its references: the lane maths against the C library, and the HBAO kernel of every
// instruction set this CPU runs against the pixel-at-a-time build of the same text.
#define OBSCURA_LANES 4 // SSE2: runs on every x86-64; the polynomials are the same at every width
#include "cpu/lanes.h"

#include "core/operator.h"
#include "cpu/lane_cpu.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

using namespace obscura;
using namespace obscura::test;
namespace lanes = obscura::cpu::lanes;

namespace {

// Largest |f_lane(x) - f_reference(x)| over n points of [lo, hi].
// (An angle's error is taken modulo 2 pi with `period`.)
template <class LaneFn, class RefFn>
double maxError(double lo, double hi, int n, LaneFn laneFn, RefFn refFn, bool relative = false, double period = 0) {
    double worst = 0;
    for (int i = 0; i < n; i += 4) {
        lanes::lfloat x;
        for (int k = 0; k < 4; ++k) x.v[k] = (float)(lo + (hi - lo) * (i + k) / (n - 1));
        const lanes::lfloat y = laneFn(x);
        for (int k = 0; k < 4; ++k) {
            const double ref = refFn((double)x[k]);
            double err = std::abs((double)y[k] - ref) / (relative ? std::abs(ref) : 1.0);
            if (period > 0) err = std::min(err, std::abs(period - err));
            worst = std::max(worst, err);
        }
    }
    return worst;
}

} // namespace

TEST(LaneMath, SinCosWithinAFewUlpOverSeveralTurns) {
    EXPECT_LT(maxError(-20.0, 20.0, 400000, [](lanes::lfloat x) { return lanes::sin(x); },
                       [](double x) { return std::sin(x); }),
              3e-7);
    EXPECT_LT(maxError(-20.0, 20.0, 400000, [](lanes::lfloat x) { return lanes::cos(x); },
                       [](double x) { return std::cos(x); }),
              3e-7);
}

TEST(LaneMath, AtanOfEveryOctant) {
    // atan(y, x) around the unit circle and at other radii: every octant and both swaps.
    for (double radius : {1e-6, 1.0, 3e4}) {
        const double worst = maxError(-M_PI, M_PI, 100000,
                                      [radius](lanes::lfloat a) {
                                          return lanes::atan(lanes::sin(a) * (float)radius, lanes::cos(a) * (float)radius);
                                      },
                                      [](double a) { return a; }, false, 2 * M_PI);
        EXPECT_LT(worst, 1e-6) << "radius " << radius;
    }
    const lanes::lfloat zero(0.0f), one(1.0f);
    EXPECT_EQ(lanes::atan(zero, one)[0], 0.0f);
    EXPECT_NEAR(lanes::atan(one, zero)[0], M_PI / 2, 1e-7);
}

TEST(LaneMath, InverseSqrtAndFloor) {
    EXPECT_LT(maxError(1e-30, 1e30, 200000, [](lanes::lfloat x) { return lanes::inversesqrt(x); },
                       [](double x) { return 1.0 / std::sqrt(x); }, true),
              4e-7);
    EXPECT_LT(maxError(1e-6, 4.0, 200000, [](lanes::lfloat x) { return lanes::inversesqrt(x); },
                       [](double x) { return 1.0 / std::sqrt(x); }, true),
              4e-7);
    const lanes::lfloat x(-2.5f), y(3.0f), z(-1e9f), w(0.75f);
    EXPECT_EQ(lanes::floor(x)[0], -3.0f);
    EXPECT_EQ(lanes::floor(y)[0], 3.0f);
    EXPECT_EQ(lanes::floor(z)[0], -1e9f);
    EXPECT_EQ(lanes::floor(w)[0], 0.0f);
}

// The unsigned bit operations HBAO's visibility bitmask uses, lane by lane against scalar C++.
TEST(LaneMath, BitOpsPerLane) {
    const std::uint32_t a[4] = {0xffffffffu, 0x80000001u, 0x12345678u, 0u};
    const std::uint32_t n[4] = {0u, 31u, 7u, 16u};
    lanes::luint va(0u), vn(0u);
    for (int k = 0; k < 4; ++k) va.v[k] = a[k], vn.v[k] = n[k];
    const lanes::lbool odd = lanes::lint((lanes::vint)(vn.v & 1u)) > lanes::lint(0);
    const lanes::luint left = va << vn, right = va >> vn, diff = va - vn, inv = ~va;
    const lanes::luint chosen = lanes::select(odd, va, vn);
    for (int k = 0; k < 4; ++k) {
        EXPECT_EQ(left.v[k], a[k] << n[k]) << k;
        EXPECT_EQ(right.v[k], a[k] >> n[k]) << k;
        EXPECT_EQ(diff.v[k], a[k] - n[k]) << k;
        EXPECT_EQ(inv.v[k], ~a[k]) << k;
        EXPECT_EQ(chosen.v[k], (n[k] & 1u) ? a[k] : n[k]) << k;
    }
}

// Every instruction set's HBAO and SSAO equal the pixel-at-a-time build within float rounding
// (FMA contraction and the 12/14-bit estimates refined by Newton differ in the last bits),
// for every weighting, falloff and projection.
TEST(LaneKernels, EveryInstructionSetMatchesThePixelAtATimeBuild) {
  for (cpu::LaneKernel kernel : {cpu::LaneKernel::Hbao, cpu::LaneKernel::Ssao}) {
    const std::vector<std::string> isas = cpu::laneIsas();
    ASSERT_EQ(isas.front(), "scalar");
    ASSERT_GE(isas.size(), 2u);
    const int W = 157, H = 101; // not a multiple of any lane count: partial vectors at row ends
    for (bool ortho : {false, true}) {
        for (DepthKind kind : {DepthKind::Planar, DepthKind::Radial}) {
            if (ortho && kind == DepthKind::Radial) continue;
            const Camera cam = ortho ? lookAtOrthographic(glm::dvec3(4, 5, 9), glm::dvec3(-1, 0.6, -3), 12.0, W, H)
                                     : studioCamera(W, H);
            const SceneBuffers sb = renderScene(studioScene(), cam, Box2i{0, 0, W, H}, Box2i{0, 0, W, H}, kind);
            for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
                for (int variant = 0; variant < 5; ++variant) {
                    // Linear falloff, binary, binary with a fixed thickness (the visibility bitmask),
                    // with the automatic one (runs), and linear with it; each with another border
                    // policy (auto: open, where runs leaving the buffer are cut).
                    const Falloff f = variant == 0 || variant == 4 ? Falloff::Linear : Falloff::None;
                    if (variant >= 2 && kernel != cpu::LaneKernel::Hbao) continue;
                    Settings s;
                    s.radius = 1.0f;
                    s.weighting = w;
                    s.falloff = f;
                    s.thickness = variant == 2 ? 0.2f : variant >= 3 ? kThicknessAuto : kThicknessInfinite;
                    s.border = variant == 0 || variant == 3 ? kBorderOpen : variant == 1 ? kBorderClamp : kBorderTangent;
                    s.ssaoHemisphere = w == Weighting::Cosine;  // both SSAO forms, without doubling the cases
                    const KernelParams p = makeKernelParams(sb.inputs(), s);
                    Image reference(W, H, 1);
                    cpu::runLaneKernel(kernel, p, sb.depth.view(), sb.normal.view(), reference.view(), 1, "scalar");
                    ASSERT_LT(*std::min_element(reference.pixels.begin(), reference.pixels.end()), 0.9f)
                        << "the scene must have occlusion to compare";
                    for (size_t i = 1; i < isas.size(); ++i) {
                        Image ao(W, H, 1);
                        cpu::runLaneKernel(kernel, p, sb.depth.view(), sb.normal.view(), ao.view(), 2, isas[i]);
                        double worst = 0;
                        for (size_t k = 0; k < ao.pixels.size(); ++k) {
                            ASSERT_TRUE(std::isfinite(ao.pixels[k]));
                            worst = std::max(worst, (double)std::abs(ao.pixels[k] - reference.pixels[k]));
                        }
                        EXPECT_LT(worst, 5e-5) << isas[i] << (ortho ? " ortho" : " persp")
                                               << (kind == DepthKind::Radial ? " radial" : "") << " w" << (int)w
                                               << " f" << (int)f << " T " << s.thickness << " kernel " << (int)kernel;
                    }
                }
            }
        }
    }
  }
}

TEST(LaneKernels, UnknownInstructionSetIsRefused) {
    Image depth(4, 4, 1, 1.0f), normal(4, 4, 3, 0.0f), ao(4, 4, 1);
    KernelParams p{};
    p.width = p.height = 4;
    EXPECT_THROW(cpu::runHbao(p, depth.view(), normal.view(), ao.view(), 1, "x86-64-v9"), std::invalid_argument);
}
