// Multi-view (stereo) files (issue 28, item 5) and --inspect answering on any readable file
// (item 6). The plate is what a compositor is handed: RGBA + Z in half float, no normals, no
// camera, the data window a crop inside the display window, its background Z = 0 where alpha
// is 0; once with the views as channel names in one part (multiView attribute), once as a part
// per view (view attribute). Each view's AO must be exactly what the same run gives on a plain
// file holding only that view, and every input channel and part must come back unchanged.
#include "core/settings_schema.h"
#include "io/exr_file.h"
#include "io/views.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scratch.h"

#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <gtest/gtest.h>

#include <fstream>

#include <cmath>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::fixtures;
using obscura::test::CliResult;
using obscura::test::outcome;
using obscura::test::runObscura;
namespace fs = std::filesystem;

namespace {

const Imath::Box2i kDisplay(Imath::V2i(0, 0), Imath::V2i(63, 47));
const Imath::Box2i kData(Imath::V2i(4, 3), Imath::V2i(59, 43));  // a crop inside the display window
const std::vector<std::string> kViews = {"left", "right"};

// A ground plane receding up the frame and a box standing in front of it; the right eye sees
// them 3 pixels to the left. Left of x = 8 (in each eye) there is nothing: alpha 0, Z 0.
bool covered(int view, int x) { return x + 3 * view >= 8; }
float depthAt(int view, int x, int y) {
    if (!covered(view, x)) return 0.0f;
    const int xs = x + 3 * view;
    const bool box = xs >= 24 && xs < 36 && y >= 14 && y < 30;
    return 6.0f - 0.06f * (float)y - (box ? 1.5f : 0.0f);
}

// R, G, B, A and Z of one view, named with `prefix` ("" or "right.").
std::vector<FixtureChannel> plateChannels(int view, const std::string& prefix) {
    std::vector<FixtureChannel> out;
    for (int c = 0; c < 3; ++c)
        out.push_back({prefix + "RGB"[c], Imf::HALF, 1, 1,
                       [view, c](int x, int y) { return 0.125f * (float)((x + 2 * y + c + view) % 8); }});
    out.push_back({prefix + "A", Imf::HALF, 1, 1, [view](int x, int) { return covered(view, x) ? 1.0f : 0.0f; }});
    out.push_back({prefix + "Z", Imf::HALF, 1, 1, [view](int x, int y) { return depthAt(view, x, y); }});
    return out;
}

FixturePart platePart(const std::string& name) {
    FixturePart p;
    p.name = name;
    p.displayWindow = kDisplay;
    p.dataWindow = kData;
    return p;
}

// (a) One part: the left (default) view's channels unprefixed, the right's named right.*.
void writeViewsByName(const std::string& path) {
    FixturePart p = platePart("");
    p.channels = plateChannels(0, "");
    for (FixtureChannel& c : plateChannels(1, "right.")) p.channels.push_back(c);
    p.editHeader = [](Imf::Header& h) { Imf::addMultiView(h, Imf::StringVector(kViews.begin(), kViews.end())); };
    writeFixture(path, {p});
}

// (b) A part per view, each with its view attribute and the same channel names.
void writeViewsByPart(const std::string& path) {
    std::vector<FixturePart> parts;
    for (int v = 0; v < 2; ++v) {
        parts.push_back(platePart(kViews[v]));
        parts.back().channels = plateChannels(v, "");
        parts.back().stringAttributes["view"] = kViews[v];
    }
    writeFixture(path, parts);
}

// One view alone as a plain file: what that view's AO must equal.
void writeMono(const std::string& path, int view) {
    FixturePart p = platePart("");
    p.channels = plateChannels(view, "");
    writeFixture(path, {p});
}

std::vector<std::string> runFlags() { return {"--fov-deg", "40", "--device", "cpu", "--threads", "2", "--quiet"}; }

CliResult run(const std::string& in, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {in, "-o", out};
    for (const std::string& f : runFlags()) args.push_back(f);
    args.insert(args.end(), extra.begin(), extra.end());
    return runObscura(args);
}

std::string viewOf(const Imf::Header& h) { return h.hasView() ? h.view() : ""; }

// The values of `channel` in the part of `path` whose view attribute is `view` ("" for none);
// empty when there is no such part or channel.
std::vector<float> channelIn(const std::string& path, const std::string& view, const std::string& channel) {
    const ExrInfo info = readExrInfo(path);
    for (size_t p = 0; p < info.parts.size(); ++p)
        if (viewOf(info.parts[p].header) == view && info.parts[p].findChannel(channel) >= 0)
            return obscura::test::partChannel(path, (int)p, channel);
    return {};
}

// Every channel of every input part, in the output's part of the same index, with its type and
// the same values (every codec here is lossless), and each part's view attribute.
void expectInputKept(const std::string& in, const std::string& out) {
    const ExrInfo a = readExrInfo(in), b = readExrInfo(out);
    ASSERT_GE(b.parts.size(), a.parts.size());
    for (size_t p = 0; p < a.parts.size(); ++p) {
        EXPECT_EQ(viewOf(b.parts[p].header), viewOf(a.parts[p].header)) << "part " << p;
        for (const ExrChannel& ch : a.parts[p].channels) {
            const int i = b.parts[p].findChannel(ch.name);
            ASSERT_GE(i, 0) << ch.name << " of part " << p << " was dropped";
            EXPECT_EQ(b.parts[p].channels[i].type, ch.type) << ch.name;
            EXPECT_EQ(obscura::test::partChannel(out, (int)p, ch.name), obscura::test::partChannel(in, (int)p, ch.name))
                << ch.name << " of part " << p << " changed";
        }
    }
}

// The AO of each view of `out` (in its part, under its name) finite in [0, 1], not all 1, and
// equal to the AO of the same run on a file holding only that view.
void expectViewsAo(const fs::path& dir, const std::string& out, const std::vector<std::pair<std::string, std::string>>& where,
                   const std::vector<int>& views) {
    for (int v : views) {
        SCOPED_TRACE(kViews[v]);
        const std::string mono = (dir / ("mono_" + kViews[v] + ".exr")).string(), monoOut = mono + ".ao.exr";
        writeMono(mono, v);
        const CliResult r = run(mono, monoOut);
        ASSERT_EQ(r.exitCode, 0) << outcome(r);
        const std::vector<float> want = obscura::test::partChannel(monoOut, 0, "obscura.AO.Y");
        const std::vector<float> got = channelIn(out, where[v].first, where[v].second);
        ASSERT_EQ(got.size(), want.size()) << "no " << where[v].second << " in a part of view '" << where[v].first << "'";
        bool occluded = false;
        for (float a : got) {
            ASSERT_TRUE(std::isfinite(a) && a >= 0.0f && a <= 1.0f) << a;
            occluded |= a < 0.99f;
        }
        EXPECT_TRUE(occluded) << "the box occludes the ground: some AO must be below 1";
        EXPECT_EQ(got, want);
    }
}

TEST(ViewNames, FollowOpenExrsConvention) {
    EXPECT_EQ(channelView("Z", kViews), "left");  // no dot: the default view
    EXPECT_EQ(channelView("right.Z", kViews), "right");
    EXPECT_EQ(channelView("depth.right.Z", kViews), "right");  // layer.view.channel
    EXPECT_EQ(channelView("right.depth.Z", kViews), "right");  // the view as a prefix
    EXPECT_EQ(channelView("depth.Z", kViews), "");             // in no view
    EXPECT_EQ(nameInView("obscura.AO.Y", kViews, 1), "obscura.AO.right.Y");
    EXPECT_EQ(nameInView("obscura.AO.Y", kViews, 0), "obscura.AO.left.Y");
    EXPECT_EQ(nameInView("Z", kViews, 0), "Z");
    EXPECT_EQ(nameInView("Z", kViews, 1), "right.Z");
}

struct Case {
    const char* name;
    bool byPart;
    const char* write;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class Views : public ::testing::TestWithParam<Case> {};

// Where each view's AO is: by name, in the unviewed part(s) as layer.view.Y; by part, as
// obscura.AO.Y in a part carrying the view.
std::vector<std::pair<std::string, std::string>> aoPlaces(bool byPart) {
    if (byPart) return {{"left", "obscura.AO.Y"}, {"right", "obscura.AO.Y"}};
    return {{"", "obscura.AO.left.Y"}, {"", "obscura.AO.right.Y"}};
}

TEST_P(Views, EveryViewGetsItsAoAndTheInputIsKept) {
    const Case& c = GetParam();
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "plate.exr").string(), out = (dir / "plate_ao.exr").string();
    c.byPart ? writeViewsByPart(in) : writeViewsByName(in);
    const std::string report = (dir / "plate_ao.json").string();
    const CliResult r = run(in, out, {"--write", c.write, "--report", report});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    if (std::string(c.write) != "new") expectInputKept(in, out);
    expectViewsAo(dir, out, aoPlaces(c.byPart), {0, 1});
    // Each channel written, told apart where a part per view repeats the names.
    std::ifstream f(report);
    const nlohmann::json j = nlohmann::json::parse(f);
    EXPECT_EQ(j["written"], c.byPart ? nlohmann::json({"obscura.AO.Y", "obscura.AO.Y"})
                                     : nlohmann::json({"obscura.AO.left.Y", "obscura.AO.right.Y"}));
    EXPECT_EQ(j.contains("written_views"), c.byPart);
    if (c.byPart) {
        EXPECT_EQ(j["written_views"], nlohmann::json({"left", "right"}));
    }
    EXPECT_EQ(fileViews(readExrInfo(out)), kViews) << "a stereo-aware reader must still find both views";
}

TEST_P(Views, ViewRestrictsTheRunAndAViewNotInTheFileIsRefused) {
    const Case& c = GetParam();
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "plate.exr").string(), out = (dir / "right_ao.exr").string();
    c.byPart ? writeViewsByPart(in) : writeViewsByName(in);
    const CliResult r = run(in, out, {"--write", c.write, "--view", "right"});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    if (std::string(c.write) != "new") expectInputKept(in, out);
    expectViewsAo(dir, out, aoPlaces(c.byPart), {1});
    EXPECT_TRUE(channelIn(out, aoPlaces(c.byPart)[0].first, aoPlaces(c.byPart)[0].second).empty()) << "left was not asked for";

