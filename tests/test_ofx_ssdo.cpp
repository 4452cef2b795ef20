// The OpenFX plugin's SSDO outputs (DO, GI, relit) against the operator, the CLI and Python, through the test host.
#include "core/operator.h"
#include "ofx_host/ofx_host.h"
#include "support/exr_fixtures.h"
#include "support/ofx_fixtures.h"
#include "support/scenes.h"

#include <OpenEXR/ImfPixelType.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::ofxhost;
using namespace obscura::test;

namespace {

constexpr int kOutDo = 2, kOutGi = 3, kOutRelit = 4;

// An albedo pass (RGBA clip, y up) over the scene's data window.
HostImage albedoClipOf(const Scene& s) {
    HostImage a(s.beautyClip.bounds, 4);
    for (int y = a.bounds.y1; y < a.bounds.y2; ++y)
        for (int x = a.bounds.x1; x < a.bounds.x2; ++x) {
            float* p = a.at(x, y);
            p[0] = 0.2f + 0.1f * (x % 5), p[1] = 0.6f, p[2] = 0.05f * (y % 9), p[3] = 1.0f;
        }
    return a;
}

// A clip's RGB over the data window as a display-ordered (y down) 3-channel plane.
Image displayRgb(const HostImage& clip, const Box2i& data) {
    Image img(data.width(), data.height(), 3);
    for (int dy = data.y0; dy < data.y1; ++dy)
        for (int dx = data.x0; dx < data.x1; ++dx) {
            const float* p = clip.at(dx, kH - 1 - dy);
            float* o = img.at(dx - data.x0, dy - data.y0);
            o[0] = p[0], o[1] = p[1], o[2] = p[2];
        }
    return img;
}

struct SsdoOptions {
    int samples = 64, interleave = 2;
    float sky[3] = {1.0f, 1.0f, 1.0f};
    double envRotation = 0, envIntensity = 1;
    bool zUp = false;
};

void applySsdo(Instance& inst, const SsdoOptions& o) {
    EXPECT_EQ(inst.setInt("samples", o.samples), kOfxStatOK);
    EXPECT_EQ(inst.setInt("interleave", o.interleave), kOfxStatOK);
    EXPECT_EQ(inst.setRGB("skyColour", o.sky[0], o.sky[1], o.sky[2]), kOfxStatOK);
    EXPECT_EQ(inst.setDouble("envRotation", o.envRotation), kOfxStatOK);
    EXPECT_EQ(inst.setDouble("envIntensity", o.envIntensity), kOfxStatOK);
    EXPECT_EQ(inst.setInt("upAxis", o.zUp ? 1 : 0), kOfxStatOK);
}

// runOperator as the plugin calls it for a whole frame: the same planes, camera and settings.
OperatorOutputs ssdoReference(const Config& c, const Scene& s, const SsdoOptions& o, bool bounce,
                              const Image* environment = nullptr, const char* method = "ssdo") {
    OperatorInputs in;
    in.displayWindow = Box2i{0, 0, kW, kH};
    in.dataWindow = s.buf.data;
    in.depth = s.buf.depth.view();
    in.normal = s.buf.normal.view();
    in.depthKind = c.depth;
    in.normalSpace = c.normals;
    in.camera = c.orthographic ? Camera::orthographic(s.orthoWidth, kW, kH, 1.0)
                               : Camera::perspectiveFromFov(s.fovDeg * 3.14159265358979323846 / 180, kW, kH, 1.0);
    in.camera.cameraToWorld = s.cam.cameraToWorld;
    in.camera.hasPose = true;
    const Image radiance = displayRgb(s.beautyClip, s.buf.data);
    if (bounce) in.radiance = radiance.view();
    in.environment = environment;
    Settings st;
    st.method = method;
    st.radius = (float)c.radius;
    st.directions = c.directions, st.steps = c.steps;
    st.weighting = c.cosine ? Weighting::Cosine : Weighting::Uniform;
    st.falloff = c.noFalloff ? Falloff::None : Falloff::Linear;
    st.blur = c.blur;
    st.device = "cpu";
    st.ssdoSamples = o.samples, st.interleave = o.interleave;
    for (int k = 0; k < 3; ++k) st.skyRadiance[k] = o.sky[k];
    st.envRotationDeg = (float)o.envRotation, st.envIntensity = (float)o.envIntensity, st.zUp = o.zUp;
    st.bounce = bounce;
    st.maxRadiusPixels = (float)c.maxScreenRadius;
    return runOperator(in, st);
}

// What the plugin's RGB should be at display (dx, dy): the CLI's formulas (frame_job.cpp).
struct Expected {
    int output;
    bool timesAlbedo;
};
void expectSsdoPixels(const HostImage& frame, const Expected& e, const OperatorOutputs& ref, const Scene& s,
                      const HostImage& albedo, const std::string& what) {
    const Box2i data = s.buf.data;
    ASSERT_EQ(frame.bounds.x1, data.x0) << what;
    ASSERT_EQ(frame.width(), data.width()) << what;
    ASSERT_EQ(frame.height(), data.height()) << what;
    const float k = (float)(1.0 / M_PI);
    int differing = 0;
    std::string first;
    for (int dy = data.y0; dy < data.y1; ++dy)
        for (int dx = data.x0; dx < data.x1; ++dx) {
            const int oy = kH - 1 - dy;
            const float* p = frame.at(dx, oy);
            const float* alb = albedo.at(dx, oy);
            static constexpr float kNoDo[3] = {0.0f, 0.0f, 0.0f};  // hbao's bounce has no DO
            const float* d = ref.directional.empty() ? kNoDo : ref.directional.at(dx - data.x0, dy - data.y0);
            const float* g = e.output == kOutDo ? nullptr : ref.indirect.at(dx - data.x0, dy - data.y0);
            float want[4];
            for (int c = 0; c < 3; ++c) {
                if (e.output == kOutRelit) {
                    want[c] = alb[c] * (d[c] + g[c]) * k;
                } else {
                    const float E = e.output == kOutDo ? d[c] : g[c];
                    want[c] = e.timesAlbedo ? E * (alb[c] * k) : E;
                }
            }
            want[3] = e.output == kOutRelit ? s.beautyClip.at(dx, oy)[3] : 1.0f;
            if (std::memcmp(p, want, sizeof want) != 0 && differing++ == 0)
                first = "at display (" + std::to_string(dx) + "," + std::to_string(dy) + "): plugin " + num(p[0]) + "," +
                        num(p[1]) + "," + num(p[2]) + "," + num(p[3]) + " operator " + num(want[0]) + "," +
                        num(want[1]) + "," + num(want[2]) + "," + num(want[3]);
        }
    EXPECT_EQ(differing, 0) << what << ": " << differing << " pixels differ, first " << first;
}

// The node loaded, described and instantiated on these clips (each test sets its parameters).
Loaded instantiateSsdo(const HostImage& depth, const HostImage& normal, const HostImage& source,
                       const HostImage& albedo) {
    Loaded l;
    l.host = std::make_unique<Host>(kBundle);
    EXPECT_EQ(l.host->error(), "");
    if (!l.host->plugin()) return l;
    EXPECT_EQ(l.host->load(), kOfxStatOK);
    EXPECT_EQ(l.host->describe(), kOfxStatOK);
    ProjectSetup project;
    project.width = kW, project.height = kH;
    OfxStatus st = kOfxStatFailed;
    l.inst = l.host->createInstance(
        project, {{"Depth", &depth}, {"Normal", &normal}, {"Source", &source}, {"Albedo", &albedo}}, &st);
    EXPECT_EQ(st, kOfxStatOK);
    return l;
}

// The bounce is really there (a test would be weak on an all-black GI).
void expectSomeGi(const OperatorOutputs& ref) {
    ASSERT_FALSE(ref.indirect.empty());
    double giSum = 0;
    for (float v : ref.indirect.pixels) giSum += v;
    EXPECT_GT(giSum, 0.0);
}

// The node on the scene's clips, set to the config and the SSDO options.
Loaded nodeOn(const Config& c, const Scene& s, const HostImage& albedo, const SsdoOptions& o) {
    Loaded l = instantiateSsdo(s.depthClip, s.normalClip, s.beautyClip, albedo);
    if (l.inst) {
        applyConfig(*l.inst, c, s);
        applySsdo(*l.inst, o);
    }
    return l;
}

class OfxSsdoMatchesOperator : public ::testing::TestWithParam<Config> {};

TEST_P(OfxSsdoMatchesOperator, DoGiRelitWholeFrameAndTiles) {
    const Config c = GetParam();
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    SsdoOptions o;
    o.sky[0] = 0.8f, o.sky[1] = 1.0f, o.sky[2] = 1.3f;
    const OperatorOutputs ref = ssdoReference(c, s, o, true);
    expectSomeGi(ref);
    Loaded l = nodeOn(c, s, albedo, o);
    ASSERT_TRUE(l.inst);
    for (Expected e : {Expected{kOutDo, false}, Expected{kOutGi, false}, Expected{kOutRelit, false},
                       Expected{kOutDo, true}, Expected{kOutGi, true}}) {
        const std::string what = std::string(e.output == kOutDo ? "DO" : e.output == kOutGi ? "GI" : "relit") +
                                 (e.timesAlbedo ? " x albedo" : "");
        ASSERT_EQ(l.inst->setInt("output", e.output), kOfxStatOK);
        ASSERT_EQ(l.inst->setInt("timesAlbedo", e.timesAlbedo ? 1 : 0), kOfxStatOK);
        std::vector<std::string> problems;
        const HostImage whole = l.inst->renderFrame(0, 0, 1, problems);
        EXPECT_EQ(joined(problems), "") << what;
        expectSsdoPixels(whole, e, ref, s, albedo, what + ", whole frame");
        for (auto [tw, th, threads] : {std::tuple{32, 32, 1}, std::tuple{17, 11, 3}}) {
            problems.clear();
            const HostImage tiled = l.inst->renderFrame(tw, th, threads, problems);
            EXPECT_EQ(joined(problems), "") << what << " " << tw << "x" << th;
            EXPECT_TRUE(sameBits(tiled, whole)) << what << ": tiles " << tw << "x" << th << " differ from the whole frame";
        }
    }
    EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
}

INSTANTIATE_TEST_SUITE_P(Configs, OfxSsdoMatchesOperator,
                         ::testing::Values(cfg("perspective"),
                                           [] {
                                               Config c = cfg("orthographic_overscan_camera_normals");
                                               c.orthographic = true, c.overscan = 6, c.radius = 1.5;
                                               c.normals = NormalSpace::Camera;
                                               return c;
                                           }()),
                         [](const ::testing::TestParamInfo<Config>& i) { return i.param.name; });

// GI Method = hbao: the GI and Relit outputs are hbao's bounce of Source (--method hbao --bounce
// --bounce-source beauty), relit = albedo GI / pi, whole frame and tiled alike; DO stays SSDO's.
TEST(OfxSsdo, GiMethodHbaoGivesTheHorizonBounce) {
    const Config c = cfg("perspective");
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    const SsdoOptions o;
    const OperatorOutputs ref = ssdoReference(c, s, o, true, nullptr, "hbao");
    ASSERT_TRUE(ref.directional.empty());
    expectSomeGi(ref);
    Loaded l = nodeOn(c, s, albedo, o);
    ASSERT_TRUE(l.inst);
    std::vector<std::string> problems;
    ASSERT_EQ(l.inst->setInt("output", kOutDo), kOfxStatOK);
    const HostImage ssdoDo = l.inst->renderFrame(0, 0, 1, problems);
    ASSERT_EQ(l.inst->setInt("giMethod", 0), kOfxStatOK);  // hbao: the first GI writer in the table
    const HostImage doWithHbaoGi = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_TRUE(sameBits(doWithHbaoGi, ssdoDo)) << "DO must stay SSDO's";
    for (Expected e : {Expected{kOutGi, false}, Expected{kOutRelit, false}, Expected{kOutGi, true}}) {
        const std::string what = std::string(e.output == kOutGi ? "hbao GI" : "hbao relit") + (e.timesAlbedo ? " x albedo" : "");
        ASSERT_EQ(l.inst->setInt("output", e.output), kOfxStatOK);
        ASSERT_EQ(l.inst->setInt("timesAlbedo", e.timesAlbedo ? 1 : 0), kOfxStatOK);
        const HostImage whole = l.inst->renderFrame(0, 0, 1, problems);
        expectSsdoPixels(whole, e, ref, s, albedo, what + ", whole frame");
        const HostImage tiled = l.inst->renderFrame(17, 11, 3, problems);
        EXPECT_TRUE(sameBits(tiled, whole)) << what << ": tiles differ from the whole frame";
    }
    EXPECT_EQ(joined(problems), "");
    EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
}

TEST(OfxSsdo, RegionsOfInterestFollowWhatEachOutputReads) {
    Config c;
    c.radius = 3.0, c.maxScreenRadius = 7.5;
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    Loaded l = instantiateSsdo(s.depthClip, s.normalClip, s.beautyClip, albedo);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    const OfxRectD window{40, 20, 56, 36};
    const int apron = 8 + 2 + 2;  // cap, texel snapping, the interleave (2) blur
    auto same = [](const OfxRectD& a, const OfxRectD& b) {
        return a.x1 == b.x1 && a.y1 == b.y1 && a.x2 == b.x2 && a.y2 == b.y2;
    };
    auto empty = [](const OfxRectD& r) { return r.x2 - r.x1 <= 0 || r.y2 - r.y1 <= 0; };
    const OfxRectD grown{window.x1 - apron, window.y1 - apron, window.x2 + apron, window.y2 + apron};
    std::map<std::string, OfxRectD> rois;

    ASSERT_EQ(l.inst->setInt("output", kOutDo), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_TRUE(same(rois["Depth"], grown));
    EXPECT_TRUE(empty(rois["Source"]));  // no bounce: no radiance read
    EXPECT_TRUE(empty(rois["Albedo"]));
    EXPECT_TRUE(empty(rois["Position"]));
    ASSERT_EQ(l.inst->setInt("timesAlbedo", 1), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_TRUE(same(rois["Albedo"], window));  // the receiver's albedo, under the window
    ASSERT_EQ(l.inst->setInt("timesAlbedo", 0), kOfxStatOK);

    // The bounce's blur is SSDO_GI_BLUR_SCALE times the interleave's (kernels/kernel_params.glsl).
    const int giApron = apron + (glsl::SSDO_GI_BLUR_SCALE - 1) * 2;
    const OfxRectD grownGi{window.x1 - giApron, window.y1 - giApron, window.x2 + giApron, window.y2 + giApron};
    for (int out : {kOutGi, kOutRelit}) {
        ASSERT_EQ(l.inst->setInt("output", out), kOfxStatOK);
        ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
        EXPECT_TRUE(same(rois["Depth"], grownGi)) << out;
        EXPECT_TRUE(same(rois["Source"], grownGi)) << out;  // the senders, within the apron
        EXPECT_EQ(empty(rois["Albedo"]), out == kOutGi) << out;
        if (out == kOutRelit) {
            EXPECT_TRUE(same(rois["Albedo"], window));
        }
    }
    // Strength does not switch the SSDO outputs off (nor make them an identity).
    ASSERT_EQ(l.inst->setDouble("strength", 0.0), kOfxStatOK);
    std::string clip;
    EXPECT_EQ(l.inst->isIdentity({0, 0, kW, kH}, clip), kOfxStatReplyDefault);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_TRUE(same(rois["Depth"], grownGi));

    // The interleave sets the blur, hence the apron (relit: the bounce's, scaled); an explicit
    // Blur replaces it.
    ASSERT_EQ(l.inst->setInt("interleave", 4), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x2, window.x2 + 8 + 2 + glsl::SSDO_GI_BLUR_SCALE * 4);
    ASSERT_EQ(l.inst->setInt("blur", 1), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x2, window.x2 + 8 + 2 + glsl::SSDO_GI_BLUR_SCALE * 1);

    // Relit without an Albedo clip is an error the host shows.
    Loaded noAlbedo = instantiate(s, true);
    ASSERT_TRUE(noAlbedo.inst);
    applyConfig(*noAlbedo.inst, c, s);
    ASSERT_EQ(noAlbedo.inst->setInt("output", kOutRelit), kOfxStatOK);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(noAlbedo.inst->render({0, 0, 16, 16}, frame), kOfxStatFailed);
    const auto msgs = noAlbedo.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("Albedo"), std::string::npos) << msgs[0];
    EXPECT_EQ(noAlbedo.host->liveImages(), 0);
}

// The furnace: an open plane under a constant sky receives the sky's irradiance, pi x sky,
// at every pixel, and no bounce (nothing blocks). Relit is then albedo x sky.
TEST(OfxSsdo, FurnaceOpenPlaneUnderWhiteSkyGivesPi) {
    const OfxRectI b{0, 0, kW, kH};
    HostImage depth(b, 1), normal(b, 4), beauty(b, 4), albedo(b, 4);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            depth.at(x, y)[0] = 5.0f;
            float* n = normal.at(x, y);
            n[0] = 0, n[1] = 0, n[2] = 1, n[3] = 1;  // camera space: facing the (orthographic) camera
            float* bt = beauty.at(x, y);
            bt[0] = bt[1] = bt[2] = 0.7f, bt[3] = 1.0f;
            float* a = albedo.at(x, y);
            a[0] = 0.5f, a[1] = 0.25f, a[2] = 1.0f, a[3] = 1.0f;
        }
    Loaded l = instantiateSsdo(depth, normal, beauty, albedo);
    ASSERT_TRUE(l.inst);
    Instance& inst = *l.inst;
    EXPECT_EQ(inst.setInt("projection", 1), kOfxStatOK);
    EXPECT_EQ(inst.setDouble("orthoWidth", 10.0), kOfxStatOK);
    EXPECT_EQ(inst.setInt("normalSpace", 1), kOfxStatOK);
    EXPECT_EQ(inst.setDouble("radius", 0.5), kOfxStatOK);
    EXPECT_EQ(inst.setInt("device", 0), kOfxStatOK);
    const double pi = M_PI;
    std::vector<std::string> problems;
    for (auto [r, g, bl] : {std::tuple{1.0, 1.0, 1.0}, std::tuple{0.5, 1.0, 2.0}}) {
        ASSERT_EQ(inst.setRGB("skyColour", r, g, bl), kOfxStatOK);
        const double sky[3] = {r, g, bl};
        ASSERT_EQ(inst.setInt("output", kOutDo), kOfxStatOK);
        const HostImage dO = inst.renderFrame(32, 32, 2, problems);
        ASSERT_EQ(inst.setInt("output", kOutGi), kOfxStatOK);
        const HostImage gi = inst.renderFrame(0, 0, 1, problems);
        ASSERT_EQ(inst.setInt("output", kOutRelit), kOfxStatOK);
        const HostImage relit = inst.renderFrame(17, 11, 2, problems);
        EXPECT_EQ(joined(problems), "");
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x)
                for (int c = 0; c < 3; ++c) {
                    ASSERT_NEAR(dO.at(x, y)[c], pi * sky[c], 1e-5 * pi * sky[c]) << x << "," << y;
                    ASSERT_EQ(gi.at(x, y)[c], 0.0f) << x << "," << y;
                    ASSERT_NEAR(relit.at(x, y)[c], albedo.at(x, y)[c] * sky[c], 1e-5) << x << "," << y;
                }
        EXPECT_EQ(dO.at(5, 5)[3], 1.0f);
    }
    EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
}

