// The OpenFX plugin against what an official-HostSupport host checks (issue 13): PAR, render scale, clips, colour.
#include "ofx_host/ofx_host.h"
#include "support/ofx_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::ofxhost;
using namespace obscura::test;

namespace {

void expectBounds(const HostImage& img, int w, int h) {
    EXPECT_EQ(img.bounds.x1, 0);
    EXPECT_EQ(img.bounds.y1, 0);
    EXPECT_EQ(img.bounds.x2, w);
    EXPECT_EQ(img.bounds.y2, h);
}

TEST(OfxHostFindings, DeclaresWhatTheSpecificationNames) {
    Host host(kBundle);
    ASSERT_EQ(host.error(), "");
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    const PropertySet& d = host.descriptor().props;
    // Spelled as the specification spells them, not through ofx_api.h.
    EXPECT_EQ(d.integer("OfxImageEffectPropMultipleClipDepths", 0, -1), 0);
    EXPECT_EQ(d.integer("OfxImageEffectPropSupportsMultiResolution", 0, -1), 1);
    EXPECT_EQ(d.strings("OfxImageEffectPropClipPreferencesSlaveParam"), std::vector<std::string>{"output"});
    EXPECT_FALSE(d.has("OfxImageEffectPropColourManagementStyle"));  // a 1.4 host offered none
    // Only General is declared: any other context is a feature this host asks for in vain.
    EXPECT_EQ(host.describeInContext("OfxImageEffectContextFilter"), kOfxStatErrMissingHostFeature);
}

// Anamorphic project (PAR 2): canonical x is twice pixel x. With exact-region delivery,
// tiles only see what their RoI asked for, so a halved apron would show as seams.
TEST(OfxHostFindings, Par2TilesEqualWholeFrame) {
    Config c;
    c.maxScreenRadius = 12;  // a real apron: tiles do not read the whole frame
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH, 2.0), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    OfxRectD rod{};
    ASSERT_EQ(l.inst->regionOfDefinition(rod), kOfxStatOK);
    EXPECT_EQ(rod.x2, 2.0 * kW);  // canonical
    std::vector<std::string> p1, p2;
    const HostImage whole = l.inst->renderFrame(0, 0, 1, p1);
    const HostImage tiled = l.inst->renderFrame(20, 16, 2, p2);
    EXPECT_EQ(joined(p1) + joined(p2), "");
    expectBounds(whole, kW, kH);
    EXPECT_LE(maxAbsDiff(whole, tiled), 1e-6f);

    // The PAR reaches the camera: the same pixels in a square-pixel project give other AO.
    Loaded sq = instantiateIn(s, project(kW, kH, 1.0), {"Depth", "Normal"});
    applyConfig(*sq.inst, c, s);
    std::vector<std::string> p3;
    EXPECT_GT(maxAbsDiff(whole, sq.inst->renderFrame(0, 0, 1, p3)), 0.05f);
    EXPECT_EQ(joined(p3), "");
}

// A proxy render (render scale 0.5) of a kW x kH project over half-size inputs is the full
// render of a half-size project with the pixel-sized parameters (Blur, Max Screen Radius)
// halved: the camera's intrinsics and the pixel radii follow the scale. Tiles agree.
TEST(OfxHostFindings, RenderScaleHalfIsTheHalfSizeRender) {
    Config c;
    c.radius = 3, c.maxScreenRadius = 24, c.blur = 2;  // a radius the cap binds
    const Scene half = makeScene(c, kW / 2, kH / 2);
    Loaded proxy = instantiateIn(half, project(kW, kH, 1.0, 0.5), {"Depth", "Normal"});
    ASSERT_TRUE(proxy.inst);
    applyConfig(*proxy.inst, c, half);
    std::vector<std::string> p1, p2, p3;
    const HostImage whole = proxy.inst->renderFrame(0, 0, 1, p1);
    const HostImage tiled = proxy.inst->renderFrame(10, 12, 2, p2);
    EXPECT_EQ(joined(p1) + joined(p2), "");
    expectBounds(whole, kW / 2, kH / 2);
    EXPECT_LE(maxAbsDiff(whole, tiled), 1e-6f);

    Config ch = c;
    ch.maxScreenRadius = 12, ch.blur = 1;
    Loaded small = instantiateIn(half, project(kW / 2, kH / 2), {"Depth", "Normal"});
    applyConfig(*small.inst, ch, half);
    const HostImage ref = small.inst->renderFrame(0, 0, 1, p3);
    EXPECT_EQ(joined(p3), "");
    EXPECT_LE(maxAbsDiff(whole, ref), 1e-6f);
    float lo = 1;
    for (size_t i = 0; i < whole.pixels.size(); i += 4) lo = std::min(lo, whole.pixels[i]);
    EXPECT_LT(lo, 0.9f);  // the frame holds occlusion, not a constant
}

