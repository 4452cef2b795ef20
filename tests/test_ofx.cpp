// The OpenFX plugin's bundle, what it declares, parity with the CLI (whole frame and tiled), host behaviour, install.
// A test host (tests/ofx_host) loads the built bundle with dlopen as Nuke, Natron or Resolve would and drives
// describe / describeInContext / createInstance / getRegionsOfInterest / isIdentity / render over tiles; the
// output is compared with the command line on the same planes. test_ofx_ssdo.cpp has the SSDO outputs,
// test_ofx_host_findings.cpp what a HostSupport host checks; support/ofx_fixtures.h the shared scene and host set-up.
#include "core/devices.h"
#include "core/methods.h"
#include "ofx_host/ofx_host.h"
#include "support/cli_runner.h"
#include "support/ofx_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::ofxhost;
using namespace obscura::test;

namespace {

std::string readText(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// Compares the plugin's frame (y up) with the CLI's AO (y down) pixel for pixel, bitwise.
void expectSameAsCli(const HostImage& frame, const std::vector<float>& cli, const Box2i& data, const char* what) {
    ASSERT_EQ(frame.bounds.x1, data.x0) << what;
    ASSERT_EQ(frame.width(), data.width()) << what;
    ASSERT_EQ(frame.height(), data.height()) << what;
    ASSERT_EQ(cli.size(), (size_t)data.width() * data.height()) << what;
    int differing = 0;
    std::string first;
    for (int dy = data.y0; dy < data.y1; ++dy)
        for (int dx = data.x0; dx < data.x1; ++dx) {
            const float* p = frame.at(dx, kH - 1 - dy);
            const float want = cli[(size_t)(dy - data.y0) * data.width() + (dx - data.x0)];
            const bool same = std::memcmp(&p[0], &want, sizeof(float)) == 0 && p[1] == p[0] && p[2] == p[0] && p[3] == 1.0f;
            if (!same && differing++ == 0)
                first = "at display (" + std::to_string(dx) + "," + std::to_string(dy) + "): plugin " + num(p[0]) +
                        ", CLI " + num(want);
        }
    EXPECT_EQ(differing, 0) << what << ": " << differing << " pixels differ, first " << first;
}

// ---------------------------------------------------------------------------
// The bundle and what the plugin declares
// ---------------------------------------------------------------------------

TEST(OfxBundle, LayoutInfoPlistAndExports) {
    const fs::path bin = fs::path(kBundle) / "Contents" / OBSCURA_OFX_ARCH / "obscura.ofx";
    ASSERT_TRUE(fs::is_regular_file(bin)) << bin;
    const std::string plist = readText(fs::path(kBundle) / "Contents" / "Info.plist");
    EXPECT_NE(plist.find("<key>CFBundleExecutable</key>"), std::string::npos);
    EXPECT_NE(plist.find("<string>obscura.ofx</string>"), std::string::npos);
    EXPECT_NE(plist.find("<string>BNDL</string>"), std::string::npos);

    Host host(kBundle);
    ASSERT_EQ(host.error(), "");
    EXPECT_EQ(host.numberOfPlugins(), 1);
    ASSERT_NE(host.plugin(), nullptr);
    EXPECT_STREQ(host.plugin()->pluginApi, "OfxImageEffectPluginAPI");
    EXPECT_EQ(host.plugin()->apiVersion, 1);
    EXPECT_STREQ(host.plugin()->pluginIdentifier, "io.github.obscura.AmbientOcclusion");

    // Only the two OFX entry points are exported: nothing of obscura (or its static
    // dependencies) can clash with the host's own symbols.
    const test::CliResult nm = test::runProgram("/usr/bin/nm", {"-D", "--defined-only", bin.string()});
    if (nm.exitCode == 0) {
        std::istringstream lines(nm.out);
        std::string line;
        std::vector<std::string> exported;
        while (std::getline(lines, line)) {
            std::istringstream f(line);
            std::string addr, type, name;
            f >> addr >> type >> name;
            if (type == "T" || type == "D" || type == "B" || type == "R") exported.push_back(name);
        }
        std::sort(exported.begin(), exported.end());
        EXPECT_EQ(exported, (std::vector<std::string>{"OfxGetNumberOfPlugins", "OfxGetPlugin"}));
    }
}

TEST(OfxDescribe, DeclaresContextsDepthsClipsAndParameters) {
    Host host(kBundle);
    ASSERT_EQ(host.error(), "");
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    const auto suites = host.fetchedSuites();
    for (const char* s : {"OfxPropertySuite v1", "OfxImageEffectSuite v1", "OfxParameterSuite v1"})
        EXPECT_NE(std::find(suites.begin(), suites.end(), s), suites.end()) << s;

    const PropertySet& d = host.descriptor().props;
    EXPECT_EQ(d.strings(kOfxImageEffectPropSupportedContexts), (std::vector<std::string>{kOfxImageEffectContextGeneral}));
    EXPECT_EQ(d.strings(kOfxImageEffectPropSupportedPixelDepths), (std::vector<std::string>{kOfxBitDepthFloat}));
    EXPECT_EQ(d.string(kOfxImageEffectPluginRenderThreadSafety), kOfxImageEffectRenderFullySafe);
    EXPECT_EQ(d.integer(kOfxImageEffectPropSupportsTiles), 1);
    EXPECT_EQ(d.integer(kOfxImageEffectPluginPropSingleInstance), 0);
    EXPECT_EQ(d.integer(kOfxImageEffectPropTemporalClipAccess), 0);

    struct ClipWant {
        const char* name;
        int optional;
    };
    for (ClipWant c : {ClipWant{"Source", 1}, {"Depth", 0}, {"Normal", 1}, {"Position", 1}, {"Albedo", 1}, {"Output", 0}}) {
        const Clip* clip = host.descriptor().clip(c.name);
        ASSERT_NE(clip, nullptr) << c.name;
        EXPECT_EQ(clip->props.integer(kOfxImageClipPropOptional), c.optional) << c.name;
        const auto comps = clip->props.strings(kOfxImageEffectPropSupportedComponents);
        EXPECT_NE(std::find(comps.begin(), comps.end(), kOfxImageComponentRGBA), comps.end()) << c.name;
    }
    const ParamSet& params = host.descriptor().params;
    for (const char* p : {"output", "strength", "method", "radius", "directions", "steps", "weighting", "falloff", "blur",
                          "projection", "fovDeg", "focalMm", "apertureMm", "orthoWidth", "cameraToWorld", "depthKind",
                          "depthRangeNear", "depthRangeFar", "normalSpace", "skyDepth",
                          "maxScreenRadius", "device", "threads", "samples", "interleave", "skyColour", "envMap",
                          "envRotation", "envIntensity", "upAxis", "timesAlbedo"})
        EXPECT_NE(params.find(p), nullptr) << p;
    // Hosts store a choice's index: new entries are appended, never inserted.
    EXPECT_EQ(params.find("output")->props.strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"AO", "Beauty x AO", "Directional occlusion (DO)", "Indirect (GI)", "Relit"}));
    EXPECT_EQ(params.find("method")->props.strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"hbao", "ssdo", "ssao", "rtao", "discs"}));
    // The methods' own parameters come from the method table, with its ranges, one group per method.
    EXPECT_EQ(params.find("ssao_samples")->props.ints(kOfxParamPropMax), (std::vector<int>{1024}));
    EXPECT_EQ(params.find("ssao_hemisphere")->type, kOfxParamTypeBoolean);
    EXPECT_EQ(params.find("rtao_grid")->props.ints(kOfxParamPropMin), (std::vector<int>{1}));
    // thickness is hbao's and rtao's, listed under hbao; -1 (auto) and 1e9 (inf) are inside its range.
    EXPECT_EQ(params.find("thickness")->props.doubles(kOfxParamPropMin), (std::vector<double>{-1.0}));
    EXPECT_EQ(params.find("thickness")->props.doubles(kOfxParamPropMax), (std::vector<double>{1e9}));
    EXPECT_EQ(params.find("thickness")->props.doubles(kOfxParamPropDefault), (std::vector<double>{-1.0}));
    EXPECT_EQ(params.find("thickness")->props.string(kOfxParamPropParent), "hbao");
    EXPECT_EQ(params.find("disc_window")->props.ints(kOfxParamPropMax), (std::vector<int>{4}));
    // Deep samples cannot reach an OpenFX node (its clips are flat images): no deep_layers there.
    EXPECT_EQ(params.find("deep_layers"), nullptr);
    EXPECT_EQ(params.find("disc_no_polygon")->type, kOfxParamTypeBoolean);
    EXPECT_EQ(params.find("samples")->props.ints(kOfxParamPropDefault), (std::vector<int>{64}));
    EXPECT_EQ(params.find("interleave")->props.ints(kOfxParamPropDefault), (std::vector<int>{2}));
    EXPECT_EQ(params.find("interleave")->props.ints(kOfxParamPropMax), (std::vector<int>{8}));
    EXPECT_EQ(params.find("skyColour")->type, kOfxParamTypeRGB);
    EXPECT_EQ(params.find("skyColour")->props.doubles(kOfxParamPropDefault), (std::vector<double>{1.0, 1.0, 1.0}));
    EXPECT_EQ(params.find("envMap")->props.string(kOfxParamPropStringMode), kOfxParamStringIsFilePath);
    EXPECT_EQ(params.find("upAxis")->props.strings(kOfxParamPropChoiceOption), (std::vector<std::string>{"y", "z"}));
    EXPECT_EQ(params.find("timesAlbedo")->type, kOfxParamTypeBoolean);
    for (const char* p : {"samples", "interleave", "skyColour", "envMap", "envRotation", "envIntensity", "upAxis",
                          "timesAlbedo"})
        EXPECT_EQ(params.find(p)->props.string(kOfxParamPropParent), "ssdoGroup") << p;
    EXPECT_EQ(params.find("radius")->props.doubles(kOfxParamPropDefault), (std::vector<double>{1.0}));
    EXPECT_EQ(params.find("directions")->props.ints(kOfxParamPropDefault), (std::vector<int>{8}));
    // The CLI's and Python's default blur (the method's own: medium's 1 px, ssdo's interleave width).
    EXPECT_EQ(params.find("blur")->props.ints(kOfxParamPropDefault), (std::vector<int>{obscura::Settings().blur}));
    EXPECT_EQ(params.find("maxScreenRadius")->props.doubles(kOfxParamPropDefault), (std::vector<double>{256.0}));
    // The lens and the depth encodings of the CLI (--focal-mm, --aperture-mm, --depth, --depth-range).
    EXPECT_EQ(params.find("projection")->props.strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"perspective", "orthographic", "perspective (focal length)"}));
    EXPECT_EQ(params.find("depthKind")->props.strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"planar", "radial", "inverse", "normalized"}));
    EXPECT_EQ(params.find("focalMm")->props.doubles(kOfxParamPropDefault), (std::vector<double>{50.0}));
    EXPECT_EQ(params.find("apertureMm")->props.doubles(kOfxParamPropDefault), (std::vector<double>{36.0}));
    EXPECT_EQ(params.find("device")->props.strings(kOfxParamPropChoiceOption),
              (std::vector<std::string>{"cpu", "auto", "gl", "gl-egl", "gl-osmesa"}));
}