// An environment map read from a file equals the operator given the same pixels; the
// per-instance cache sees a changed file.
// A map turned 40 degrees about a Z up axis, at 1.5x.
SsdoOptions rotatedZUpMap() {
    SsdoOptions o;
    o.envRotation = 40, o.envIntensity = 1.5, o.zUp = true;
    return o;
}

// The SSDO node over the scene with `c` and `o`, lit by the map at `path`, outputting DO.
Loaded ssdoNodeWithMap(const Config& c, const Scene& s, const HostImage& albedo, const SsdoOptions& o,
                       const std::string& path) {
    Loaded l = nodeOn(c, s, albedo, o);
    if (!l.inst) return l;
    EXPECT_EQ(l.inst->setString("envMap", path), kOfxStatOK);
    EXPECT_EQ(l.inst->setInt("output", kOutDo), kOfxStatOK);
    return l;
}

// One map lights a shot alike in the node, the CLI and Python: all read it through plugin/io,
// which converts an sRGB-encoded PNG to the working space (a linear read would differ by up to
// ~4x), and the same settings give the same DO in each host.
TEST(OfxSsdo, EnvironmentMapLightsTheNodeAsTheCliAndPython) {
    const fs::path dir = testDir();
    const std::string png = (dir / "env.png").string();
    {
        const int w = 32, h = 16;
        std::vector<unsigned char> px((size_t)w * h * 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                for (int c = 0; c < 3; ++c) px[((size_t)y * w + x) * 3 + c] = (unsigned char)(40 + 5 * x + 7 * y + 30 * c);
        auto out = OIIO::ImageOutput::create(png);
        ASSERT_TRUE(out && out->open(png, OIIO::ImageSpec(w, h, 3, OIIO::TypeDesc::UINT8)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
        out->close();
    }
    Config c;
    c.method = 1;
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    const SsdoOptions o = rotatedZUpMap();
    Loaded l = ssdoNodeWithMap(c, s, albedo, o, png);
    ASSERT_TRUE(l.inst);
    std::vector<std::string> problems;
    const HostImage node = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_EQ(joined(problems), "");
    const std::vector<std::string> flags = {"--env", png, "--samples", "64", "--interleave", "2", "--env-rotate", "40",
                                            "--env-intensity", "1.5", "--up", "z"};
    const std::vector<std::string> doChannels = {"obscura.DO.R", "obscura.DO.G", "obscura.DO.B"};
    const std::vector<float> cli = runCli(c, s, dir, flags, doChannels);
    const std::vector<float> python = runCli(c, s, dir, flags, doChannels, true);
    EXPECT_TRUE(python == cli) << "Python's process() and the CLI differ on the same settings";
    const Box2i data = s.buf.data;
    ASSERT_EQ(cli.size(), (size_t)data.width() * data.height() * 3);
    double worst = 0, mean = 0;
    for (int dy = data.y0; dy < data.y1; ++dy)
        for (int dx = data.x0; dx < data.x1; ++dx)
            for (int k = 0; k < 3; ++k) {
                const float want = cli[(((size_t)(dy - data.y0) * data.width()) + (dx - data.x0)) * 3 + k];
                worst = std::max(worst, (double)std::fabs(node.at(dx, kH - 1 - dy)[k] - want));
                mean += want;
            }
    mean /= (double)cli.size();
    EXPECT_GT(mean, 0.05);  // the map lights the scene
    EXPECT_LE(worst, 1e-5 * std::max(1.0, mean)) << "mean DO " << mean;
}

TEST(OfxSsdo, EnvironmentMapFromFileMatchesOperator) {
    const fs::path dir = testDir();
    const Config c;
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    auto writeEnv = [&](int w, int h, float scale) {
        Image env(w, h, 3);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                float* p = env.at(x, y);
                p[0] = scale * (0.2f + (float)x / w), p[1] = scale * (1.5f - (float)y / h), p[2] = scale * 0.3f;
            }
        fixtures::FixturePart part;
        part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(w - 1, h - 1));
        for (int k = 0; k < 3; ++k) {
            fixtures::FixtureChannel ch;
            ch.name = std::string(1, "RGB"[k]);
            ch.type = Imf::FLOAT;
            ch.value = [&env, k](int x, int y) { return env.at(x, y)[k]; };
            part.channels.push_back(ch);
        }
        fixtures::writeFixture((dir / "env.exr").string(), {part});
        return env;
    };
    const Image env1 = writeEnv(32, 16, 1.0f);
    const SsdoOptions o = rotatedZUpMap();
    Loaded l = ssdoNodeWithMap(c, s, albedo, o, (dir / "env.exr").string());
    ASSERT_TRUE(l.inst);
    std::vector<std::string> problems;
    const HostImage a = l.inst->renderFrame(0, 0, 1, problems);
    expectSsdoPixels(a, {kOutDo, false}, ssdoReference(c, s, o, false, &env1), s, albedo, "env 1");
    const HostImage aTiled = l.inst->renderFrame(32, 32, 2, problems);
    EXPECT_TRUE(sameBits(a, aTiled));

    const Image env2 = writeEnv(16, 8, 3.0f);  // another size: the cache key changes for sure
    const HostImage b = l.inst->renderFrame(0, 0, 1, problems);
    expectSsdoPixels(b, {kOutDo, false}, ssdoReference(c, s, o, false, &env2), s, albedo, "env 2");
    EXPECT_EQ(joined(problems), "");
    EXPECT_EQ(l.host->messages(), std::vector<std::string>{});

    ASSERT_EQ(l.inst->setString("envMap", (dir / "missing.exr").string()), kOfxStatOK);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame), kOfxStatFailed);
    EXPECT_EQ(l.host->liveImages(), 0);

    // A Radiance header claiming 20000 x 20000 pixels (and no pixels) is refused before the
    // 4.8 GB it claims are allocated.
    std::ofstream(dir / "huge_env.hdr") << "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 20000\n";
    ASSERT_EQ(l.inst->setString("envMap", (dir / "huge_env.hdr").string()), kOfxStatOK);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame), kOfxStatFailed);
    const std::vector<std::string> msgs = l.host->messages();
    ASSERT_FALSE(msgs.empty());
    EXPECT_NE(msgs.back().find("huge_env.hdr': image window [0,0 - 19999,19999] holds 20000 x 20000 pixels"),
              std::string::npos)
        << msgs.back();
    EXPECT_EQ(l.host->liveImages(), 0);
}

} // namespace

