// Deep EXR input (docs/deep.md): the reader (samples sorted, NaN and empty pixels counted,
// touching samples merged, at most K surfaces), HBAO with hidden layers against a closed form
// and against itself without them, and the command line end to end on a ray-traced scene.
#include "base/error.h"
#include "core/operator.h"
#include "io/deep_file.h"
#include "support/cli_runner.h"
#include "support/closed_forms.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/reference_runs.h"
#include "support/roof_scene.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// (Z, ZBack) samples per pixel, in the order given.
using Samples = std::vector<std::pair<float, float>>;

// A deep EXR of W x 1 pixels with channels A, Z, ZBack; tiled when `tiled`.
void writeDeepFile(const std::string& path, const std::vector<Samples>& pixels, bool tiled) {
    OIIO::ImageSpec spec((int)pixels.size(), 1, 3, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"A", "Z", "ZBack"};
    spec.alpha_channel = 0;
    spec.z_channel = 1;
    spec.deep = true;
    if (tiled) spec.tile_width = spec.tile_height = 16;
    OIIO::DeepData dd;
    dd.init(spec);
    for (size_t p = 0; p < pixels.size(); ++p) dd.set_samples((int64_t)p, (int)pixels[p].size());
    for (size_t p = 0; p < pixels.size(); ++p)
        for (size_t s = 0; s < pixels[p].size(); ++s) {
            dd.set_deep_value((int64_t)p, 0, (int)s, 1.0f);
            dd.set_deep_value((int64_t)p, 1, (int)s, pixels[p][s].first);
            dd.set_deep_value((int64_t)p, 2, (int)s, pixels[p][s].second);
        }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
    ASSERT_TRUE(out->write_deep_image(dd)) << out->geterror();
    ASSERT_TRUE(out->close());
}

float front(const DeepLayers& d, int x, int k) { return d.planes.at(x, 0)[2 * k]; }
float back(const DeepLayers& d, int x, int k) { return d.planes.at(x, 0)[2 * k + 1]; }

} // namespace

// Every case the reader must handle, in one file written by OpenImageIO, scanline and tiled.
TEST(DeepRead, LayersAreSortedCountedMergedAndCapped) {
    const fs::path dir = testDir("deep");
    const std::vector<Samples> pixels = {
        {},                                       // 0: no sample: sky
        {{5, 5}, {2, 2}, {9, 9}},                 // 1: unsorted
        {{kNaN, kNaN}, {3, 3}, {kInf, kInf}},     // 2: NaN Z dropped; inf Z the sky, no surface
        {{2, 3}, {3, 4}, {6, 7}},                 // 3: a span touching the next: one surface [2, 4]
        {{1, 1}, {2, 2}, {3, 3}, {4, 4}, {5, 5}}, // 4: five surfaces, four kept
        {{4, 8}, {5, 6}},                         // 5: a sample inside a span: one surface [4, 8]
        {{7, kNaN}},                              // 6: NaN ZBack: a point sample
    };
    for (bool tiled : {false, true}) {
        const std::string path = (dir / (tiled ? "tiled.exr" : "scanline.exr")).string();
        writeDeepFile(path, pixels, tiled);
        EXPECT_TRUE(isDeepFile(path));
        const DeepLayers d = readDeepLayers(path, 4);
        EXPECT_EQ(d.layers, 4);
        EXPECT_EQ(d.planes.channels, 8);
        EXPECT_EQ(d.emptyPixels, 1);
        EXPECT_EQ(d.droppedSamples, 1);
        EXPECT_EQ(d.unsortedPixels, 1);
        EXPECT_EQ(d.truncatedPixels, 1);
        EXPECT_EQ(front(d, 0, 0), kInf);
        EXPECT_EQ(front(d, 1, 0), 2.0f);
        EXPECT_EQ(front(d, 1, 1), 5.0f);
        EXPECT_EQ(front(d, 1, 2), 9.0f);
        EXPECT_EQ(front(d, 1, 3), kInf);
        EXPECT_EQ(front(d, 2, 0), 3.0f);
        EXPECT_EQ(front(d, 2, 1), kInf);
        EXPECT_EQ(front(d, 3, 0), 2.0f);
        EXPECT_EQ(back(d, 3, 0), 4.0f);
        EXPECT_EQ(front(d, 3, 1), 6.0f);
        EXPECT_EQ(back(d, 3, 1), 7.0f);
        EXPECT_EQ(front(d, 4, 3), 4.0f);
        EXPECT_EQ(back(d, 5, 0), 8.0f);
        EXPECT_EQ(front(d, 5, 1), kInf);
        EXPECT_EQ(back(d, 6, 0), 7.0f);
        // K = 2 keeps the two nearest.
        const DeepLayers two = readDeepLayers(path, 2);
        EXPECT_EQ(two.layers, 2);
        EXPECT_EQ(front(two, 1, 1), 5.0f);
        EXPECT_EQ(two.truncatedPixels, 2);
    }
}

