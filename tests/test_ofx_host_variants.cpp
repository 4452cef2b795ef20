// The OpenFX plugin under what the specification lets a host do differently from our test host's
// defaults: make the Output Alpha when no input is RGBA, answer kOfxStatFailed for an image it has
// none of, give the clips another pixel aspect ratio than the project's, offer only version 1 of
// the message suite. And the parameter page as the specification defines one.
#include "ofx_host/ofx_host.h"
#include "support/ofx_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <thread>
#include <vector>

using namespace obscura;
using namespace obscura::ofxhost;
using namespace obscura::test;

namespace {

constexpr int kOutBeautyTimesAo = 1, kOutDo = 2, kOutGi = 3;

// Two instances of one scene, set up alike, render the same pixels and post no message: `a` as one
// tile on this thread, `b` in tileW x tileH tiles on two threads.
void expectSameRender(Instance& a, Instance& b, const Config& c, const Scene& s, int tileW, int tileH) {
    applyConfig(a, c, s);
    applyConfig(b, c, s);
    std::vector<std::string> pa, pb;
    const HostImage expected = a.renderFrame(0, 0, 1, pa);
    const HostImage got = b.renderFrame(tileW, tileH, 2, pb);
    EXPECT_EQ(joined(pa) + joined(pb), "");
    EXPECT_LE(maxAbsDiff(expected, got), 0.0f);
}

bool enabled(Instance& inst, const char* param) {
    return inst.effect().params.find(param)->props.integer(kOfxParamPropEnabled, 0, 1) != 0;
}

// The general context's default Output is Alpha when no connected input is RGBA, as here (an
// Alpha depth alone). DO is colour: the plugin asks for RGBA, and keeps Depth Alpha.
TEST(OfxHostVariants, ColourOutputsAskForRgbaOverAnAlphaDefault) {
    Config c;
    c.normals = NormalSpace::Depth;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH, 1.0, 1.0, /*outputComponents*/ 1), {"Depth"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    ASSERT_EQ(l.inst->setInt("output", kOutDo), kOfxStatOK);  // a slave of the clip preferences
    EXPECT_EQ(l.inst->outputComponents, 4);
    PropertySet prefs;
    ASSERT_EQ(l.inst->clipPreferences(prefs), kOfxStatOK);
    EXPECT_EQ(prefs.string("OfxImageClipPropComponents_Depth"), kOfxImageComponentAlpha);
    std::vector<std::string> problems;
    const HostImage frame = l.inst->renderFrame(0, 0, 1, problems);
    EXPECT_EQ(joined(problems), "");
    std::set<float> red;
    for (size_t i = 0; i < frame.pixels.size(); i += 4) red.insert(frame.pixels[i]);
    EXPECT_GT(red.size(), 10u) << "DO is an image, not a constant";
    // AO may stay Alpha: the plugin leaves that Output to the host.
    ASSERT_EQ(l.inst->setInt("output", 0), kOfxStatOK);
    EXPECT_EQ(l.inst->outputComponents, 4);  // the host's last answer stands until it changes it
}

// A host may answer a fetch with kOfxStatFailed where it has no image: the plugin goes on as if the
// image were black and transparent. A Source covering the left half only, in tiles: the right half
// is black, the left half the same as from a host that hands over empty images.
TEST(OfxHostVariants, AnImageTheHostHasNoneOfIsBlack) {
    const Config c;
    Scene s = makeScene(c);
    HostImage left(OfxRectI{s.beautyClip.bounds.x1, s.beautyClip.bounds.y1, kW / 2, s.beautyClip.bounds.y2}, 4);
    for (int y = left.bounds.y1; y < left.bounds.y2; ++y)
        for (int x = left.bounds.x1; x < left.bounds.x2; ++x) std::copy_n(s.beautyClip.at(x, y), 4, left.at(x, y));
    s.beautyClip = left;
    std::vector<HostImage> frames;
    for (const bool fail : {false, true}) {
        Loaded l = instantiate(s, true);
        ASSERT_TRUE(l.inst);
        l.host->failEmptyFetch = fail;
        applyConfig(*l.inst, c, s);
        ASSERT_EQ(l.inst->setInt("output", kOutBeautyTimesAo), kOfxStatOK);
        std::vector<std::string> problems;
        frames.push_back(l.inst->renderFrame(16, 16, 2, problems));
        EXPECT_EQ(joined(problems), "") << (fail ? "failing host" : "empty images");
        EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
    }
    EXPECT_LE(maxAbsDiff(frames[0], frames[1]), 0.0f);
    EXPECT_EQ(frames[1].at(kW - 1, kH / 2)[0], 0.0f);
    EXPECT_GT(frames[1].at(2, kH / 2)[0], 0.0f);
}

// The clips' pixel aspect ratio (2) maps canonical to pixel coordinates, not the project's (1):
// HostSupport gives the clips the inputs' PAR. The same pixels as in a PAR-2 project, and every
// fetch inside its region of interest.
TEST(OfxHostVariants, ClipParNotProjectPar) {
    Config c;
    c.maxScreenRadius = 12;
    const Scene s = makeScene(c);
    ProjectSetup anamorphic = project(kW, kH, 2.0);
    Loaded same = instantiateIn(s, anamorphic, {"Depth", "Normal"});
    anamorphic.projectPar = 1.0;
    Loaded square = instantiateIn(s, anamorphic, {"Depth", "Normal"});
    ASSERT_TRUE(same.inst && square.inst);
    expectSameRender(*same.inst, *square.inst, c, s, 20, 16);
}

// A Depth clip whose region of definition the host flags infinite (a generator's, ofxCore.h's
// kOfxFlagInfiniteMin / Max) is read over the project's frame: the same pixels as its finite
// region gives, at any pixel aspect and with the automatic cap (the flags overflowed pixel
// coordinates: a black frame at PAR 0.9, a 1-pixel cap at 0).
TEST(OfxHostVariants, AnInfiniteDepthRegionIsTheProjectsFrame) {
    for (const double par : {1.0, 0.9}) {
        for (const double cap : {256.0, 0.0}) {
            SCOPED_TRACE("par " + std::to_string(par) + ", cap " + std::to_string(cap));
            Config c;
            c.maxScreenRadius = cap;
            const Scene s = makeScene(c);
            Loaded finite = instantiateIn(s, project(kW, kH, par), {"Depth", "Normal"});
            Loaded infinite = instantiateIn(s, project(kW, kH, par), {"Depth", "Normal"});
            ASSERT_TRUE(finite.inst && infinite.inst);
            infinite.inst->effect().clip("Depth")->props.setInt("HostInfiniteRoD", {1});
            expectSameRender(*finite.inst, *infinite.inst, c, s, 24, 16);
            OfxRectD a{}, b{};
            ASSERT_EQ(finite.inst->regionOfDefinition(a), kOfxStatOK);
            ASSERT_EQ(infinite.inst->regionOfDefinition(b), kOfxStatOK);
            EXPECT_EQ(std::vector<double>({a.x1, a.y1, a.x2, a.y2}), std::vector<double>({b.x1, b.y1, b.x2, b.y2}));
        }
    }
}

// A host call that fails inside an action (here the Depth clip's region, answered ErrUnknown)
// makes the action answer Failed, a status ofxImageEffect.h allows it, with a message on the node;
// the host's own status went back as the action's, silently.
TEST(OfxHostVariants, AFailingHostCallIsAFailedActionWithAMessage) {
    Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    l.inst->effect().clip("Depth")->props.setInt("HostRoDStatus", {kOfxStatErrUnknown});
    std::map<std::string, OfxRectD> rois;
    EXPECT_EQ(l.inst->regionsOfInterest({0, 0, 16, 16}, rois), kOfxStatFailed);
    const std::vector<std::string> shown = l.host->messages();
    ASSERT_FALSE(shown.empty());
    EXPECT_NE(shown.back().find("the host answered status " + std::to_string(kOfxStatErrUnknown)), std::string::npos)
        << shown.back();
}

// A failure is one error on the node however many tiles and actions meet it, persistent where the
// host has version 2 of the message suite, and cleared by the next render that succeeds.
TEST(OfxHostVariants, AnErrorIsShownOnceAndClearedByASuccess) {
    const Config c;
    const Scene s = makeScene(c);
    for (const bool v2 : {true, false}) {
        Loaded l = instantiate(s);
        ASSERT_TRUE(l.inst);
        l.host->messageSuiteV2 = v2;
        ASSERT_EQ(l.host->load(), kOfxStatOK);  // fetches the suites again
        applyConfig(*l.inst, c, s);
        ASSERT_EQ(l.inst->setString("cameraToWorld", "1,2,3"), kOfxStatOK);
        std::vector<std::string> problems;
        l.inst->renderFrame(kW / 2, kH / 2, 2, problems);
        const std::vector<std::string> msgs = l.host->messages();
        ASSERT_EQ(msgs.size(), 1u) << joined(msgs);
        EXPECT_EQ(msgs[0].rfind(v2 ? "persistent OfxMessageError" : "OfxMessageError", 0), 0u) << msgs[0];
        EXPECT_EQ(l.host->persistentMessage().empty(), !v2);
        applyConfig(*l.inst, c, s);
        problems.clear();
        l.inst->renderFrame(0, 0, 1, problems);
        EXPECT_EQ(joined(problems), "");
        EXPECT_EQ(l.host->persistentMessage(), "");
        EXPECT_EQ(l.host->messages().size(), 1u);
        // The same failure after a success is shown again.
        ASSERT_EQ(l.inst->setString("cameraToWorld", "1,2,3"), kOfxStatOK);
        l.inst->renderFrame(0, 0, 1, problems);
        EXPECT_EQ(l.host->messages().size(), 2u);
        EXPECT_EQ(l.host->persistentMessage().empty(), !v2);
    }
}

// GI and Relit run the GI Method: with hbao there, hbao's controls are live and SSDO's greyed out.
TEST(OfxHostVariants, TheGiMethodsControlsAreTheLiveOnes) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s, true);
    ASSERT_TRUE(l.inst);
    ASSERT_EQ(l.inst->setInt("output", kOutGi), kOfxStatOK);
    const std::vector<const char*> gi = {"hbao", "ssdo"};  // the GI Method's choices, in the method table's order
    for (int index = 0; index < 2; ++index) {
        ASSERT_EQ(l.inst->setInt("giMethod", index), kOfxStatOK);
        const bool hbao = std::string(gi[index]) == "hbao";
        EXPECT_EQ(enabled(*l.inst, "thickness"), hbao) << gi[index];
        EXPECT_EQ(enabled(*l.inst, "border"), hbao) << gi[index];
        EXPECT_EQ(enabled(*l.inst, "samples"), !hbao) << gi[index];
        EXPECT_EQ(enabled(*l.inst, "envMap"), !hbao) << gi[index];
        EXPECT_TRUE(enabled(*l.inst, "giMethod"));
        EXPECT_FALSE(enabled(*l.inst, "method"));
    }
    ASSERT_EQ(l.inst->setInt("output", 0), kOfxStatOK);
    EXPECT_FALSE(enabled(*l.inst, "giMethod"));
    EXPECT_TRUE(enabled(*l.inst, "method"));
}

