// Deep elements with no flat file (docs/deep.md): OpenEXR's flattening rules against their closed
// forms, a deep-only plane (AO = 1), three elements rendered apart whose merge changes the AO
// (a tree shadows the ball beside it only when merged), the per-element AO, and bad inputs.
#include "io/deep_merge.h"
#include "support/cli_runner.h"
#include "support/deep_elements.h"
#include "support/read_back.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

constexpr int W = 160, H = 96;

void writeElement(const std::string& path, const DeepHit& hit, int width = W, int height = H) {
    writeDeepElement(path, hit, width, height);
}

// The ball, the tree and the ground written in `dir` (the ball's file named `ballName`).
std::array<std::string, 3> writeScene(const fs::path& dir, const std::string& ballName = "ball.exr") {
    const std::array<std::string, 3> paths = {(dir / ballName).string(), (dir / "tree.exr").string(),
                                              (dir / "ground.exr").string()};
    writeElement(paths[0], deepBall);
    writeElement(paths[1], deepTree);
    writeElement(paths[2], deepGround);
    return paths;
}

std::vector<std::string> aoArgs(const std::string& out) {
    return {"-o", out, "--fov-deg", "40", "--radius", "1", "--blur", "0", "--quality", "medium",
            "--falloff", "none", "--quiet"};
}