TEST(DeepRead, FlatFileAndMissingZAreOneLineErrors) {
    const fs::path dir = testDir("deep");
    const std::string flat = (dir / "flat.exr").string();
    {
        OIIO::ImageSpec spec(4, 4, 1, OIIO::TypeDesc::FLOAT);
        std::vector<float> px(16, 1.0f);
        auto out = OIIO::ImageOutput::create(flat);
        ASSERT_TRUE(out && out->open(flat, spec) && out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
    }
    EXPECT_FALSE(isDeepFile(flat));
    try {
        readDeepLayers(flat, 4);
        FAIL() << "a flat file read as deep";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("not a deep image"), std::string::npos) << e.what();
    }
    const std::string deep = (dir / "deep.exr").string();
    writeDeepFile(deep, {{{1, 1}}}, false);
    try {
        readDeepLayers(deep, 4, DeepChannelNames{"depth", "depthBack"});
        FAIL() << "a missing Z channel went unnoticed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("without a depth channel"), std::string::npos) << e.what();
    }
}

// A deep header's windows are bounded like a flat one's, before its samples are read.
TEST(DeepRead, WindowOverMaxPixelsIsRefusedBeforeReading) {
    const fs::path dir = testDir("deep");
    const std::string deep = (dir / "wide.exr").string();
    writeDeepFile(deep, std::vector<Samples>(8, Samples{{1, 1}}), false);
    EXPECT_EQ(readDeepLayers(deep, 4, {}, 8).layers, 1);
    try {
        readDeepLayers(deep, 4, {}, 7);
        FAIL() << "an 8-pixel deep file passed a limit of 7";
    } catch (const FileError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("8 x 1 pixels, more than the limit of 7 (--max-pixels)"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
}

// A block hidden under a roof beyond R: without deep input the floor beside it is open (the
// roof is out of reach); with it, the block is a wall of height >= R, whose AO within R is
// the corner's closed form.
TEST(DeepHbao, HiddenBlockUnderRoofMatchesCornerClosedForm) {
    const float R = 1.0f;
    const RoofScene scene(3.0f * R, 1.5f * R);
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
        const Settings s = hbaoSettings(w, Falloff::None, R, 32, 32);
        const OperatorOutputs flat = runOperator(scene.inputs(false), s);
        const OperatorOutputs deep = runOperator(scene.inputs(true), s);
        for (double d : {0.1, 0.25, 0.5, 0.75}) {
            // The column centre sits half a pixel from d: compare with the closed form there.
            const double at = (std::lround(d * RoofScene::kPixelsPerUnit - 0.5) + 0.5) / RoofScene::kPixelsPerUnit;
            EXPECT_GE(RoofScene::columnMean(flat.ao, d), 0.999) << "d=" << d << " " << toString(w);
            EXPECT_NEAR(RoofScene::columnMean(deep.ao, d), cornerAo(w, Falloff::None, at / R), 0.02)
                << "d=" << d << " " << toString(w);
        }
    }
}

// Deep input whose only layer is the visible one, as point samples, is the thickness rule
// without deep input plus each sample's footprint: the same intervals through the same code, and
// more. Footprints add occupied angles, so pixels only get darker, but for a few in 10^4 that get
// lighter by up to 0.006 (measured; not explained yet: the sectors' accounting is the suspect).
TEST(DeepHbao, PointSamplesOfTheVisibleLayerAddFootprintsToTheFlatResult) {
    const int W = 160, H = 120;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.0f}});  // the visible layer, point samples
    OperatorInputs in = sb.inputs();
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
        Settings s = hbaoSettings(w, Falloff::None, 1.0f);
        // A fixed T: for flat input `auto` measures each occluder by runs, which deep input does not
        // take (its layers say how deep things are; a point sample gets 0.85 R).
        s.thickness = 0.85f * s.radius;
        const OperatorOutputs flat = runOperator(in, s);
        in.deepLayers = deep.view();
        const OperatorOutputs withDeep = runOperator(in, s);
        in.deepLayers = ConstPlane{};
        float minAo = 1.0f;
        double changed = 0;
        int lighter = 0;
        for (size_t i = 0; i < flat.ao.pixels.size(); ++i) {
            ASSERT_LE(withDeep.ao.pixels[i], flat.ao.pixels[i] + 0.01f) << "pixel " << i;
            lighter += withDeep.ao.pixels[i] > flat.ao.pixels[i] + 1e-5f;
            minAo = std::min(minAo, flat.ao.pixels[i]);
            changed += flat.ao.pixels[i] - withDeep.ao.pixels[i] > 1e-3f;
        }
        EXPECT_LT(minAo, 0.8f) << "the scene must have occlusion to compare";
        // The footprints reach the creases between samples (the studio's floor and walls).
        EXPECT_GT(changed / flat.ao.pixels.size(), 0.05) << toString(w);
        EXPECT_LT(lighter, (int)flat.ao.pixels.size() / 1000) << toString(w);
        std::printf("%s: %.1f%% of pixels darker by > 1e-3 with footprints, %d lighter by > 1e-5\n", toString(w),
                    100.0 * changed / flat.ao.pixels.size(), lighter);
    }
}

