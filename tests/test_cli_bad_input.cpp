// The obscura CLI on bad input and bad usage: one clear stderr line, the right exit code, nothing written.
#include "core/camera.h"
#include "support/cli_fixtures.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using namespace obscura::test;

namespace {

// The AO channel of an output file as floats (empty, with a failure, if it is missing).
std::vector<float> aoValues(const std::string& path, const std::string& name = "obscura.AO.Y", int part = 0) {
    const FileData fd = readAll(path);
    const ChannelData* ch = fd.find(part, name);
    if (!ch) {
        ADD_FAILURE() << "no channel " << name << " in " << path;
        return {};
    }
    return ch->floats();
}

// ---------------------------------------------------------------------------
// 1. Bad input: one clear line, non-zero exit, nothing written
// ---------------------------------------------------------------------------

TEST(CliBadInput, MissingInputFile) {
    const fs::path dir = testDir();
    const fs::path out = dir / "out.exr";
    const CliResult r = cli({(dir / "nope.exr").string(), "-o", out.string()});
    expectCleanFailure(r, 1, out, {"nope.exr"});
}

TEST(CliBadInput, TextFileIsNotAnExr) {
    const fs::path dir = testDir();
    const fs::path in = dir / "notes.exr", out = dir / "out.exr";
    std::ofstream(in) << "these are not the pixels you are looking for\nsecond line\n";
    const CliResult r = cli({in.string(), "-o", out.string()});
    expectCleanFailure(r, 1, out, {"notes.exr"});
}

TEST(CliBadInput, TruncatedExr) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    const std::string good = writeGeneric(dir, "good.exr", planesOf(s));
    const fs::path in = dir / "cut.exr", out = dir / "out.exr";
    truncatedCopy(good, in.string(), fileSize(good) * 2 / 3);
    const CliResult r = cli(cat({in.string(), "-o", out.string()}, cameraFlags(s)));
    expectCleanFailure(r, 1, out, {"cut.exr", "truncated or corrupt"});
}

TEST(CliBadInput, RequiredLayerMissing) {
    const fs::path dir = testDir();
    const fs::path in = dir / "beauty.exr", out = dir / "out.exr";
    writeSimple(in.string(), {"R", "G", "B"}, 16, 12);
    const CliResult r = cli({in.string(), "-o", out.string()});
    // Names the missing role and what was found.
    expectCleanFailure(r, 1, out, {"no depth layer", "R G B", "--layer depth="});
}

TEST(CliBadInput, SubsampledNormalRefused) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    const Planes planes = planesOf(s);  // the fixture's channels read from these
    FixturePart part = makePart(planes, kGeneric);
    for (FixtureChannel& c : part.channels)
        if (c.name == "N.Y") c.xSampling = c.ySampling = 2;
    const fs::path in = dir / "sub.exr", out = dir / "out.exr";
    writeFixture(in.string(), {part});
    const CliResult r = cli(cat({in.string(), "-o", out.string()}, cameraFlags(s)));
    expectCleanFailure(r, 1, out, {"'" + in.string() + "': channel 'N.Y' is subsampled (2x2)"});
}

TEST(CliBadInput, SubsampledPassThroughKept) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    const Planes planes = planesOf(s);  // the fixture's channels read from these
    FixturePart part = makePart(planes, kGeneric);
    part.channels.push_back({"chroma.RY", Imf::HALF, 2, 2, {}});
    const fs::path in = dir / "sub.exr", out = dir / "out.exr";
    writeFixture(in.string(), {part});
    const CliResult r = cli(cat({in.string(), "-o", out.string()}, cameraFlags(s)));
    expectSuccess(r, out);
    Imf::MultiPartInputFile f(out.c_str());
    const Imf::Channel* ry = f.header(0).channels().findChannel("chroma.RY");
    ASSERT_NE(ry, nullptr);
    EXPECT_EQ(ry->xSampling, 2);
    EXPECT_EQ(ry->ySampling, 2);
}

