// SSDO directional occlusion and its one-bounce indirect light, through the operator.
#include "base/error.h"
#include "core/operator.h"
#include "support/closed_forms.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace obscura;
using namespace obscura::test;
using glm::dvec3;

namespace {

Settings ssdoSettings(bool bounce) {
    Settings s;
    s.method = "ssdo";
    s.radius = 1.0f;
    s.ssdoSamples = 64;
    s.interleave = 2;
    s.bounce = bounce;
    return s;
}

// A floor (y = 0, x <= 0) and, optionally, a wall at x = 0 facing -x, seen from the open side.
SceneBuffers floorScene(bool wall, int w, int h) {
    const double L = 50;
    std::vector<Rect> rects = {Rect{dvec3(-L, 0, -L), dvec3(L, 0, 0), dvec3(0, 0, 2 * L)}};
    if (wall) rects.push_back(Rect{dvec3(0, 0, -L), dvec3(0, 3, 0), dvec3(0, 0, 2 * L)});
    return renderScene(rects, lookAtPerspective(dvec3(-6, 5, 3), dvec3(-0.8, 0, 0), 50.0 * M_PI / 180, w, h), w, h);
}

// Radiance of the bounce source: red on the wall (x ~ 0), white on the floor.
Image wallColouredRadiance(const SceneBuffers& sb) {
    Image r(sb.depth.width, sb.depth.height, 3, 0.0f);
    for (int y = 0; y < r.height; ++y)
        for (int x = 0; x < r.width; ++x) {
            if (!(*sb.depth.at(x, y) < 1e9f)) continue;
            const bool onWall = sb.normal.at(x, y)[0] < -0.5f;
            float* v = r.at(x, y);
            v[0] = 1.0f;
            v[1] = v[2] = onWall ? 0.0f : 1.0f;
        }
    return r;
}

} // namespace

// Furnace: a white constant sky (radiance 1) over an open plane gives DO = pi (the sky's
// irradiance), AO = 1 and no bounce, at every pixel.
TEST(Ssdo, FurnaceOpenPlaneReceivesTheWholeSky) {
    const SceneBuffers sb = floorScene(false, 64, 48);
    const Image radiance = wallColouredRadiance(sb);
    OperatorInputs in = sb.inputs();
    in.radiance = radiance.view();
    const OperatorOutputs out = runOperator(in, ssdoSettings(true));
    int surface = 0;
    for (int i = 0; i < 64 * 48; ++i) {
        if (!(sb.depth.pixels[i] < 1e9f)) continue;
        ++surface;
        for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(out.directional.pixels[3 * i + c], M_PI, 0.01 * M_PI);
            EXPECT_EQ(out.indirect.pixels[3 * i + c], 0.0f);
        }
        EXPECT_NEAR(out.ao.pixels[i], 1.0f, 1e-6);
    }
    EXPECT_GT(surface, 1000);
}

// A white floor beside a red wall receives red indirect light near the wall, more the closer
// it is, and none without the wall.
TEST(Ssdo, RedWallBleedsRedOntoTheFloor) {
    const int W = 160, H = 120;
    for (bool wall : {true, false}) {
        const SceneBuffers sb = floorScene(wall, W, H);
        const Image radiance = wallColouredRadiance(sb);
        OperatorInputs in = sb.inputs();
        in.radiance = radiance.view();
        const OperatorOutputs out = runOperator(in, ssdoSettings(true));
        double redNear = 0, redFar = 0, greenNear = 0;
        int nNear = 0, nFar = 0;
        for (double z = -1.0; z <= 1.0; z += 0.1) {
            int x, y;
            ASSERT_TRUE(sb.pixelOf(dvec3(-0.2, 0, z), x, y));
            redNear += out.indirect.at(x, y)[0];
            greenNear += out.indirect.at(x, y)[1];
            ++nNear;
            ASSERT_TRUE(sb.pixelOf(dvec3(-0.8, 0, z), x, y));
            redFar += out.indirect.at(x, y)[0];
            ++nFar;
        }
        redNear /= nNear;
        redFar /= nFar;
        greenNear /= nNear;
        if (wall) {
            EXPECT_GT(redNear, 0.05) << "a red wall a fifth of R away must light the floor red";
            EXPECT_LT(greenNear, 0.05 * redNear) << "the bounce carries the wall's colour";
            EXPECT_GT(redNear, redFar) << "closer to the wall, more bounce";
        } else {
            EXPECT_EQ(redNear, 0.0);
        }
    }
}