std::vector<std::string> plus(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

std::vector<bool> coverage(const DeepHit& hit, const std::function<bool(double x)>& side = nullptr) {
    return deepCoverage(hit, W, H, side);
}

void expectOneLineFailure(const CliResult& r, const std::string& file, const std::string& what, const fs::path& out) {
    EXPECT_EQ(r.exitCode, 1) << outcome(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("'" + file + "'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

} // namespace

// Over of two point samples, and a volume split by a point sample inside it: 1 - (1 - a)^x of
// its alpha in front of the point, the channels scaled with it (OpenEXR's rules).
TEST(DeepFlatten, OverAndVolumeSplitMatchClosedForms) {
    std::vector<float> scratch;
    float out[2];
    // Z, ZBack, R, A: half-covering red in front of opaque white.
    const float over[] = {1, 1, 0.5f, 0.5f, 2, 2, 1, 1};
    flattenSamples(over, 2, 4, 1, scratch, out);
    EXPECT_FLOAT_EQ(out[0], 1.0f);
    EXPECT_FLOAT_EQ(out[1], 1.0f);
    // A volume 1..3 of alpha 0.75 (R 0.75) with an opaque point (R 1) at 2: half the volume's
    // depth holds alpha 1 - 0.25^0.5 = 0.5 (R 0.5), then the point covers the rest.
    const float split[] = {1, 3, 0.75f, 0.75f, 2, 2, 1, 1};
    flattenSamples(split, 2, 4, 1, scratch, out);
    EXPECT_NEAR(out[0], 0.5f + 0.5f * 1.0f, 1e-6);
    EXPECT_NEAR(out[1], 1.0f, 1e-6);
    // Without the point, the whole volume: its own alpha and colour.
    flattenSamples(split, 1, 4, 1, scratch, out);
    EXPECT_NEAR(out[0], 0.75f, 1e-6);
}

// Two samples over one range combine: optical depths add (alpha 1 - 0.5 * 0.5 = 0.75), each
// channel in proportion to its share of them (here equal: R = G = 0.375).
TEST(DeepFlatten, SamplesOverOneRangeCombine) {
    std::vector<float> scratch;
    float out[3];
    const float same[] = {1, 2, 0.5f, 0.0f, 0.5f, 1, 2, 0.0f, 0.5f, 0.5f};  // Z, ZBack, R, G, A
    flattenSamples(same, 2, 5, 2, scratch, out);
    EXPECT_NEAR(out[0], 0.375f, 1e-6);
    EXPECT_NEAR(out[1], 0.375f, 1e-6);
    EXPECT_NEAR(out[2], 0.75f, 1e-6);
}

// A deep file alone: the output is its flattened image, its depth and the AO; a plane filling
// the frame gives AO = 1 (normals reconstructed from the depth).
TEST(DeepElements, DeepOnlyPlaneGivesAoOne) {
    const fs::path dir = testDir("deep_elements");
    const std::string in = (dir / "wall.exr").string(), out = (dir / "wall_ao.exr").string();
    // A plane through (0, 0, -5) facing the camera at 30 degrees, over the whole frame.
    const double n[3] = {0, std::sin(M_PI / 6), std::cos(M_PI / 6)};
    writeElement(in, [&](const double d[3]) {
        const float t = (float)(-5.0 * n[2] / (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]));
        return std::vector<DeepSample>{{t, t, 0.25f, 0.5f, 0.75f, 1.0f}};
    });
    const CliResult r = runObscura(plus({in}, aoArgs(out)));
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    const std::vector<float> ao = partChannel(out, 0, "obscura.AO.Y"), z = partChannel(out, 0, "Z");
    ASSERT_EQ(ao.size(), (size_t)W * H);
    for (size_t i = 0; i < ao.size(); ++i) {
        ASSERT_TRUE(std::isfinite(ao[i]) && ao[i] >= 0.0f && ao[i] <= 1.0f) << i;
        EXPECT_GE(ao[i], 0.999f) << "pixel " << i % W << "," << i / W;
    }
    for (const auto& [name, value] : {std::pair{"R", 0.25f}, {"G", 0.5f}, {"B", 0.75f}, {"A", 1.0f}})
        EXPECT_EQ(partChannel(out, 0, name)[W * H / 2], value) << name;
    EXPECT_GT(z[0], 0.0f);
    Imf::MultiPartInputFile written(out.c_str());
    EXPECT_EQ(written.header(0).channels().findChannel("ZBack"), nullptr) << "the depths flatten to the front's Z";
}

// A sample at Z = +inf is the sky (docs/conventions.md): its colour is flattened behind everything,
// as OpenEXR's flattening keeps it, and it is no surface and no skipped sample.
TEST(DeepElements, SkySamplesKeepTheirColour) {
    const fs::path dir = testDir("deep_elements");
    const std::string in = (dir / "sky.exr").string(), out = (dir / "sky_ao.exr").string();
    const float inf = std::numeric_limits<float>::infinity();
    writeElement(in, [&](const double d[3]) {
        if (d[1] > 0) return std::vector<DeepSample>{{inf, inf, 0.2f, 0.3f, 0.4f, 0.0f}};  // above the horizon
        const float t = (float)(-1.0 / d[1]);  // the ground, y = -1
        return std::vector<DeepSample>{{t, t, 0.5f, 0.5f, 0.5f, 1.0f}, {inf, inf, 0.2f, 0.3f, 0.4f, 0.0f}};
    });
    const std::string report = (dir / "sky.json").string();
    const CliResult r = runObscura(plus({in, "--report", report}, aoArgs(out)));
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    const std::vector<float> red = partChannel(out, 0, "R"), alpha = partChannel(out, 0, "A"),
                             z = partChannel(out, 0, "Z"), ao = partChannel(out, 0, "obscura.AO.Y");
    EXPECT_FLOAT_EQ(red[W / 2], 0.2f) << "the sky's colour, top row";
    EXPECT_FLOAT_EQ(alpha[W / 2], 0.0f);
    EXPECT_EQ(z[W / 2], inf);
    EXPECT_FLOAT_EQ(ao[W / 2], 1.0f);
    EXPECT_FLOAT_EQ(red[W * (H - 1) + W / 2], 0.5f) << "the ground, opaque, hides the sky";
    std::ifstream f(report);
    const nlohmann::json j = nlohmann::json::parse(f);
    EXPECT_EQ(j["warnings"].dump().find("skipped"), std::string::npos) << j["warnings"].dump();
}

// Three elements rendered apart: the tree darkens the side of the ball that faces it only when
// it is merged in; the far side, beyond the radius from the tree, keeps its AO. The order of the
// elements changes nothing.
TEST(DeepElements, MergedTreeShadowsTheBall) {
    const fs::path dir = testDir("deep_elements");
    const auto [b, t, g] = writeScene(dir);
    const std::string two = (dir / "two.exr").string(), three = (dir / "three.exr").string(),
                      other = (dir / "other.exr").string();
    for (const auto& [inputs, out] : {std::pair{std::vector<std::string>{b, g}, two},
                                      {std::vector<std::string>{b, t, g}, three}, {std::vector<std::string>{g, t, b}, other}}) {
        const CliResult r = runObscura(plus(inputs, aoArgs(out)));
        ASSERT_EQ(r.exitCode, 0) << outcome(r);
    }
    const std::vector<float> without = partChannel(two, 0, "obscura.AO.Y"), with = partChannel(three, 0, "obscura.AO.Y");
    for (float v : with) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    // The ball's visible pixels (the tree stands beside it, never in front): facing the tree, x > 0.2.
    const std::vector<bool> facing = coverage(deepBall, [](double x) { return x > 0.2; });
    const std::vector<bool> away = coverage(deepBall, [](double x) { return x < -0.3; });
    EXPECT_LT(meanOver(with, facing), meanOver(without, facing) - 0.05)
        << "without the tree " << meanOver(without, facing) << ", with it " << meanOver(with, facing);
    EXPECT_NEAR(meanOver(with, away), meanOver(without, away), 0.02);
    // The flattened image: red where the ball is in front, green on the tree, grey ground.
    const std::vector<float> red = partChannel(three, 0, "R"), green = partChannel(three, 0, "G");
    const std::vector<bool> onBall = coverage(deepBall), onTree = coverage(deepTree);
    for (size_t i = 0; i < red.size(); ++i) {
        if (onBall[i]) {
            EXPECT_EQ(red[i], 1.0f) << i;
        } else if (onTree[i]) {
            EXPECT_EQ(green[i], 1.0f) << i;
        }
    }
    for (const char* channel : {"obscura.AO.Y", "R", "G", "B", "A", "Z"})
        EXPECT_EQ(partChannel(three, 0, channel), partChannel(other, 0, channel)) << channel;
}

// --per-element-ao: each element's own visible surface, with every element as occluder. The
// ball's is darker than the ball alone where it faces the tree; the ground's covers the ground
// hidden behind the ball, darkened by it.
TEST(DeepElements, PerElementAoCoversEachElementsOwnSurface) {
    const fs::path dir = testDir("deep_elements");
    const auto [b, t, g] = writeScene(dir, "ball.0007.exr");
    const std::string out = (dir / "comp.exr").string(), alone = (dir / "alone.exr").string();
    CliResult r = runObscura(plus({b, t, g, "--per-element-ao", "--report", (dir / "comp.json").string()}, aoArgs(out)));
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    r = runObscura(plus({b}, aoArgs(alone)));
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    const std::vector<float> merged = partChannel(out, 0, "obscura.AO.Y"), own = partChannel(out, 0, "obscura.AO.ball.Y"),
                             single = partChannel(alone, 0, "obscura.AO.Y"),
                             ground = partChannel(out, 0, "obscura.AO.ground.Y");
    ASSERT_EQ(own.size(), merged.size());
    ASSERT_EQ(ground.size(), merged.size());
    ASSERT_EQ(partChannel(out, 0, "obscura.AO.tree.Y").size(), merged.size());
    const std::vector<bool> facing = coverage(deepBall, [](double x) { return x > 0.2; });
    EXPECT_LT(meanOver(own, facing), meanOver(single, facing) - 0.05);
    // Behind the ball, the ground's own AO: a surface, darkened by the ball standing on it.
    const std::vector<bool> onBall = coverage(deepBall), onGround = coverage(deepGround);
    std::vector<bool> hidden(onBall.size());
    for (size_t i = 0; i < hidden.size(); ++i) hidden[i] = onBall[i] && onGround[i];
    EXPECT_LT(meanOver(ground, hidden), 0.99);
    for (size_t i = 0; i < ground.size(); ++i) ASSERT_TRUE(std::isfinite(ground[i]) && ground[i] >= 0 && ground[i] <= 1);
    const nlohmann::json report = readJson(dir / "comp.json");
    EXPECT_EQ(report["deep"]["elements"].size(), 3u) << report.dump();
}

// --inspect on deep elements with no flat file describes them as a run merges them, and its
// command (with the lens and --falloff none it adds, each noted) runs.
TEST(DeepElements, InspectDescribesTheMergeAndItsCommandRuns) {
    const fs::path dir = testDir("deep_elements");
    const auto [b, t, g] = writeScene(dir);
    const CliResult one = runObscura({b, "--inspect"});
    ASSERT_EQ(one.exitCode, 0) << outcome(one);
    EXPECT_NE(one.out.find("deep:    1 element, no flat file: 1 layer(s)"), std::string::npos) << one.out;
    EXPECT_NE(one.out.find("depth: Z"), std::string::npos) << one.out;
    EXPECT_EQ(one.out.find("problem:"), std::string::npos) << one.out;
    EXPECT_NE(one.out.find("write:   copy: the flattened image plus the new layers"), std::string::npos) << one.out;
    const CliResult three = runObscura({b, t, g, "--inspect", "--json"});
    ASSERT_EQ(three.exitCode, 0) << outcome(three);
    const nlohmann::json j = nlohmann::json::parse(three.out);
    EXPECT_EQ(j["deep_elements"]["files"], (std::vector<std::string>{b, t, g}));
    EXPECT_EQ(j["deep_elements"]["layers"], 2) << "the ground behind the ball and the tree";
    ASSERT_TRUE(j["command_args"].is_array()) << j["command_problem"];
    std::vector<std::string> args = j["command_args"];
    EXPECT_NE(std::find(args.begin(), args.end(), "--falloff"), args.end()) << j["command"];
    EXPECT_EQ(j["command_notes"].size(), 2u) << j["command_notes"];
    const std::string out = (dir / "suggested.exr").string();
    const auto o = std::find(args.begin(), args.end(), "-o");
    ASSERT_NE(o, args.end());
    *(o + 1) = out;
    const CliResult run = runObscura(std::vector<std::string>(args.begin() + 1, args.end()));
    ASSERT_EQ(run.exitCode, 0) << outcome(run);
    for (float v : partChannel(out, 0, "obscura.AO.Y")) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
}

// Linear falloff (the default) keeps the horizon alone and so ignores the merge's layers: said
// in a warning, which --falloff none does not get, and the merge builds none.
TEST(DeepElements, LinearFalloffIsWarnedToIgnoreTheLayers) {
    const fs::path dir = testDir("deep_elements");
    const auto [b, t, g] = writeScene(dir);
    for (const bool linear : {true, false}) {
        const std::string out = (dir / (linear ? "linear.exr" : "none.exr")).string();
        const fs::path report = dir / (linear ? "linear.json" : "none.json");
        std::vector<std::string> args = {b, t, g, "-o", out, "--fov-deg", "40", "--report", report.string()};
        if (!linear) args.insert(args.end(), {"--falloff", "none"});
        const CliResult r = runObscura(args);
        ASSERT_EQ(r.exitCode, 0) << outcome(r);
        EXPECT_EQ(r.err.find("warning: linear falloff (the default) ignores the deep layers") != std::string::npos, linear)
            << r.err;
        // With linear falloff the merge flattens and builds no layers.
        const nlohmann::json j = readJson(report);
        EXPECT_EQ(j["deep"]["elements"].size(), 3u) << j.dump();
        EXPECT_EQ(j["deep"]["layers"].get<int>() == 0, linear) << j.dump();
    }
}

TEST(DeepElements, BadInputsAreOneLineAndWriteNothing) {
    const fs::path dir = testDir("deep_elements");
    const auto [b, t, g] = writeScene(dir);
    const std::string small = (dir / "small.exr").string(), noZ = (dir / "noz.exr").string(),
                      out = (dir / "out.exr").string();
    writeElement(small, deepGround, W / 2, H / 2);
    expectOneLineFailure(runObscura(plus({b, small}, aoArgs(out))), small, "display window", out);
    {  // The same display window, its data window a crop inside it (no samples: sky).
        OIIO::ImageSpec spec(W - 8, H, 6, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"R", "G", "B", "A", "Z", "ZBack"};
        spec.x = 4;
        spec.full_width = W;
        spec.full_height = H;
        spec.deep = true;
        OIIO::DeepData dd;
        dd.init(spec);
        auto o = OIIO::ImageOutput::create(small);
        ASSERT_TRUE(o && o->open(small, spec) && o->write_deep_image(dd) && o->close());
    }
    expectOneLineFailure(runObscura(plus({b, small}, aoArgs(out))), small, "data window", out);
    {  // A deep file with colour and alpha but no Z.
        OIIO::ImageSpec spec(4, 4, 2, OIIO::TypeDesc::FLOAT);
        spec.channelnames = {"A", "depth"};
        spec.deep = true;
        OIIO::DeepData dd;
        dd.init(spec);
        auto o = OIIO::ImageOutput::create(noZ);
        ASSERT_TRUE(o && o->open(noZ, spec) && o->write_deep_image(dd) && o->close());
    }
    expectOneLineFailure(runObscura(plus({noZ}, aoArgs(out))), noZ, "without a Z channel", out);
    expectOneLineFailure(runObscura(plus({b, noZ}, aoArgs(out))), noZ, "without a Z channel", out);
    // Cameras: a sidecar beside each element, their fields of view apart.
    for (const auto& [file, fov] : {std::pair{b, 0.7}, {g, 0.6}}) {
        std::ofstream(fs::path(file).replace_extension(".json"))
            << R"({"projection": "persp", "camera_to_world": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1], )"
            << R"("horizontal_fov_rad": )" << fov << "}";
    }
    std::vector<std::string> args = aoArgs(out);
    args.erase(args.begin() + 2, args.begin() + 4);  // no --fov-deg: each element's sidecar
    expectOneLineFailure(runObscura(plus({b, g}, args)), g, "camera", out);
    // Usage: --flat takes one deep input; --per-element-ao needs a method that reads deep layers.
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{b, g, "--flat", g}, {b, g, "--per-element-ao", "--method", "ssao"}}) {
        const CliResult r = runObscura(plus(bad, aoArgs(out)));
        EXPECT_EQ(r.exitCode, 2) << outcome(r);
        EXPECT_FALSE(fs::exists(out));
    }
}