// A Source clip with NaN pixels: the bounce takes them as 0, so GI stays finite, and the node says
// so with a persistent warning (not a failure: the frame is written), until a render whose Source
// is clean. Outputs that read no Source say nothing.
TEST(OfxSsdo, NanInTheSourceWarnsOnTheNodeUntilItIsClean) {
    const Config c = cfg("perspective");
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    HostImage source = s.beautyClip;
    Loaded l = instantiateSsdo(s.depthClip, s.normalClip, source, albedo);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    applySsdo(*l.inst, SsdoOptions{});
    const std::string warning = "OfxMessageWarning: obscura: the Source clip held NaN, infinite or huge (above 1e9) "
                                "values; the light takes them as 0 (black)";
    for (int y = 10; y < 20; ++y)
        for (int x = 10; x < 20; ++x) source.at(source.bounds.x1 + x, source.bounds.y1 + y)[1] = NAN;
    std::vector<std::string> problems;
    ASSERT_EQ(l.inst->setInt("output", kOutDo), kOfxStatOK);
    l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_EQ(l.host->persistentMessage(), "") << "DO reads no Source";
    ASSERT_EQ(l.inst->setInt("output", kOutGi), kOfxStatOK);
    const HostImage gi = l.inst->renderFrame(17, 11, 3, problems);
    EXPECT_EQ(l.host->persistentMessage(), warning);
    long long nonFinite = 0;
    for (float v : gi.pixels) nonFinite += std::isfinite(v) ? 0 : 1;
    EXPECT_EQ(nonFinite, 0);
    std::copy(s.beautyClip.pixels.begin(), s.beautyClip.pixels.end(), source.pixels.begin());
    l.inst->renderFrame(17, 11, 3, problems);
    EXPECT_EQ(l.host->persistentMessage(), "");
    EXPECT_EQ(joined(problems), "");
    // Posted once when it appeared and cleared once, however many tiles met it.
    const std::vector<std::string> posted = l.host->messages();
    EXPECT_EQ(std::count(posted.begin(), posted.end(), "persistent " + warning), 1) << joined(posted);
}