// A page's children are parameters, never groups or pages (ofxParam.h, kOfxParamPropPageChild),
// and every control is on the page.
TEST(OfxHostVariants, ThePageHoldsEveryControlAndNoGroup) {
    Host host(kBundle);
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    std::vector<std::string> children, controls;
    for (const auto& p : host.descriptor().params.params) {
        if (p->type == kOfxParamTypePage) children = p->props.strings(kOfxParamPropPageChild);
        else if (p->type != kOfxParamTypeGroup) controls.push_back(p->name);
    }
    EXPECT_EQ(children, controls);
}

// The method table's parameters read as controls: a label, and the numbers the node stores for
// the table's words. A thickness below 0 is auto's, as -1 is.
TEST(OfxHostVariants, MethodParametersSayWhatTheirNumbersMean) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiate(s);
    ASSERT_TRUE(l.inst);
    const PropertySet& thickness = l.host->descriptor().params.find("thickness")->props;
    EXPECT_EQ(thickness.string(kOfxPropLabel), "Thickness");
    EXPECT_NE(thickness.string(kOfxParamPropHint).find("-1 = auto, 1e+09 = inf"), std::string::npos);
    EXPECT_LE(thickness.doubles(kOfxParamPropDisplayMin)[0], -1.0);
    EXPECT_EQ(l.host->descriptor().params.find("ssao_samples")->props.string(kOfxPropLabel), "SSAO Samples");
    EXPECT_NE(l.host->descriptor().params.find("border")->props.string(kOfxParamPropHint).find("0 = open, 1 = clamp, 2 = tangent"),
              std::string::npos);
    applyConfig(*l.inst, c, s);
    std::vector<std::string> problems;
    const HostImage autoThickness = l.inst->renderFrame(0, 0, 1, problems);
    ASSERT_EQ(l.inst->setDouble("thickness", -0.5), kOfxStatOK);
    EXPECT_LE(maxAbsDiff(autoThickness, l.inst->renderFrame(0, 0, 1, problems)), 0.0f);
    EXPECT_EQ(joined(problems), "");
}

} // namespace