// A wall seen from 2 cm above a floor 10 m away: the floor within R of the wall's foot is seen
// at 0.1-0.3 degrees and lies inside the one pixel row below the wall, which every horizon
// sample steps over. The footprint of that row's pixels on their tangent plane (and the plane
// carried back to the crease with the wall) is the floor there: the wall's AO at height h is
// the corner's closed form at h / R, as the floor's at distance h from a wall.
TEST(DeepHbao, GrazingFloorBeforeAWallMatchesCornerClosedForm) {
    const int W = 160, H = 120;
    const float R = 1.0f;
    const double eyeHeight = 0.02;
    const SceneBuffers sb = renderScene(cornerScene(), lookAtPerspective({-10, eyeHeight, 0}, {0, eyeHeight - 1.5, 0},
                                                                          M_PI / 3, W, H), W, H);
    const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.0f}});  // the visible layer, point samples
    OperatorInputs in = sb.inputs();
    for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
        const Settings s = hbaoSettings(w, Falloff::None, R, 16, 12);
        in.deepLayers = ConstPlane{};
        const OperatorOutputs flat = runOperator(in, s);
        in.deepLayers = deep.view();
        const OperatorOutputs withDeep = runOperator(in, s);
        // Mean |AO - closed form| over the wall's pixels between 0.05 R and 0.9 R above the floor.
        double flatError = 0, deepError = 0;
        int n = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 8; x < W - 8; ++x) {
                const float* p = sb.position.at(x, y);
                const double h = p[1];
                if (std::abs(p[0]) > 1e-6 || h < 0.05 * R || h > 0.9 * R) continue;  // the wall x = 0 only
                const double expected = cornerAo(w, Falloff::None, h / R);
                flatError += std::abs(*flat.ao.at(x, y) - expected);
                deepError += std::abs(*withDeep.ao.at(x, y) - expected);
                ++n;
            }
        ASSERT_GT(n, 500);
        flatError /= n;
        deepError /= n;
        std::printf("%s: wall foot mean |error| flat %.4f, deep point samples with footprints %.4f (%d px)\n",
                    toString(w), flatError, deepError, n);
        EXPECT_GT(flatError, 0.1) << "the floor must be out of the depth pass's reach";
        EXPECT_LT(deepError, 0.03) << toString(w);
    }
}