// The wall blocks light: DO on the floor falls towards the corner, and AO from the same pass
// follows the closed form of the corner.
TEST(Ssdo, CornerDarkensDirectionalOcclusion) {
    const int W = 160, H = 120;
    const SceneBuffers sb = floorScene(true, W, H);
    Settings s = ssdoSettings(false);
    s.ssdoSamples = 256;
    const OperatorOutputs out = runOperator(sb.inputs(), s);
    EXPECT_TRUE(out.indirect.empty()) << "no bounce was asked for: none is computed";
    for (double d : {0.3, 0.6}) {
        double ao = 0, dOcc = 0;
        int n = 0;
        for (double z = -1.0; z <= 1.0; z += 0.1) {
            int x, y;
            ASSERT_TRUE(sb.pixelOf(dvec3(-d, 0, z), x, y));
            ao += *out.ao.at(x, y);
            dOcc += out.directional.at(x, y)[0];
            ++n;
        }
        // Sample points sit uniformly in (0, R] along each direction, so a direction w is found
        // blocked with probability 1 - d / (R w_x): SSDO's AO is cosine-weighted AO with linear falloff.
        const double expected = cornerAo(Weighting::Cosine, Falloff::Linear, d);
        // 0.02: 64 samples per pixel (256 / 2^2) averaged over 21 pixels and blurred over 2 px.
        EXPECT_NEAR(ao / n, expected, 0.02) << "d=" << d;
        EXPECT_NEAR(dOcc / n, M_PI * ao / n, 1e-3) << "a white sky: DO = pi * AO";
    }
}

// A directional light adds n.l times its irradiance where nothing blocks it.
TEST(Ssdo, DirectionalLightAddsLambertIrradiance) {
    const SceneBuffers sb = floorScene(false, 48, 36);
    Settings s = ssdoSettings(false);
    s.skyRadiance[0] = s.skyRadiance[1] = s.skyRadiance[2] = 0.0f;
    const float l = 1.0f / std::sqrt(2.0f);
    s.lights.push_back({{l, l, 0.0f}, {2.0f, 2.0f, 2.0f}});
    const OperatorOutputs out = runOperator(sb.inputs(), s);
    for (int i = 0; i < 48 * 36; ++i) {
        if (sb.depth.pixels[i] < 1e9f) {
            EXPECT_NEAR(out.directional.pixels[3 * i], 2.0f * l, 1e-4);
        }
    }
}

// A contact shadow much smaller than r_max: a sun 30 degrees above the horizon, from +x, over a
// 0.1 block on a floor casts a shadow 0.17 long (x in [-0.223, -0.05], |z| < 0.05). The light's
// march from about a pixel out finds the block where points a quarter of r_max apart pass over it.
TEST(Ssdo, DirectionalLightFindsAContactShadowSmallerThanItsRadius) {
    const int W = 96, H = 72;
    std::vector<Rect> rects = {planeRect(dvec3(0), dvec3(1, 0, 0), dvec3(0, 0, 1))};
    addBox(rects, dvec3(-0.05, 0.0, -0.05), dvec3(0.05, 0.1, 0.05));
    const SceneBuffers sb =
        renderScene(rects, lookAtPerspective(dvec3(-1.0, 1.0, 0.6), dvec3(-0.1, 0.0, 0.0), 40.0 * M_PI / 180, W, H), W, H);
    Settings s = ssdoSettings(false);
    s.interleave = 1;
    s.blur = 0;
    s.skyRadiance[0] = s.skyRadiance[1] = s.skyRadiance[2] = 0.0f;
    const float c = std::cos((float)M_PI / 6), sn = std::sin((float)M_PI / 6);
    s.lights.push_back({{c, sn, 0.0f}, {2.0f, 2.0f, 2.0f}});
    const OperatorOutputs out = runOperator(sb.inputs(), s);
    for (double x : {-0.15, -0.12, -0.09, -0.07})
        for (double z : {-0.03, 0.0, 0.03}) {
            int px, py;
            ASSERT_TRUE(sb.pixelOf(dvec3(x, 0, z), px, py));
            EXPECT_EQ(out.directional.at(px, py)[0], 0.0f) << "in the shadow at x " << x << ", z " << z;
        }
    for (double x : {-0.5, -0.4})
        for (double z : {-0.03, 0.0, 0.03}) {
            int px, py;
            ASSERT_TRUE(sb.pixelOf(dvec3(x, 0, z), px, py));
            EXPECT_NEAR(out.directional.at(px, py)[0], 2.0f * sn, 1e-4) << "past the shadow at x " << x;
        }
}

TEST(Ssdo, BounceWithoutSourceIsAClearError) {
    const SceneBuffers sb = floorScene(true, 16, 12);
    EXPECT_THROW(runOperator(sb.inputs(), ssdoSettings(true)), Error);
}