TEST(CliBadInput, BrokenSidecarNamedOnOneLine) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    const std::string in = writeGeneric(dir, "in.exr", planesOf(s));
    const fs::path json = dir / "in.json", out = dir / "out.exr";
    std::ofstream(json) << "{\"camera_to_world\": [[1, 0, 0, 0],\n \"horizontal";
    const CliResult r = cli({in, "-o", out.string()});
    expectCleanFailure(r, 1, out, {"'" + json.string() + "': camera sidecar is not valid JSON"});
    EXPECT_FALSE(contains(r.err, "json.exception")) << r.err;
}

// Every failure a file or a flag naming a file can cause reads "obscura: 'FILE': what", FILE
// the one at fault, exit 1, and leaves nothing behind.
TEST(CliBadInput, EveryFailureNamesTheFileAtFault) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(32, 24);
    const std::string in = writeGeneric(dir, "in.exr", planesOf(s));
    const std::string out = (dir / "out.exr").string(), missing = (dir / "nope.exr").string();
    const std::string notExr = (dir / "notes.exr").string(), cut = (dir / "cut.exr").string();
    std::ofstream(notExr) << "not pixels\n";
    truncatedCopy(in, cut, fileSize(in) / 2);
    const std::string json = (dir / "broken.json").string();
    std::ofstream(json) << "{\"camera_to_world\": 3}";
    const std::string noDir = (dir / "no_such_dir").string();
    // A pipe no one writes: opening it would block the run for good.
    const std::string pipe = (dir / "pipe.exr").string();
    ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
    const std::vector<std::string> cam = cameraFlags(s);
    struct Case {
        std::vector<std::string> args;
        std::string file, what;
    };
    const std::vector<Case> cases = {
        {{missing, "-o", out}, missing, "cannot open: no such file"},
        {{dir.string(), "-o", out}, dir.string(), "cannot open: it is a directory"},
        {{notExr, "-o", out}, notExr, "not an OpenEXR file"},
        {{pipe, "-o", out}, pipe, "not a regular file"},
        {cat({cut, "-o", out}, cam), cut, "truncated or corrupt"},
        {cat({in, "-o", noDir + "/o.exr"}, cam), noDir + "/o.exr", "cannot write: directory"},
        {cat({in, "-o", out, "--report", noDir + "/r.json"}, cam), noDir + "/r.json", "cannot write: directory"},
        {cat({in, "-o", out, "--preview", noDir + "/p.png"}, cam), noDir + "/p.png", "cannot write: directory"},
        {{in, "-o", out, "--camera", json}, json, "camera sidecar"},
        {{in, "-o", out, "--camera", missing}, missing, "cannot open the camera sidecar"},
        {cat({in, "-o", out, "--method", "ssdo", "--env", missing}, cam), missing, "cannot read the environment map"},
        {cat({in, "-o", out, "--layer", "normal=nope"}, cam), in, "--layer normal=nope: no layer or channel 'nope'"},
        {cat({in, "-o", out, "--reference", "nope"}, cam), in, "no reference layer 'nope'"},
        // Neither a direct-diffuse nor an albedo layer: one line names both ways on.
        {cat({in, "-o", out, "--method", "ssdo", "--bounce"}, cam), in,
         "no direct-diffuse layer for the bounce; use --bounce-source beauty or --layer direct-diffuse=NAME, and GI "
         "alone (--out-layer gi=NAME in place of --bounce: relit needs an albedo)"},
        {cat({in, "-o", out, "--per-element-ao", "--falloff", "none"}, cam), in,
         "holds no deep data: the per-element AO is made of deep elements"},
        {cat({(dir / "seq.####.exr").string(), "-o", (dir / "o.####.exr").string()}, cam),
         (dir / "seq.####.exr").string(), "no frames match"},
    };
    for (const Case& c : cases) {
        const CliResult r = cli(c.args);
        SCOPED_TRACE(c.args[0] + " ... " + c.args.back());
        expectCleanFailure(r, 1, out, {"obscura: '" + c.file + "': ", c.what});
    }
}