// A plane stays unoccluded whatever lies behind it: hidden layers are below its tangent plane.
TEST(DeepHbao, PlaneWithLayersBehindStaysExact) {
    for (bool ortho : {false, true})
        for (double tiltDeg : {0.0, 60.0}) {
            const SceneBuffers sb = tiltedPlaneView(tiltDeg, 20.0, ortho, 64, 48);
            // The plane is a slab, a point surface behind it, then a span.
            const Image deep = deepLayersFromDepth(sb.depth, {{0.0f, 0.5f}, {1.0f, 1.0f}, {1.5f, 3.0f}});
            OperatorInputs in = sb.inputs();
            in.deepLayers = deep.view();
            for (Weighting w : {Weighting::Uniform, Weighting::Cosine}) {
                const OperatorOutputs out = runOperator(in, hbaoSettings(w, Falloff::None, 4.0f));
                EXPECT_GE(*std::min_element(out.ao.pixels.begin(), out.ao.pixels.end()), 1.0f - 2e-4f)
                    << "ortho " << ortho << " tilt " << tiltDeg;
            }
        }
}

TEST(DeepHbao, OddChannelCountIsAnError) {
    const RoofScene scene(3.0f, 1.5f);
    OperatorInputs in = scene.inputs(true);
    Image odd(RoofScene::W, RoofScene::H, 3);
    in.deepLayers = odd.view();
    EXPECT_THROW(runOperator(in, hbaoSettings(Weighting::Cosine, Falloff::None, 1.0f)), Error);
}

// Deep layers given to a method that does not read them are an error, not silently ignored.
TEST(DeepHbao, OtherMethodsRefuseDeepLayers) {
    const RoofScene scene(3.0f, 1.5f);
    const OperatorInputs in = scene.inputs(true);
    Settings s = hbaoSettings(Weighting::Cosine, Falloff::None, 1.0f);
    EXPECT_NO_THROW(runOperator(in, s));
    s.method = "ssao";
    try {
        runOperator(in, s);
        FAIL() << "ssao took deep layers";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--method ssao does not read deep layers"), std::string::npos) << e.what();
    }
}