// ---------------------------------------------------------------------------
// Identical to the CLI, whole frame and tiled
// ---------------------------------------------------------------------------

class OfxMatchesCli : public ::testing::TestWithParam<Config> {};

TEST_P(OfxMatchesCli, WholeFrameAndTilesAreTheCliPixels) {
    const Config c = GetParam();
    const fs::path dir = testDir();
    const Scene s = makeScene(c);
    const std::vector<float> cli = runCli(c, s, dir);
    ASSERT_FALSE(cli.empty());

    // Normals from the depth: no Normal clip at all (the CLI's file has them; --normals depth ignores them).
    Loaded l = c.normals == NormalSpace::Depth ? instantiateIn(s, project(kW, kH), {"Depth"}) : instantiate(s);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    OfxRectD rod{};
    ASSERT_EQ(l.inst->regionOfDefinition(rod), kOfxStatOK);
    EXPECT_EQ(rod.x1, s.depthClip.bounds.x1);
    EXPECT_EQ(rod.y2, s.depthClip.bounds.y2);

    std::vector<std::string> problems;
    const HostImage whole = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_EQ(joined(problems), "");
    expectSameAsCli(whole, cli, s.buf.data, "whole frame");

    for (auto [tw, th, threads] : {std::tuple{32, 32, 1}, std::tuple{17, 11, 3}, std::tuple{kW + 2 * c.overscan, 5, 2}}) {
        problems.clear();
        const HostImage tiled = l.inst->renderFrame(tw, th, threads, problems);
        EXPECT_EQ(joined(problems), "") << tw << "x" << th;
        EXPECT_TRUE(sameBits(tiled, whole)) << "tiles " << tw << "x" << th << " differ from the whole frame";
        expectSameAsCli(tiled, cli, s.buf.data, "tiled");
    }
    EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(Configs, OfxMatchesCli,
                         ::testing::Values(cfg("perspective"),
                                           [] {
                                               Config c = cfg("cosine_none_blur_auto_cap");
                                               c.cosine = true, c.noFalloff = true, c.blur = 2, c.radius = 1.0;
                                               c.maxScreenRadius = 0;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("orthographic_overscan");
                                               c.orthographic = true, c.overscan = 6, c.directions = 6, c.steps = 5;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("radial_camera_normals");
                                               c.depth = DepthKind::Radial, c.normals = NormalSpace::Camera;
                                               c.blur = 1, c.overscan = 3;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("no_normal_clip_normals_from_depth");
                                               c.normals = NormalSpace::Depth, c.blur = 1, c.overscan = 3;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("film_back_inverse_depth_no_normal_clip");
                                               c.filmBack = true, c.stored = "inverse", c.normals = NormalSpace::Depth;
                                               c.overscan = 2;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("film_back_normalized_depth_white_near");
                                               c.filmBack = true, c.stored = "normalized", c.blur = 1;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("ssao_normals_from_depth");
                                               c.method = 2, c.normals = NormalSpace::Depth;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("ssao_from_the_method_table");
                                               c.method = 2, c.ssaoSamples = 12, c.overscan = 4;
                                               return c;
                                           }(),
                                           [] {
                                               Config c = cfg("rtao_thickness_grid");
                                               c.method = 3, c.thickness = 0.1, c.rtaoGrid = 2, c.cosine = true;
                                               return c;
                                           }(),
                                           [] {  // a hierarchy over the whole frame: every tile reads it all
                                               Config c = cfg("discs_whole_frame_hierarchy");
                                               c.method = 4, c.overscan = 3, c.maxScreenRadius = 10;
                                               return c;
                                           }()),
                         [](const ::testing::TestParamInfo<Config>& i) { return i.param.name; });

// ---------------------------------------------------------------------------
// Host behaviour: regions of interest, tiles, identity, instances
// ---------------------------------------------------------------------------

// With a cap the radius actually reaches, tiles still equal the whole frame, and each
// tile asks for exactly its window plus the apron (cap + 2 + blur), clipped to the RoD.
TEST(OfxHostBehaviour, PinnedCapTilesEqualWholeFrameWithExactApron) {
    Config c;
    c.radius = 3.0, c.maxScreenRadius = 7.5, c.blur = 2;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);

    std::map<std::string, OfxRectD> rois;
    ASSERT_EQ(l.inst->regionsOfInterest({40, 20, 56, 36}, rois), kOfxStatOK);
    const int apron = 8 + 2 + 2;
    const OfxRectD want{40.0 - apron, 20.0 - apron, 56.0 + apron, 36.0 + apron};
    for (const char* clip : {"Depth", "Normal"}) {
        EXPECT_EQ(rois[clip].x1, want.x1) << clip;
        EXPECT_EQ(rois[clip].y1, want.y1) << clip;
        EXPECT_EQ(rois[clip].x2, want.x2) << clip;
        EXPECT_EQ(rois[clip].y2, want.y2) << clip;
    }
    // Near a corner the apron is clipped to the depth's RoD: never more than exists.
    ASSERT_EQ(l.inst->regionsOfInterest({0, 0, 8, 8}, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x1, 0.0);
    EXPECT_EQ(rois["Depth"].y1, 0.0);
    EXPECT_EQ(rois["Depth"].x2, 8.0 + apron);
    // Inputs the AO output does not read are not requested.
    for (const char* clip : {"Source", "Position", "Albedo"}) {
        EXPECT_EQ(rois[clip].x2 - rois[clip].x1, 0.0) << clip;
    }

    std::vector<std::string> problems;
    const HostImage whole = l.inst->renderFrame(0, 0, 1, problems);
    for (auto [tw, th] : {std::pair{8, 8}, std::pair{23, 9}, std::pair{1, 64}}) {
        const HostImage tiled = l.inst->renderFrame(tw, th, 2, problems);
        EXPECT_TRUE(sameBits(tiled, whole)) << tw << "x" << th;
    }
    EXPECT_EQ(joined(problems), "");
    // The cap binds here, so the automatic (CLI) cap gives a different image: the pin matters.
    ASSERT_EQ(l.inst->setDouble("maxScreenRadius", 0.0), kOfxStatOK);
    const HostImage autoCap = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_FALSE(sameBits(autoCap, whole));
}

TEST(OfxHostBehaviour, PositiveRowBytesAndAlphaOutput) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded rgba = instantiate(s);
    ASSERT_TRUE(rgba.inst);
    applyConfig(*rgba.inst, c, s);
    std::vector<std::string> problems;
    const HostImage ref = rgba.inst->renderFrame(0, 0, 1, problems);
    rgba.reset();

    Loaded alpha = instantiate(s, false, 1);
    ASSERT_TRUE(alpha.inst);
    alpha.host->negativeRowBytes = false;
    applyConfig(*alpha.inst, c, s);
    const HostImage a = alpha.inst->renderFrame(16, 16, 2, problems);
    EXPECT_EQ(joined(problems), "");
    ASSERT_EQ(a.components, 1);
    for (size_t i = 0; i < a.pixels.size(); ++i) ASSERT_EQ(a.pixels[i], ref.pixels[i * 4]) << i;
}