struct BrokenFrame {
    SceneBuffers scene = cornerScene(48, 32);
    Planes planes = planesOf(scene);
    int x = 0, y = 0;  // a surface pixel
    BrokenFrame() {
        for (y = 31; y > 0; --y)
            if (*planes.depth.at(x = 10, y) < 1e9f) break;
    }
    // Writes the planes to DIR/NAME and runs the CLI on them with the scene's camera and `flags`,
    // writing `out`.
    CliResult run(const fs::path& dir, const std::string& name, const fs::path& out,
                  const std::vector<std::string>& flags = {}) const {
        const std::string in = writeGeneric(dir, name, planes);
        return cli(cat(cat({in, "-o", out.string()}, flags), cameraFlags(scene)));
    }
};

TEST(CliBadInput, NanDepthErrorsByDefault) {
    const fs::path dir = testDir();
    BrokenFrame f;
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::quiet_NaN();
    const fs::path out = dir / "out.exr";
    const CliResult r = f.run(dir, "nan.exr", out);
    expectCleanFailure(r, 1, out, {"NaN", std::to_string(f.x) + "," + std::to_string(f.y), "--bad-pixels skip"});
}

TEST(CliBadInput, NanDepthSkipped) {
    const fs::path dir = testDir();
    BrokenFrame f;
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::quiet_NaN();
    *f.planes.depth.at(f.x + 1, f.y) = std::numeric_limits<float>::quiet_NaN();
    const fs::path out = dir / "out.exr";
    const CliResult r = f.run(dir, "nan.exr", out, {"--bad-pixels", "skip", "--out-type", "float"});
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    const ChannelData* ao = fd.find(0, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    const std::vector<float> v = ao->floats();
    for (size_t i = 0; i < v.size(); ++i) ASSERT_TRUE(v[i] >= 0.0f && v[i] <= 1.0f) << i << ": " << v[i];
    EXPECT_EQ(v[(size_t)f.y * 48 + f.x], 1.0f) << "a NaN-depth hole gets AO 1";
    EXPECT_LT(*std::min_element(v.begin(), v.end()), 0.9f) << "the rest of the frame is still computed";
    EXPECT_TRUE(contains(r.err, "warning")) << r.err;
}

TEST(CliBadInput, NegativeDepthErrors) {
    const fs::path dir = testDir();
    BrokenFrame f;
    *f.planes.depth.at(f.x, f.y) = -2.0f;
    const fs::path out = dir / "out.exr";
    const CliResult r = f.run(dir, "neg.exr", out);
    expectCleanFailure(r, 1, out, {"negative", std::to_string(f.x) + "," + std::to_string(f.y)});
}

TEST(CliBadInput, InfiniteDepthIsSky) {
    const fs::path dir = testDir();
    BrokenFrame f;
    for (int y = 0; y < 32; ++y)
        if (*f.planes.depth.at(0, y) >= 1e9f) *f.planes.depth.at(0, y) = std::numeric_limits<float>::infinity();
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::infinity();  // a hole in a surface
    const fs::path out = dir / "out.exr";
    const CliResult r = f.run(dir, "inf.exr", out, {"--out-type", "float"});
    expectSuccess(r, out);
    const std::vector<float> v = aoValues(out.string());
    ASSERT_EQ(v.size(), f.planes.depth.pixels.size());
    for (size_t i = 0; i < v.size(); ++i) {
        ASSERT_TRUE(v[i] >= 0.0f && v[i] <= 1.0f) << i << ": " << v[i];
        if (std::isinf(f.planes.depth.pixels[i])) {
            EXPECT_EQ(v[i], 1.0f) << "+inf depth is sky, pixel " << i;
        }
    }
}

TEST(CliBadInput, ZeroNormalsEverywhereErrors) {
    const fs::path dir = testDir();
    BrokenFrame f;
    std::fill(f.planes.normal.pixels.begin(), f.planes.normal.pixels.end(), 0.0f);
    const fs::path out = dir / "out.exr";
    const CliResult r = f.run(dir, "zeron.exr", out);
    expectCleanFailure(r, 1, out, {"normal", "zero"});
}

TEST(CliBadInput, NonUnitNormalsAreNormalised) {
    const fs::path dir = testDir();
    BrokenFrame f;
    const std::string unitIn = writeGeneric(dir, "unit.exr", f.planes);
    for (float& v : f.planes.normal.pixels) v *= 3.0f;
    const std::string longIn = writeGeneric(dir, "long.exr", f.planes);
    const fs::path unitOut = dir / "unit_ao.exr", longOut = dir / "long_ao.exr";
    const CliResult r1 = cli(cat({unitIn, "-o", unitOut.string(), "--out-type", "float"}, cameraFlags(f.scene)));
    const CliResult r2 = cli(cat({longIn, "-o", longOut.string(), "--out-type", "float"}, cameraFlags(f.scene)));
    expectSuccess(r1, unitOut);
    expectSuccess(r2, longOut);
    const std::vector<float> a = aoValues(unitOut.string()), b = aoValues(longOut.string());
    ASSERT_EQ(a.size(), f.planes.depth.pixels.size());
    ASSERT_EQ(b.size(), a.size());
    float minAo = 1;
    for (size_t i = 0; i < b.size(); ++i) {
        ASSERT_TRUE(b[i] >= 0.0f && b[i] <= 1.0f) << i << ": " << b[i];
        EXPECT_NEAR(b[i], a[i], 1e-3f) << "length-3 normals should give the unit-normal AO, pixel " << i;
        minAo = std::min(minAo, b[i]);
    }
    EXPECT_LT(minAo, 0.9f);
}

// Normals of a length float cannot square (1e-30, 1e30) are neither called zero nor taken: the
// line says their length, and --bad-pixels skip runs with AO in [0, 1].
TEST(CliBadInput, NormalsOfAnExtremeLengthAreSaidAndSkipped) {
    const fs::path dir = testDir();
    for (const float scale : {1e-30f, 1e30f}) {
        SCOPED_TRACE(scale);
        BrokenFrame f;
        for (float& v : f.planes.normal.pixels) v *= scale;
        const std::string in = writeGeneric(dir, "scaled.exr", f.planes);
        const fs::path out = dir / "scaled_ao.exr";
        expectCleanFailure(cli(cat({in, "-o", out.string()}, cameraFlags(f.scene))), 1, out,
                           {"scaled.exr", "of a length outside 1e-6 to 1e19"});
        const CliResult r = cli(cat({in, "-o", out.string(), "--bad-pixels", "skip", "--out-type", "float"}, cameraFlags(f.scene)));
        expectSuccess(r, out);
        for (const float ao : aoValues(out.string())) ASSERT_TRUE(ao >= 0.0f && ao <= 1.0f) << ao;
        fs::remove(out);
    }
}

TEST(CliBadInput, OneByOneFrameWorks) {
    const fs::path dir = testDir();
    const fs::path in = dir / "one.exr", out = dir / "out.exr";
    FixturePart part;
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(0, 0));
    part.channels = {{"Z", Imf::FLOAT, 1, 1, [](int, int) { return 2.0f; }},
                     {"N.X", Imf::FLOAT, 1, 1, [](int, int) { return 0.0f; }},
                     {"N.Y", Imf::FLOAT, 1, 1, [](int, int) { return 0.0f; }},
                     {"N.Z", Imf::FLOAT, 1, 1, [](int, int) { return 1.0f; }}};
    writeFixture(in.string(), {part});
    const CliResult r = cli({in.string(), "-o", out.string(), "--fov-deg", "50", "--camera-to-world",
                             "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1"});
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    const ChannelData* ao = fd.find(0, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    ASSERT_EQ(ao->width * ao->height, 1);
    // A lone pixel has no neighbours to be occluded by.
    EXPECT_EQ(ao->at(0), 1.0f);
}

TEST(CliBadInput, EmptyDataWindowErrors) {
    const fs::path dir = testDir();
    const fs::path in = dir / "empty.exr", out = dir / "out.exr";
    bool written = false;
    try {
        FixturePart part;
        part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(-1, 11));
        part.channels = {{"Z", Imf::FLOAT, 1, 1, {}}, {"N.X", Imf::FLOAT, 1, 1, {}},
                         {"N.Y", Imf::FLOAT, 1, 1, {}}, {"N.Z", Imf::FLOAT, 1, 1, {}}};
        writeFixture(in.string(), {part});
        written = true;
    } catch (const std::exception&) {
    }
    if (!written) {
        // OpenEXR refuses to write a 0-area data window, so write a valid file and patch
        // its header: dataWindow (box2i, 16 bytes) gets xMax = xMin - 1.
        writeSimple(in.string(), {"Z", "N.X", "N.Y", "N.Z"}, 16, 12);
        std::string bytes = fileBytes(in);
        const std::string key("dataWindow\0box2i\0", 17);
        const size_t at = bytes.find(key);
        ASSERT_NE(at, std::string::npos);
        const size_t box = at + key.size() + 4;
        int xMin;
        std::memcpy(&xMin, &bytes[box], 4);
        const int xMax = xMin - 1;
        std::memcpy(&bytes[box + 8], &xMax, 4);
        std::ofstream(in, std::ios::binary | std::ios::trunc) << bytes;
    }
    const CliResult r = cli({in.string(), "-o", out.string(), "--fov-deg", "50", "--camera-to-world",
                             "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1"});
    expectCleanFailure(r, 1, out, {"empty.exr"});
}

