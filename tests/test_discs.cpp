// Disc AO (kernels/discs.glsl): analytic properties on both devices, the instruction sets
// against the pixel-at-a-time build, and the corrections' switches.
#include "core/methods.h"
#include "core/operator.h"
#include "cpu/discs_cpu.h"
#include "cpu/lane_cpu.h"
#include "support/closed_forms.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

Settings discsSettings(const char* device, float radius) {
    Settings s;
    s.method = "discs";
    s.device = device;
    s.radius = radius;
    s.weighting = Weighting::Cosine;
    s.falloff = Falloff::None;
    return s;
}

// Mean AO over the floor pixels on the line at distance d from the corner's wall.
double cornerLine(const SceneBuffers& sb, const Image& ao, double d) {
    double sum = 0;
    int n = 0;
    for (double z = -1.0; z <= 1.0; z += 0.05) {
        int x, y;
        if (!sb.pixelOf(dvec3(-d, 0, z), x, y)) continue;
        sum += *ao.at(x, y);
        ++n;
    }
    EXPECT_GT(n, 20);
    return sum / std::max(n, 1);
}

} // namespace

TEST(Discs, CornerDiagnostic) {
    const int W = 320, H = 240;
    Camera cam = lookAtPerspective(dvec3(-7, 6, 4), dvec3(-0.6, 0, 0), 40.0 * M_PI / 180, W, H);
    SceneBuffers sb = renderScene(cornerScene(), cam, W, H);
    for (int variant = 0; variant < 4; ++variant) {
        Settings s = discsSettings("cpu", 1.0f);
        s.discsPasses = 1;
        s.discsWindow = variant + 1;
        const Image ao = runOperator(sb.inputs(), s).ao;
        for (double d : {0.02, 0.05, 0.2, 0.4, 0.7, 1.2})
            std::printf("variant %d d %.2f  discs %.4f  closed %.4f\n", variant, d, cornerLine(sb, ao, d),
                        cornerAo(Weighting::Cosine, Falloff::None, d));
    }
}