TEST(OfxHostBehaviour, BeautyTimesAoAndIdentityWhenOff) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s, true);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    std::vector<std::string> problems;
    const HostImage ao = l.inst->renderFrame(0, 0, 1, problems);

    ASSERT_EQ(l.inst->setInt("output", 1), kOfxStatOK);
    std::map<std::string, OfxRectD> rois;
    ASSERT_EQ(l.inst->regionsOfInterest({10, 10, 20, 20}, rois), kOfxStatOK);
    EXPECT_EQ(rois["Source"].x1, 10.0);  // the beauty is read under the window only
    EXPECT_EQ(rois["Source"].x2, 20.0);
    const HostImage lit = l.inst->renderFrame(24, 16, 2, problems);
    EXPECT_EQ(joined(problems), "");
    for (int y = lit.bounds.y1; y < lit.bounds.y2; ++y)
        for (int x = lit.bounds.x1; x < lit.bounds.x2; ++x) {
            const float* b = s.beautyClip.at(x, y);
            const float a = ao.at(x, y)[0];
            const float* o = lit.at(x, y);
            ASSERT_EQ(o[0], b[0] * a);
            ASSERT_EQ(o[1], b[1] * a);
            ASSERT_EQ(o[2], b[2] * a);
            ASSERT_EQ(o[3], b[3]);
        }

    // Strength 0 is "off": an identity on Source, so the host need not render at all.
    ASSERT_EQ(l.inst->setDouble("strength", 0.0), kOfxStatOK);
    std::string clip;
    EXPECT_EQ(l.inst->isIdentity({0, 0, kW, kH}, clip), kOfxStatOK);
    EXPECT_EQ(clip, "Source");
    ASSERT_EQ(l.inst->setInt("output", 0), kOfxStatOK);
    EXPECT_EQ(l.inst->isIdentity({0, 0, kW, kH}, clip), kOfxStatReplyDefault);
    ASSERT_EQ(l.inst->regionsOfInterest({10, 10, 20, 20}, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x2 - rois["Depth"].x1, 0.0);  // AO off reads no depth
    const HostImage white = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_EQ(joined(problems), "");
    for (int y = white.bounds.y1; y < white.bounds.y2; ++y)
        for (int x = white.bounds.x1; x < white.bounds.x2; ++x) ASSERT_EQ(white.at(x, y)[0], 1.0f);
}