    const std::string never = (dir / "never.exr").string();
    const CliResult bad = run(in, never, {"--write", c.write, "--view", "middle"});
    EXPECT_EQ(bad.exitCode, 1) << outcome(bad);
    EXPECT_EQ(bad.err, "obscura: '" + in + "': no view 'middle'; the file's views: left, right\n");
    EXPECT_FALSE(fs::exists(never));
}

INSTANTIATE_TEST_SUITE_P(Plates, Views,
                         ::testing::Values(Case{"by_name_copy", false, "copy"}, Case{"by_name_new", false, "new"},
                                           Case{"by_name_append", false, "append"}, Case{"by_part_copy", true, "copy"},
                                           Case{"by_part_new", true, "new"}, Case{"by_part_append", true, "append"}),
                         [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

// The command `--inspect --json` gives for `in`, run.
CliResult runInspectCommand(const std::string& in, nlohmann::json& inspected) {
    const CliResult js = runObscura({in, "--inspect", "--json"});
    EXPECT_EQ(js.exitCode, 0) << outcome(js);
    inspected = nlohmann::json::parse(js.out);
    EXPECT_TRUE(inspected["command_args"].is_array()) << js.out;
    if (!inspected["command_args"].is_array()) return {};
    std::vector<std::string> args = inspected["command_args"];
    EXPECT_EQ(args.at(0), "obscura");
    args.erase(args.begin());
    return runObscura(args);
}

// --inspect describes the plate without a camera, and the command it prints runs.
TEST(Inspect, AnswersOnThePlateAndItsCommandRuns) {
    const fs::path dir = obscura::test::testDir("views");
    for (bool byPart : {false, true}) {
        SCOPED_TRACE(byPart ? "by part" : "by name");
        const std::string in = (dir / (byPart ? "parts.exr" : "names.exr")).string();
        byPart ? writeViewsByPart(in) : writeViewsByName(in);
        const CliResult text = runObscura({in, "--inspect"});
        ASSERT_EQ(text.exitCode, 0) << outcome(text);
        EXPECT_NE(text.out.find("normal: (not found) normals: reconstructed from depth"), std::string::npos) << text.out;
        EXPECT_NE(text.out.find("views:   left (default), right"), std::string::npos) << text.out;
        EXPECT_NE(text.out.find("camera:  none"), std::string::npos) << text.out;
        nlohmann::json j;
        const CliResult r = runInspectCommand(in, j);
        ASSERT_EQ(r.exitCode, 0) << outcome(r);
        EXPECT_EQ(j["views_processed"], nlohmann::json(kViews));
        EXPECT_EQ(j["depth_statistics"]["type"], "half");
        EXPECT_GT(j["depth_statistics"]["sky_share"].get<double>(), 0.0);  // Z = 0 where alpha is 0
        EXPECT_NE(text.out.find("run:     " + j["command"].get<std::string>()), std::string::npos);
        const std::string out = (dir / ((byPart ? "parts" : "names") + std::string("_ao.exr"))).string();
        expectInputKept(in, out);
        for (const auto& [view, channel] : aoPlaces(byPart)) EXPECT_FALSE(channelIn(out, view, channel).empty()) << channel;
    }
}

// A --view the plate lacks: --inspect names it as what stops a run, and describes the roles as
// the default view holds them (its depth is found), not as a file with no depth.
TEST(Inspect, NamesAViewTheFileLacks) {
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "names.exr").string();
    writeViewsByName(in);
    const CliResult r = runObscura({in, "--inspect", "--view", "middle"});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_NE(r.out.find("a run processes nothing (the problem below)"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("problem: '" + in + "': no view 'middle'; the file's views: left, right"), std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("depth: (not found)"), std::string::npos) << r.out;
}

// A --layer that names a layer of one view only (N.X holds no view by OpenEXR's rule, N.right.X
// the right view's): the view without it is named, and nothing is written, rather than the
// hero eye left without its AO. --inspect names the same problem and still finds the depth.
TEST(Views, ALayerOneViewLacksIsRefusedNamingTheView) {
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "normals_one_view.exr").string(), out = (dir / "never.exr").string();
    FixturePart p = platePart("");
    p.channels = plateChannels(0, "");
    for (FixtureChannel& c : plateChannels(1, "right.")) p.channels.push_back(c);
    for (const std::string prefix : {"N.", "N.right."})
        for (int c = 0; c < 3; ++c) p.channels.push_back({prefix + "XYZ"[c], Imf::HALF, 1, 1, [c](int, int) { return c == 1 ? 1.0f : 0.0f; }});
    p.editHeader = [](Imf::Header& h) { Imf::addMultiView(h, Imf::StringVector(kViews.begin(), kViews.end())); };
    writeFixture(in, {p});
    const CliResult r = run(in, out, {"--layer", "normal=N"});
    EXPECT_EQ(r.exitCode, 1) << outcome(r);
    EXPECT_EQ(r.err.rfind("obscura: '" + in + "': view 'left': --layer normal=N: no layer or channel 'N'", 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(out));
    const CliResult right = run(in, out, {"--layer", "normal=N", "--normals", "camera", "--view", "right"});
    EXPECT_EQ(right.exitCode, 0) << "the view that has it runs alone: " << outcome(right);
    const CliResult inspect = runObscura({in, "--inspect", "--layer", "normal=N"});
    EXPECT_NE(inspect.out.find("problem: '" + in + "': view 'left'"), std::string::npos) << inspect.out;
    EXPECT_EQ(inspect.out.find("depth: (not found)"), std::string::npos) << inspect.out;
}

// A part that prefixes its other views ("right.depth.Z") and leaves the default view's layers as
// they are ("depth.Z", of no view by OpenEXR's rule): the default view holds them, so both eyes
// get their AO, each equal to its own mono run's.
TEST(Views, ThePrefixedFormLeavesTheDefaultViewItsLayers) {
    const fs::path dir = obscura::test::testDir("views_prefixed");
    const std::string in = (dir / "prefixed.exr").string(), out = (dir / "prefixed_ao.exr").string();
    FixturePart p = platePart("");
    for (int v = 0; v < 2; ++v)
        for (FixtureChannel c : plateChannels(v, v == 0 ? "" : "right.")) {
            if (c.name.back() == 'Z') c.name.insert(c.name.size() - 1, "depth.");
            p.channels.push_back(c);
        }
    p.editHeader = [](Imf::Header& h) { Imf::addMultiView(h, Imf::StringVector(kViews.begin(), kViews.end())); };
    writeFixture(in, {p});
    const CliResult r = run(in, out);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_EQ(r.err.find("no depth of its own"), std::string::npos) << r.err;
    expectInputKept(in, out);
    expectViewsAo(dir, out, aoPlaces(false), {0, 1});
    // Run again on that output, which now also names layers OpenEXR's way (obscura.AO.left.Y):
    // the default view still holds its layers.
    const std::string again = (dir / "again.exr").string();
    const CliResult r2 = run(out, again);
    ASSERT_EQ(r2.exitCode, 0) << outcome(r2);
    EXPECT_EQ(r2.err.find("no depth of its own"), std::string::npos) << r2.err;
    expectViewsAo(dir, again, aoPlaces(false), {0, 1});
}

// Run again on its own output (a part per view, appended: each view's AO in a part of its own,
// obscura.left and obscura.right), a copy replaces each view's AO in the part that holds it: the
// warning names each view once, and no part is added.
TEST(Views, ARunAgainReplacesEachViewsAo) {
    const fs::path dir = obscura::test::testDir("views_again");
    const std::string in = (dir / "plate.exr").string(), first = (dir / "first.exr").string();
    writeViewsByPart(in);
    ASSERT_EQ(run(in, first, {"--write", "append"}).exitCode, 0);
    const std::string again = (dir / "again.exr").string();
    const CliResult r = runObscura({first, "-o", again, "--fov-deg", "40", "--device", "cpu", "--radius", "0.5"});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_NE(r.err.find("the input already holds obscura.AO.Y (view left), obscura.AO.Y (view right); the output's "
                         "new layers replace them"),
              std::string::npos) << r.err;
    const ExrInfo a = readExrInfo(first), b = readExrInfo(again);
    EXPECT_EQ(b.parts.size(), a.parts.size());
    for (const std::string& view : kViews) {
        int parts = 0;
        for (const ExrPart& part : b.parts) parts += viewOf(part.header) == view && part.findChannel("obscura.AO.Y") >= 0;
        EXPECT_EQ(parts, 1) << view;
        EXPECT_NE(channelIn(again, view, "obscura.AO.Y"), channelIn(first, view, "obscura.AO.Y")) << "R 0.5 is not R 1";
    }
}

// A view whose own channels hold no depth gets no AO, and the run says so while the others get
// theirs (three views, the middle one with colour only).
TEST(Views, AViewWithoutADepthIsSaid) {
    const fs::path dir = obscura::test::testDir("views_center");
    const std::string in = (dir / "three.exr").string(), out = (dir / "three_ao.exr").string();
    FixturePart p = platePart("");
    p.channels = plateChannels(0, "");
    for (FixtureChannel& c : plateChannels(1, "right.")) p.channels.push_back(c);
    for (FixtureChannel& c : plateChannels(0, "center."))
        if (c.name != "center.Z") p.channels.push_back(c);
    p.editHeader = [](Imf::Header& h) { Imf::addMultiView(h, Imf::StringVector{"left", "right", "center"}); };
    writeFixture(in, {p});
    const CliResult r = runObscura({in, "-o", out, "--fov-deg", "40", "--device", "cpu", "--threads", "2"});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_NE(r.err.find("warning: view 'center' has no depth of its own and gets no AO; its layers: (top level) (R,G,B,A) half"),
              std::string::npos) << r.err;
    EXPECT_GE(channelIn(out, "", "obscura.AO.right.Y").size(), 1u);
    EXPECT_TRUE(channelIn(out, "", "obscura.AO.center.Y").empty());
}

// A depth under a name no preset knows: --inspect says so and its command takes it.
TEST(Inspect, TakesADepthUnderAnUnknownName) {
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "odd.exr").string();
    writeSimple(in, {"R", "G", "B", "A", "zdepth.V"});
    nlohmann::json j;
    const CliResult r = runInspectCommand(in, j);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_TRUE(j["roles"]["depth"].is_null());
    EXPECT_EQ(j["command_args"][4], "--layer");
    EXPECT_EQ(j["command_args"][5], "depth=zdepth.V");
    EXPECT_GE(obscura::test::partChannel((dir / "odd_ao.exr").string(), 0, "obscura.AO.Y").size(), 1u);
}

// The command never replaces an earlier output: with odd_ao.exr there it writes odd_ao_2.exr,
// and says why; the earlier output is left as it was.
TEST(Inspect, CommandWritesBesideAnEarlierOutput) {
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "odd.exr").string(), earlier = (dir / "odd_ao.exr").string();
    writeSimple(in, {"R", "G", "B", "A", "Z"});
    writeSimple(earlier, {"R", "G", "B", "A", "Z"});
    const auto before = fs::last_write_time(earlier);
    nlohmann::json j;
    const CliResult r = runInspectCommand(in, j);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    const std::string second = (dir / "odd_ao_2.exr").string();
    EXPECT_EQ(j["command_args"][3], second) << j.dump();
    EXPECT_NE(j["command_notes"].dump().find("odd_ao.exr exists; the command writes " + second), std::string::npos)
        << j.dump();
    EXPECT_EQ(fs::last_write_time(earlier), before);
    EXPECT_GE(obscura::test::partChannel(second, 0, "obscura.AO.Y").size(), 1u);
    // A frame of a sequence keeps its number last.
    const std::string frame = (dir / "odd.1001.exr").string();
    fs::copy_file(in, frame);
    const CliResult f = runObscura({frame, "--inspect", "--json"});
    ASSERT_EQ(f.exitCode, 0) << outcome(f);
    EXPECT_EQ(nlohmann::json::parse(f.out)["command_args"][3], (dir / "odd_ao.1001.exr").string()) << f.out;
}