// ---------------------------------------------------------------------------
// Usage errors: exit 2
// ---------------------------------------------------------------------------

struct UsageFixture : ::testing::Test {
    fs::path dir, out;
    std::string in;
    SceneBuffers scene = cornerScene(16, 12);
    void SetUp() override {
        dir = testDir();
        out = dir / "out.exr";
        in = writeGeneric(dir, "in.exr", planesOf(scene));
    }
};

TEST_F(UsageFixture, UnknownFlag) {
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--frobnicate"}, cameraFlags(scene))), 2, out,
                       {"--frobnicate"});
}

TEST_F(UsageFixture, FlagMissingItsValue) {
    expectCleanFailure(cli(cat(cat({in, "-o", out.string()}, cameraFlags(scene)), {"--radius"})), 2, out,
                       {"--radius"});
}

TEST_F(UsageFixture, BadNumber) {
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--radius", "abc"}, cameraFlags(scene))), 2, out,
                       {"--radius", "abc"});
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--directions", "4x"}, cameraFlags(scene))), 2, out,
                       {"--directions"});
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--radius", "nan"}, cameraFlags(scene))), 2, out,
                       {"--radius"});
}

// A value out of range is said as given (179.9999 is not "180"), with the range that holds; a
// sample count that leaves pixels of SSDO's interleave block without a sample is the request's
// fault, not the input's.
TEST_F(UsageFixture, AnOutOfRangeValueIsSaidWithItsRange) {
    expectCleanFailure(cli({in, "-o", out.string(), "--fov-deg", "179.9999"}), 2, out,
                       {"--fov-deg must be above 0 and at most 179.999, got 179.9999"});
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--thickness", "1e38"}, cameraFlags(scene))), 2, out,
                       {"--thickness must be between 0 and 1e+30, or auto, or inf"});
    const CliResult r = cli(cat({in, "-o", out.string(), "--method", "ssdo", "--samples", "2"}, cameraFlags(scene)));
    expectCleanFailure(r, 2, out, {"--samples 2 leaves pixels of the 2 x 2 --interleave block", "at least 4"});
    EXPECT_EQ(r.err.find("in.exr"), std::string::npos) << r.err;
}