// A Source larger than Depth (a plate with more overscan than its depth pass): Beauty x AO's
// region of definition is both clips', and the beauty outside the depth passes unchanged; the AO's
// stays Depth's.
TEST(OfxHostBehaviour, BeautyTimesAoKeepsALargerSource) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s, true);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    ASSERT_EQ(l.inst->setInt("output", 1), kOfxStatOK);
    std::vector<std::string> problems;
    const HostImage lit = l.inst->renderFrame(0, 0, 1, problems);

    Scene wide = s;
    const OfxRectI d = s.beautyClip.bounds;
    wide.beautyClip = HostImage({d.x1 - 8, d.y1 - 5, d.x2 + 7, d.y2 + 6}, 4);
    for (int y = wide.beautyClip.bounds.y1; y < wide.beautyClip.bounds.y2; ++y)
        for (int x = wide.beautyClip.bounds.x1; x < wide.beautyClip.bounds.x2; ++x) {
            const bool inDepth = x >= d.x1 && x < d.x2 && y >= d.y1 && y < d.y2;
            const float outside[4] = {0.25f + 0.001f * x, 0.5f, 0.125f + 0.001f * y, 0.75f};
            std::copy_n(inDepth ? s.beautyClip.at(x, y) : outside, 4, wide.beautyClip.at(x, y));
        }
    Loaded w = instantiateIn(wide, project(kW, kH), {"Depth", "Normal", "Source"});
    ASSERT_TRUE(w.inst);
    applyConfig(*w.inst, c, s);
    ASSERT_EQ(w.inst->setInt("output", 1), kOfxStatOK);
    OfxRectD rod{};
    ASSERT_EQ(w.inst->regionOfDefinition(rod), kOfxStatOK);
    EXPECT_EQ(std::vector<double>({rod.x1, rod.y1, rod.x2, rod.y2}),
              std::vector<double>({d.x1 - 8.0, d.y1 - 5.0, d.x2 + 7.0, d.y2 + 6.0}));
    const HostImage wideLit = w.inst->renderFrame(24, 16, 2, problems);
    EXPECT_EQ(joined(problems), "");
    ASSERT_EQ(wideLit.bounds.x1, d.x1 - 8);
    for (int y = wideLit.bounds.y1; y < wideLit.bounds.y2; ++y)
        for (int x = wideLit.bounds.x1; x < wideLit.bounds.x2; ++x) {
            const bool inDepth = x >= d.x1 && x < d.x2 && y >= d.y1 && y < d.y2;
            const float* expected = inDepth ? lit.at(x, y) : wide.beautyClip.at(x, y);
            for (int ch = 0; ch < 4; ++ch) ASSERT_EQ(wideLit.at(x, y)[ch], expected[ch]) << x << "," << y;
        }
    ASSERT_EQ(w.inst->setInt("output", 0), kOfxStatOK);
    ASSERT_EQ(w.inst->regionOfDefinition(rod), kOfxStatOK);
    EXPECT_EQ(std::vector<double>({rod.x1, rod.y1, rod.x2, rod.y2}),
              std::vector<double>({double(d.x1), double(d.y1), double(d.x2), double(d.y2)}));
}