TEST(OfxHostFindings, MissingDepthFailsThroughTheMessageSuite) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, kW, kH}, frame), kOfxStatFailed);
    const auto msgs = l.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("OfxMessageError"), std::string::npos) << msgs[0];
    EXPECT_NE(msgs[0].find("Depth clip is not connected"), std::string::npos) << msgs[0];
    EXPECT_EQ(l.host->liveImages(), 0);
}

// Normalized depth with its range unset (both ends 0, the default) is refused through the
// message suite, in the words of the node's parameters, as the CLI refuses --depth normalized
// without --depth-range.
TEST(OfxHostFindings, NormalizedDepthWithoutARangeFails) {
    Config c;
    c.stored = "normalized";
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    ASSERT_EQ(l.inst->setDouble("depthRangeNear", 0.0), kOfxStatOK);
    ASSERT_EQ(l.inst->setDouble("depthRangeFar", 0.0), kOfxStatOK);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, kW, kH}, frame), kOfxStatFailed);
    const auto msgs = l.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("normalized depth needs Depth Near and Depth Far"), std::string::npos) << msgs[0];
    EXPECT_EQ(l.host->liveImages(), 0);
}

// Unconnected optional clips (Source, Position, Albedo) are neither asked for nor fetched.
TEST(OfxHostFindings, UnconnectedOptionalClipsAreNotRequested) {
    Config c;
    c.maxScreenRadius = 12;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    std::map<std::string, OfxRectD> rois;
    ASSERT_EQ(l.inst->regionsOfInterest({0, 0, 16, 16}, rois), kOfxStatOK);
    for (const char* clip : {"Source", "Position", "Albedo"})
        EXPECT_TRUE(rois.count(clip) && rois[clip].x2 <= rois[clip].x1) << clip;
    EXPECT_EQ(rois["Depth"].x2, 16.0 + 12 + 2);  // the window plus the apron (cap + snapping)
    std::vector<ImageFetch> fetches;
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame, &fetches, &rois), kOfxStatOK);
    for (const ImageFetch& f : fetches) EXPECT_TRUE(f.clip == "Depth" || f.clip == "Normal") << f.clip;
}

// An OFX 1.5 host with Basic colour management: the data clips are asked for in ofx_raw, and
// the output colourspace comes from GetOutputColourspace, re-asked when `output` changes.
TEST(OfxHostFindings, ColourManagedHostGetsTheOutputColourspace) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal", "Source"}, "OfxImageEffectColourManagementBasic");
    ASSERT_TRUE(l.inst);
    EXPECT_EQ(l.host->descriptor().props.string("OfxImageEffectPropColourManagementStyle"),
              "OfxImageEffectColourManagementBasic");
    EXPECT_EQ(l.host->descriptor().props.string("OfxImageEffectPropColourManagementAvailableConfigs"),
              "ofx-native-v1.5_aces-v1.3_ocio-v2.3");
    PropertySet prefs;
    ASSERT_EQ(l.inst->clipPreferences(prefs), kOfxStatOK);
    EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Depth"), "ofx_raw");
    EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Normal"), "ofx_raw");
    EXPECT_EQ(prefs.string("OfxImageClipPropDepth_Output"), kOfxBitDepthFloat);
    const Clip& out = *l.inst->effect().clip("Output");
    EXPECT_EQ(out.props.string("OfxImageClipPropColourspace"), "ofx_raw");
    EXPECT_EQ(out.props.string(kOfxImageEffectPropPreMultiplication), kOfxImageOpaque);

    // Output is a slave of the clip preferences: the host re-runs them (and the colourspace).
    const int runs = l.inst->clipPreferencesRuns;
    ASSERT_EQ(l.inst->setInt("output", 1), kOfxStatOK);  // Beauty x AO
    EXPECT_EQ(l.inst->clipPreferencesRuns, runs + 1);
    EXPECT_EQ(out.props.string("OfxImageClipPropColourspace"), "OfxColourspace_Source");
    EXPECT_EQ(out.props.string(kOfxImageEffectPropPreMultiplication), kOfxImagePreMultiplied);
    ASSERT_EQ(l.inst->setDouble("radius", 2.0), kOfxStatOK);  // not a slave
    EXPECT_EQ(l.inst->clipPreferencesRuns, runs + 1);
}

// A host that offers no colour management, or says None, gets no colourspaces at all.
TEST(OfxHostFindings, NoColourspacesWithoutColourManagement) {
    const Config c;
    const Scene s = makeScene(c);
    for (const std::string style : {"", "OfxImageEffectColourManagementNone"}) {
        Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"}, style);
        ASSERT_TRUE(l.inst);
        EXPECT_FALSE(l.host->descriptor().props.has("OfxImageEffectPropColourManagementStyle")) << style;
        PropertySet prefs;
        ASSERT_EQ(l.inst->clipPreferences(prefs), kOfxStatOK);
        EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Depth"), "") << style;
        std::string space;
        EXPECT_EQ(l.inst->outputColourspace({"ofx_scene_linear"}, space), kOfxStatReplyDefault) << style;
        EXPECT_FALSE(l.inst->effect().clip("Output")->props.has("OfxImageClipPropColourspace")) << style;
    }
}

} // namespace