// A file with no depth at all still gets an answer: what is missing, and why no command runs.
TEST(Inspect, AnswersOnAFileWithoutDepth) {
    const fs::path dir = obscura::test::testDir("views");
    const std::string in = (dir / "rgba.exr").string();
    writeSimple(in, {"R", "G", "B", "A"});
    const CliResult r = runObscura({in, "--inspect"});
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_NE(r.out.find("depth: (not found) missing: obscura needs a depth layer"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("run:     no command can run on this file"), std::string::npos) << r.out;
    const CliResult unreadable = runObscura({(dir / "absent.exr").string(), "--inspect"});
    EXPECT_EQ(unreadable.exitCode, 1) << outcome(unreadable);
    // Only a file that cannot be read is an error: pixels cut off are one.
    const std::string plate = (dir / "plate.exr").string(), cut = (dir / "cut.exr").string();
    writeViewsByName(plate);
    truncatedCopy(plate, cut, fileSize(plate) - 64);
    const CliResult truncated = runObscura({cut, "--inspect"});
    EXPECT_EQ(truncated.exitCode, 1) << outcome(truncated);
    EXPECT_NE(truncated.err.find("truncated or corrupt"), std::string::npos) << truncated.err;
}

// --view comes from core's table of name settings: the CLI spells it and refuses what the table
// refuses; on a file without views --inspect still answers, naming the problem.
TEST(ViewSetting, TheCliTakesItFromTheTable) {
    const std::string room = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";
    for (const NameListSetting& s : nameListSettings()) {
        SCOPED_TRACE(s.flag);
        const CliResult twice = runObscura({room, "--inspect", s.flag, "a,a"});
        EXPECT_EQ(twice.exitCode, 2) << outcome(twice);
        EXPECT_EQ(twice.err, "obscura: " + nameListProblem(s, {"a", "a"}, Spelling::Flag) + "\n");
        const CliResult empty = runObscura({room, "--inspect", s.flag, "a,"});
        EXPECT_EQ(empty.exitCode, 2) << outcome(empty);
    }
    const CliResult none = runObscura({room, "--inspect", "--view", "left"});
    EXPECT_EQ(none.exitCode, 0) << outcome(none);
    EXPECT_NE(none.out.find("problem: '" + room + "': no view 'left'; the file has no views"), std::string::npos) << none.out;
}

} // namespace