// Two instances with different settings, rendering at the same time, each get their own result.
TEST(OfxHostBehaviour, InstancesShareNoState) {
    Config c1, c2;
    c2.radius = 1.5, c2.cosine = true, c2.directions = 4;
    const Scene s = makeScene(c1);
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c1, s);
    ProjectSetup project;
    project.width = kW, project.height = kH;
    OfxStatus st = kOfxStatFailed;
    auto second = l.host->createInstance(project, {{"Depth", &s.depthClip}, {"Normal", &s.normalClip}}, &st);
    ASSERT_EQ(st, kOfxStatOK);
    applyConfig(*second, c2, s);

    std::vector<std::string> p1, p2;
    const HostImage a = l.inst->renderFrame(0, 0, 1, p1);
    const HostImage b = second->renderFrame(0, 0, 1, p1);
    EXPECT_FALSE(sameBits(a, b));
    HostImage a2, b2;
    std::thread t1([&] { a2 = l.inst->renderFrame(20, 20, 2, p1); });
    std::thread t2([&] { b2 = second->renderFrame(13, 30, 2, p2); });
    t1.join();
    t2.join();
    EXPECT_EQ(joined(p1) + joined(p2), "");
    EXPECT_TRUE(sameBits(a, a2));
    EXPECT_TRUE(sameBits(b, b2));
}