// An output layer's name OpenEXR would cut (a view's channels then share one name) or that has an
// empty part is refused before anything is read.
TEST_F(UsageFixture, AnOutputLayerNameOpenExrCannotHoldIsRefused) {
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--out-layer", "ao=" + std::string(300, 'a')}, cameraFlags(scene))),
                       2, out, {"--out-layer ao: the name is 300 characters long; at most 200"});
    for (const std::string name : {"a..b", ".lead", "trail."})
        expectCleanFailure(cli(cat({in, "-o", out.string(), "--out-layer", "do=" + name}, cameraFlags(scene))), 2, out,
                           {"--out-layer do: the name '" + name + "' has an empty part"});
    const CliResult r = cli(cat({in, "-o", out.string(), "--out-layer", "ao=" + std::string(200, 'a')}, cameraFlags(scene)));
    EXPECT_EQ(r.exitCode, 0) << r.err;
}

TEST_F(UsageFixture, BadFramesListIsACommandLineError) {
    const std::string pattern = (dir / "in.####.exr").string(), outs = (dir / "out.####.exr").string();
    expectCleanFailure(cli({pattern, "-o", outs, "--frames", "5-1"}), 2, out, {"--frames", "'5-1' is an empty range"});
    expectCleanFailure(cli({pattern, "-o", outs, "--frames", "x"}), 2, out, {"--frames", "cannot read 'x'"});
}