// The command line: deep input needs --flat, --deep-layers has a range, and the ray-traced
// poles (thin cylinders the depth pass sees as walls) come out far closer to the reference
// with every solid along each ray than from the depth pass alone.
TEST(DeepCli, UsageAndErrors) {
    const fs::path dir = testDir("deep");
    const std::string deep = (dir / "d.exr").string();
    writeDeepFile(deep, {{{1, 1}}}, false);
    CliResult r = runProgram(OBSCURA_CLI_PATH, {deep, "--flat", "x.exr", "-o", "o.exr", "--deep-layers", "0"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--deep-layers must be between 1 and 16"), std::string::npos) << r.err;
    r = runProgram(OBSCURA_CLI_PATH, {deep, "--flat", "x.exr", "-o", "o.exr", "--method", "ssao"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("--flat (deep input) works with --method hbao only"), std::string::npos) << r.err;
    r = runProgram(OBSCURA_CLI_PATH, {(dir / "d.####.exr").string(), "--flat", "f.exr", "-o", "o.####.exr"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("must both be frame patterns"), std::string::npos) << r.err;
    r = runProgram(OBSCURA_CLI_PATH, {deep, "--flat", "f.####.exr", "-o", "o.####.exr"});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.err.find("must both be frame patterns"), std::string::npos) << r.err;
    // Without --flat the deep file is an input of its own (tests/test_deep_elements.cpp): this one
    // has no camera.
    r = runProgram(OBSCURA_CLI_PATH, {deep, "-o", (dir / "o.exr").string()});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("no camera"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "o.exr"));
}

TEST(DeepCli, PolesWithDeepInputBeatTheDepthPass) {
    const fs::path dir = testDir("deep");
    const std::string ref = (dir / "poles.exr").string(), deep = (dir / "poles_deep.exr").string();
    const CliResult r = renderReferenceScene("poles", ref, 200, 150, {"--deep", deep});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const DeepLayers layers = readDeepLayers(deep, 4);
    EXPECT_EQ(layers.layers, 4);  // pole, pole behind, ..., the ground
    const double flat = psnrAgainstCosineReference(ref, dir, 0.5f, {"--quality", "high"});
    const double withDeep = psnrAgainstCosineReference(deep, dir, 0.5f, {"--flat", ref, "--quality", "high"});
    std::printf("poles 200x150: hbao high %.2f dB, with deep input %.2f dB\n", flat, withDeep);
    EXPECT_GT(withDeep, flat + 8.0);
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "report.json"));
    EXPECT_EQ(report["deep"]["layers"].get<int>(), 4);
    EXPECT_EQ(report["deep"]["dropped_samples"].get<long long>(), 0);
    const CliResult inspect = runProgram(OBSCURA_CLI_PATH, {deep, "--flat", ref, "--inspect"});
    EXPECT_EQ(inspect.exitCode, 0) << inspect.err;
    EXPECT_NE(inspect.out.find("deep:    " + deep + " (Z, ZBack): 4 layer(s)"), std::string::npos) << inspect.out;
}

// reference_render --deep colours each span with what its entered surface radiates: the first
// span's colour, read back as the CLI's deep reader reads it, is the flat render's DiffDir x
// DiffCol at that pixel (same hit, same sky rays); the hidden surfaces are lit too.
TEST(DeepCli, ReferenceDeepColourIsTheFlatDirectDiffuse) {
    const fs::path dir = testDir("deep-colour");
    const std::string ref = (dir / "studio.exr").string(), deep = (dir / "studio_deep.exr").string();
    const int w = 64, h = 48;
    const CliResult r = renderReferenceScene("studio", ref, w, h, {"--ao-rays", "1", "--gi-rays", "16", "--deep", deep});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const DeepLayers layers = readDeepLayers(deep, 4, {}, kDefaultMaxPixels, true);
    ASSERT_EQ(layers.colour.channels, 3 * layers.layers);
    const std::vector<float> depth = partChannel(ref, 0, "ViewLayer.Depth.Z");
    std::vector<float> direct[3], albedo[3];
    for (int c = 0; c < 3; ++c) {
        const std::string name(1, "RGB"[c]);
        direct[c] = partChannel(ref, 0, "ViewLayer.DiffDir." + name);
        albedo[c] = partChannel(ref, 0, "ViewLayer.DiffCol." + name);
    }
    int surfaces = 0, litHidden = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * w + x;
            const float* rgb = layers.colour.at(x, y);
            if (depth[i] >= 1e9f) {
                EXPECT_EQ(layers.planes.at(x, y)[0], kInf) << x << "," << y;
                continue;
            }
            ++surfaces;
            EXPECT_EQ(layers.planes.at(x, y)[0], depth[i]) << x << "," << y;
            for (int c = 0; c < 3; ++c) {
                const float sent = direct[c][i] * albedo[c][i];
                EXPECT_NEAR(rgb[c], sent, 1e-6f * std::max(1.0f, sent)) << x << "," << y << " " << c;
            }
            for (int k = 1; k < layers.layers; ++k)
                if (layers.planes.at(x, y)[2 * k] < kInf && rgb[3 * k] + rgb[3 * k + 1] + rgb[3 * k + 2] > 0) ++litHidden;
        }
    EXPECT_GT(surfaces, w * h / 2);
    EXPECT_GT(litHidden, 100);  // the floor behind the objects, under the sun
}