// The node greys out what the method does not read, from the table the CLI and Python refuse
// by (core/methods.h): generated from it, like tests/test_method_flags.cpp.
TEST(OfxHostBehaviour, ParametersOfOtherMethodsAreDisabled) {
    const Scene s = makeScene(Config{});
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    auto enabled = [&](const std::string& name) {
        const Param* p = l.inst->effect().params.find(name);
        EXPECT_TRUE(p) << name;
        return p && p->props.integer(kOfxParamPropEnabled, 0, 1) != 0;
    };
    // Output 0 is AO, computed by the chosen method; output 2 (DO) always by ssdo.
    std::vector<std::pair<int, int>> cases;  // (output, method index)
    for (int m = 0; m < (int)methods().size(); ++m) cases.push_back({0, m});
    cases.push_back({2, 0});
    int checked = 0;
    for (const auto& [output, m] : cases) {
        ASSERT_EQ(l.inst->setInt("output", output), kOfxStatOK);
        ASSERT_EQ(l.inst->setInt("method", m), kOfxStatOK);
        const std::string method = output == 0 ? methods()[m].name : "ssdo";
        for (const MethodParam* p : allMethodParams()) {
            if (!p->ofx) continue;
            EXPECT_EQ(enabled(p->key), settingRefusal(method, p->key, Spelling::Key).empty()) << method << " " << p->key;
            ++checked;
        }
        for (const MethodOption& o : methodOptions()) {
            if (!o.ofx || std::string(o.ofx) == "timesAlbedo") continue;  // also follows the output (DO, GI)
            EXPECT_EQ(enabled(o.ofx), settingRefusal(method, o.ofx, Spelling::Key).empty()) << method << " " << o.ofx;
            ++checked;
        }
    }
    EXPECT_GT(checked, 50);
    // The describe step says the same: each such parameter names its methods in its hint.
    Host host(kBundle);
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    // The device choice is core's one list, in its stored order.
    const Param* device = host.descriptor().params.find("device");
    ASSERT_TRUE(device);
    std::vector<std::string> names;
    for (const DeviceName& d : deviceNames()) names.push_back(d.name);
    EXPECT_EQ(device->props.strings(kOfxParamPropChoiceOption), names);
    for (const MethodParam* p : allMethodParams())
        if (p->ofx) {
            const Param* d = host.descriptor().params.find(p->key);
            ASSERT_TRUE(d) << p->key;
            EXPECT_NE(d->props.string(kOfxParamPropHint).find("[read by " + methodsReading(p->key).front()), std::string::npos)
                << p->key;
        }
}