TEST_F(UsageFixture, BadCameraMatrixCount) {
    expectCleanFailure(cli({in, "-o", out.string(), "--fov-deg", "70", "--camera-to-world", "1,0,0"}), 2, out,
                       {"--camera-to-world"});
}

// ---------------------------------------------------------------------------
// Output location
// ---------------------------------------------------------------------------

TEST_F(UsageFixture, OutputDirectoryMissing) {
    const fs::path missing = dir / "no_such_dir";
    const fs::path o = missing / "out.exr";
    const CliResult r = cli(cat({in, "-o", o.string()}, cameraFlags(scene)));
    expectCleanFailure(r, 1, o, {"no_such_dir"});
    EXPECT_FALSE(fs::exists(missing));
    EXPECT_EQ(tempLeftovers(dir), std::vector<std::string>{});
}

TEST_F(UsageFixture, OutputIsInputRefused) {
    const std::string before = fileBytes(in);
    const CliResult r = cli(cat({in, "-o", in}, cameraFlags(scene)));
    expectCleanFailure(r, 2, {}, {"--in-place"});
    EXPECT_TRUE(fileBytes(in) == before) << "input modified";
    // The same file under another spelling.
    const std::string alias = (dir / "." / "in.exr").string();
    const CliResult r2 = cli(cat({in, "-o", alias}, cameraFlags(scene)));
    expectCleanFailure(r2, 2, {}, {"--in-place"});
    EXPECT_TRUE(fileBytes(in) == before) << "input modified";
    EXPECT_EQ(tempLeftovers(dir), std::vector<std::string>{});
}

TEST_F(UsageFixture, InPlaceReplacesTheInput) {
    const FileData before = readAll(in);
    const CliResult r = cli(cat({in, "-o", in, "--in-place"}, cameraFlags(scene)));
    expectSuccess(r, in);
    const FileData after = readAll(in);
    expectChannelsKept(before, after);
    ASSERT_NE(after.find(0, "obscura.AO.Y"), nullptr);
    EXPECT_EQ(after.channels.size(), before.channels.size() + 1);
}

// A --report or --preview destination in a missing directory fails before anything is
// written: no OUTPUT.exr is left behind.
TEST_F(UsageFixture, ReportDirectoryMissingLeavesNoOutput) {
    const fs::path report = dir / "no_such_dir" / "r.json";
    const CliResult r = cli(cat({in, "-o", out.string(), "--report", report.string()}, cameraFlags(scene)));
    expectCleanFailure(r, 1, out, {"no_such_dir"});
}

TEST_F(UsageFixture, PreviewDirectoryMissingLeavesNoOutput) {
    const fs::path preview = dir / "no_such_dir" / "p.png";
    const CliResult r = cli(cat({in, "-o", out.string(), "--preview", preview.string()}, cameraFlags(scene)));
    expectCleanFailure(r, 1, out, {"no_such_dir"});
}
} // namespace