// A host aborts a render when the user moves on: the plugin asks after reading the inputs and
// between the operator's tiles (at most every 10 ms), on the thread the host rendered on, and
// returns at once with nothing written and no error shown. The frame takes long enough for the
// operator to ask: 128 x 64 samples a pixel, tens of milliseconds even on a fast machine.
TEST(OfxHostVariants, AnAbortStopsTheOperatorBetweenTiles) {
    Config c;
    c.directions = 128;
    c.steps = 64;
    c.radius = 4.0;
    const Scene s = makeScene(c);
    for (const int abortFrom : {0, 1, 2}) {  // never; after reading the inputs; inside the operator
        Loaded l = instantiate(s);
        ASSERT_TRUE(l.inst);
        l.host->abortFromCall = abortFrom;
        applyConfig(*l.inst, c, s);
        ASSERT_EQ(l.inst->setInt("threads", 1), kOfxStatOK);  // the host's thread takes every tile
        std::vector<std::string> problems;
        const HostImage frame = l.inst->renderFrame(0, 0, 1, problems);  // one tile, on this thread
        EXPECT_EQ(joined(problems), abortFrom ? "some output pixels were never written\n" : "");
        EXPECT_EQ(l.host->messages(), std::vector<std::string>{});
        EXPECT_EQ(l.host->abortThreads_, std::set<std::thread::id>{std::this_thread::get_id()});
        size_t written = 0;
        for (float v : frame.pixels) written += !std::isnan(v);
        EXPECT_EQ(written, abortFrom ? 0u : frame.pixels.size()) << "abort from call " << abortFrom;
        if (abortFrom == 0) EXPECT_GE(l.host->abortCalls_.load(), 2) << "asked only before the operator";
        else EXPECT_EQ(l.host->abortCalls_.load(), abortFrom) << "asked again after it said abort";
    }
}