TEST(OfxHostBehaviour, FailuresAreReportedThroughTheMessageSuite) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    ASSERT_EQ(l.inst->setString("cameraToWorld", ""), kOfxStatOK);  // world normals without a pose
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame), kOfxStatFailed);
    const auto msgs = l.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("OfxMessageError"), std::string::npos) << msgs[0];
    EXPECT_NE(msgs[0].find("camera pose"), std::string::npos) << msgs[0];
    EXPECT_EQ(l.host->liveImages(), 0);

    ASSERT_EQ(l.inst->setString("cameraToWorld", "1,2,3"), kOfxStatOK);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame), kOfxStatFailed);
    EXPECT_EQ(l.host->liveImages(), 0);
}

// ---------------------------------------------------------------------------
// cmake --install lays out a bundle a host can load from OFX_PLUGIN_PATH
// ---------------------------------------------------------------------------

TEST(OfxInstall, CmakeInstallLaysOutALoadableBundle) {
    const fs::path prefix = testDir() / "prefix";
    const test::CliResult r = test::runProgram(
        OBSCURA_CMAKE_COMMAND, {"--install", OBSCURA_BUILD_DIR, "--prefix", prefix.string(), "--component", "ofx"});
    ASSERT_EQ(r.exitCode, 0) << r.out << r.err;
    const fs::path bundle = prefix / "OFX" / "Plugins" / "obscura.ofx.bundle";
    EXPECT_TRUE(fs::is_regular_file(bundle / "Contents" / "Info.plist"));
    EXPECT_TRUE(fs::is_regular_file(bundle / "Contents" / OBSCURA_OFX_ARCH / "obscura.ofx"));
    // Nothing else is installed by the component: the plugin, the OpenImageIO module and the colour config.
    std::vector<std::string> files;
    for (const auto& e : fs::recursive_directory_iterator(prefix))
        if (e.is_regular_file()) files.push_back(fs::relative(e.path(), prefix).string());
    std::sort(files.begin(), files.end());
    const std::string arch = std::string("OFX/Plugins/obscura.ofx.bundle/Contents/") + OBSCURA_OFX_ARCH;
    EXPECT_EQ(files, (std::vector<std::string>{"OFX/Plugins/obscura.ofx.bundle/Contents/Info.plist",
                                               arch + "/libobscura_oiio.so", arch + "/obscura.ofx",
                                               "OFX/Plugins/obscura.ofx.bundle/Contents/Resources/ocio/config.ocio"}));

    // The installed copy renders the same pixels as the build tree's.
    const Config c;
    const Scene s = makeScene(c);
    std::vector<std::string> problems;
    Loaded built = instantiate(s);
    ASSERT_TRUE(built.inst);
    applyConfig(*built.inst, c, s);
    const HostImage a = built.inst->renderFrame(0, 0, 1, problems);
    built.reset();
    Loaded installed = instantiate(s, false, 4, bundle.string());
    ASSERT_TRUE(installed.inst);
    applyConfig(*installed.inst, c, s);
    const HostImage b = installed.inst->renderFrame(32, 32, 1, problems);
    EXPECT_EQ(joined(problems), "");
    EXPECT_TRUE(sameBits(a, b));
}

} // namespace