// A deep input the CLI cannot use fails the frame with one line naming it, exit 1 and no
// output: a truncated deep file (falloff none, which reads its samples), a flat file given as
// the deep input, a deep file whose display window is not the flat passes' (with either
// falloff: linear falloff reads only the header, and checks it). The same flat passes with a
// good deep file run. With linear falloff the deep file changes nothing and is not read: the AO
// is that of the flat passes alone, bit for bit, and the report says so.
TEST(DeepCli, BadDeepInputIsOneLineAndNoOutput) {
    const fs::path dir = testDir("deep-bad");
    const std::string flat = (dir / "flat.exr").string(), good = (dir / "good.exr").string();
    // The flat passes: a plane facing the camera at depth 2, 16 x 1 pixels.
    fixtures::FixturePart passes;
    for (const auto& [name, v] : std::vector<std::pair<std::string, float>>{{"Z", 2}, {"N.X", 0}, {"N.Y", 0}, {"N.Z", 1}}) {
        fixtures::FixtureChannel c;
        c.name = name;
        c.value = [v = v](int, int) { return v; };
        passes.channels.push_back(c);
    }
    passes.displayWindow = passes.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(15, 0));
    fixtures::writeFixture(flat, {passes});
    const std::vector<Samples> pixels(16, Samples{{2, 3}, {5, 5}});
    writeDeepFile(good, pixels, false);
    const std::string out = (dir / "out.exr").string();
    auto run = [&](const std::string& deep, const char* falloff = "none", std::vector<std::string> more = {"--quiet"}) {
        std::vector<std::string> args = {deep, "--flat", flat, "-o", out, "--fov-deg", "50", "--normals", "camera",
                                         "--falloff", falloff};
        args.insert(args.end(), more.begin(), more.end());
        return runProgram(OBSCURA_CLI_PATH, args);
    };
    const CliResult ok = run(good);
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    ASSERT_TRUE(fs::exists(out));
    fs::remove(out);
    {
        const std::string report = (dir / "linear.json").string(), alone = (dir / "alone.exr").string();
        const CliResult linear = run(good, "linear", {"--report", report});
        ASSERT_EQ(linear.exitCode, 0) << linear.err;
        EXPECT_NE(linear.err.find("linear falloff (the default) ignores the deep layers"), std::string::npos) << linear.err;
        const nlohmann::json j = readJson(report);
        EXPECT_EQ(j["deep"]["layers"].get<int>(), 0) << j.dump();
        EXPECT_NE(j["plan"].dump().find("deep: " + good + " not read"), std::string::npos) << j.dump();
        const CliResult flatOnly = runProgram(OBSCURA_CLI_PATH, {flat, "-o", alone, "--fov-deg", "50", "--normals", "camera", "--quiet"});
        ASSERT_EQ(flatOnly.exitCode, 0) << flatOnly.err;
        EXPECT_EQ(partChannel(out, 0, "obscura.AO.Y"), partChannel(alone, 0, "obscura.AO.Y"));
        fs::remove(out);
    }

    const std::string truncated = (dir / "truncated.exr").string(), narrow = (dir / "narrow.exr").string();
    fixtures::truncatedCopy(good, truncated, fixtures::fileSize(good) - 16);
    writeDeepFile(narrow, std::vector<Samples>(8, Samples{{2, 3}}), false);
    const std::vector<std::pair<std::string, std::string>> cases = {
        {truncated, "truncated.exr'"},
        {flat, "not a deep image"},
        {narrow, "its display window (8x1) is not the flat passes' (16x1)"},
    };
    for (const auto& [deep, expected] : cases)
        for (const char* falloff : {"none", "linear"}) {
            if (deep == truncated && std::string(falloff) == "linear") continue;  // its header is whole
            const CliResult r = run(deep, falloff);
            std::printf("%s", r.err.c_str());
            EXPECT_EQ(r.exitCode, 1) << deep << " " << falloff;
            EXPECT_EQ(r.err.rfind("obscura: ", 0), 0u) << r.err;
            EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
            EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
            EXPECT_FALSE(fs::exists(out)) << deep << " " << falloff;
        }
}
