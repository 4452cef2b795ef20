// The obscura CLI end to end on good input: the room sample, presets == runOperator, file layouts, --layer, startup.
#include "core/camera.h"
#include "core/operator.h"
#include "io/camera_sources.h"
#include "io/exr_file.h"
#include "support/cli_fixtures.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <Imath/half.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <regex>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using namespace obscura::test;

namespace {

const std::string kData = OBSCURA_TEST_DATA_DIR;
const std::string kRoom = kData + "/room.exr";

void roundToHalf(Image& img) {
    for (float& v : img.pixels) v = float(half(v));
}

// World normals -> OpenGL camera-space normals of `cam`.
Image toCameraNormals(const Image& world, const Camera& cam) {
    Image out = world;
    const glm::dmat3 worldToCam = glm::transpose(glm::dmat3(cam.cameraToWorld));
    for (size_t i = 0; i + 2 < out.pixels.size(); i += 3) {
        const glm::dvec3 n = worldToCam * glm::dvec3(world.pixels[i], world.pixels[i + 1], world.pixels[i + 2]);
        for (int c = 0; c < 3; ++c) out.pixels[i + c] = (float)n[c];
    }
    return out;
}

// What runOperator gives on these planes with the camera the CLI flags describe.
Image expectedAo(const Planes& p, const Image& operatorNormals, NormalSpace space, const SceneBuffers& scene,
                 const Settings& settings) {
    CameraRequest req;
    req.fovDeg = kFovDeg;
    req.cameraToWorld = rowMajor(scene.camera.cameraToWorld);
    const Camera cam = resolveCamera(req, nullptr, ConstPlane{}, p.data, p.display, 1.0);
    // The flags describe the scene's camera (so the comparison is about the right camera).
    EXPECT_NEAR(cam.fx, scene.camera.fx, 1e-9 * scene.camera.fx);
    EXPECT_NEAR(cam.cx, scene.camera.cx, 1e-9);
    OperatorInputs in;
    in.displayWindow = p.display;
    in.dataWindow = p.data;
    in.depth = p.depth.view();
    in.normal = operatorNormals.view();
    in.depthKind = DepthKind::Planar;
    in.normalSpace = space;
    in.camera = cam;
    return runOperator(in, settings).ao;
}

// CLI flags and the Settings they mean, for the bit-exact comparisons.
const std::vector<std::string> kOpFlags = {"--radius", "1.5", "--directions", "6", "--steps", "4", "--threads", "2",
                                           "--out-type", "float"};
Settings opSettings() {
    Settings s;
    s.radius = 1.5f;
    s.directions = 6;
    s.steps = 4;
    s.threads = 2;
    s.skyDepth = 1e9f;
    return s;
}

// AO bit-identical to `expected`, and not trivial: occluded somewhere, exactly 1 on the sky.
void expectAoEquals(const ChannelData& ao, const Image& expected, const Image& depth) {
    ASSERT_EQ(ao.type, Imf::FLOAT);
    ASSERT_EQ(ao.width, expected.width);
    ASSERT_EQ(ao.height, expected.height);
    const std::vector<float> got = ao.floats();
    size_t mismatches = 0, first = 0;
    float maxDiff = 0, minAo = 2;
    long long sky = 0;
    for (size_t i = 0; i < got.size(); ++i) {
        if (std::memcmp(&got[i], &expected.pixels[i], sizeof(float)) != 0) {
            if (mismatches++ == 0) first = i;
            maxDiff = std::max(maxDiff, std::abs(got[i] - expected.pixels[i]));
        }
        if (depth.pixels[i] >= 1e9f) {
            ++sky;
            EXPECT_EQ(got[i], 1.0f) << "sky pixel " << i;
        } else {
            minAo = std::min(minAo, got[i]);
        }
    }
    EXPECT_EQ(mismatches, 0u) << "first at index " << first << " (x " << first % ao.width << ", y "
                              << first / ao.width << "): " << got[first] << " vs " << expected.pixels[first]
                              << "; max diff " << maxDiff
                              << " (if tiny: were obscura and test_cli linked against the same kernel build?)";
    EXPECT_GT(sky, 0) << "test scene should show some sky";
    EXPECT_LT(minAo, 0.9f) << "test scene should have occluded pixels";
}

// ---------------------------------------------------------------------------
// 2. Happy paths on the real Blender sample
// ---------------------------------------------------------------------------

// Output keeps every input channel bit-identical and adds a sane, non-trivial AO.
void checkRoomOutput(const std::string& in, const std::string& out, const std::string& aoName, Imf::PixelType type) {
    const FileData a = readAll(in), b = readAll(out);
    expectChannelsKept(a, b);
    EXPECT_EQ(b.channels.size(), a.channels.size() + 1);
    const ChannelData* ao = b.find(0, aoName);
    ASSERT_NE(ao, nullptr) << aoName;
    EXPECT_EQ(ao->type, type);
    const std::vector<float> v = ao->floats();
    const std::vector<float> depth = a.find(0, "ViewLayer.Depth.Z")->floats();
    ASSERT_EQ(v.size(), depth.size());
    long long sky = 0, occluded = 0;
    for (size_t i = 0; i < v.size(); ++i) {
        ASSERT_TRUE(v[i] >= 0.0f && v[i] <= 1.0f) << i << ": " << v[i];
        if (depth[i] >= 1e9f) {
            ++sky;
            ASSERT_EQ(v[i], 1.0f) << "sky pixel " << i;
        } else if (v[i] < 0.9f) {
            ++occluded;
        }
    }
    EXPECT_GT(sky, 0);
    EXPECT_GT(occluded, 100) << "the room's corners should be occluded";
}

TEST(CliSamples, RoomWithSidecar) {
    const fs::path dir = testDir();
    const fs::path out = dir / "room_ao.exr";
    const CliResult r = cli({kRoom, "-o", out.string(), "--radius", "1"});
    expectSuccess(r, out);
    EXPECT_TRUE(contains(r.err, "camera from sidecar:")) << r.err;
    checkRoomOutput(kRoom, out.string(), "obscura.AO.Y", Imf::HALF);
}

TEST(CliSamples, RoomWithoutSidecarFitsTheCamera) {
    const fs::path dir = testDir();
    const fs::path in = dir / "room.exr", out = dir / "room_ao.exr";
    fs::copy_file(kRoom, in);
    const CliResult r = cli({in.string(), "-o", out.string(), "--radius", "1", "--out-type", "float"});
    expectSuccess(r, out);
    EXPECT_TRUE(contains(r.err, "camera from fit:position")) << r.err;
    checkRoomOutput(in.string(), out.string(), "obscura.AO.Y", Imf::FLOAT);
}

TEST(CliSamples, ReferenceMetrics) {
    const fs::path dir = testDir();
    const fs::path out = dir / "room_ao.exr";
    const CliResult r = cli({kRoom, "-o", out.string(), "--reference", "ViewLayer.AO", "--weighting", "cosine",
                             "--falloff", "none", "--radius", "1"});
    expectSuccess(r, out);
    const std::regex line(R"(reference ViewLayer\.AO: MAE ([0-9.eE+-]+) +RMSE ([0-9.eE+-]+) +PSNR ([0-9.eE+-]+) dB +p99 ([0-9.eE+-]+))");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, line)) << describe(r);
    const double mae = std::stod(m[1]), rmse = std::stod(m[2]), psnr = std::stod(m[3]), p99 = std::stod(m[4]);
    EXPECT_GT(psnr, 15.0) << r.out;
    EXPECT_GT(mae, 0.0);
    EXPECT_LE(mae, rmse);
    EXPECT_GE(p99, 0.0);
    EXPECT_LE(p99, 1.0);
    EXPECT_NEAR(psnr, -20.0 * std::log10(rmse), 0.05) << "PSNR inconsistent with RMSE (peak 1)";
}

TEST(CliSamples, ReportJson) {
    const fs::path dir = testDir();
    const fs::path out = dir / "room_ao.exr", report = dir / "r.json";
    const CliResult r = cli({kRoom, "-o", out.string(), "--radius", "1", "--directions", "3", "--steps", "2",
                             "--weighting", "cosine", "--report", report.string()});
    expectSuccess(r, out);
    ASSERT_TRUE(fs::exists(report));
    nlohmann::json j;
    ASSERT_NO_THROW(j = nlohmann::json::parse(fileBytes(report))) << fileBytes(report);
    for (const char* stage : {"read", "compute", "write"}) {
        ASSERT_TRUE(j["timings_s"].contains(stage)) << j.dump(2);
        ASSERT_TRUE(j["timings_s"][stage].is_number()) << stage;
        EXPECT_GE(j["timings_s"][stage].get<double>(), 0.0) << stage;
    }
    EXPECT_EQ(j["settings"]["radius"].get<double>(), 1.0);
    EXPECT_EQ(j["settings"]["directions"].get<int>(), 3);
    EXPECT_EQ(j["settings"]["steps"].get<int>(), 2);
    EXPECT_EQ(j["settings"]["weighting"].get<std::string>(), "cosine");
    EXPECT_EQ(j["settings"]["method"].get<std::string>(), "hbao");
    EXPECT_EQ(j["camera"]["source"].get<std::string>().rfind("sidecar:", 0), 0u) << j["camera"].dump();
    EXPECT_EQ(j["camera"]["projection"].get<std::string>(), "perspective");
    EXPECT_EQ(j["output_channels"]["ao"].get<std::string>(), "obscura.AO.Y");
    EXPECT_EQ(j["stats"]["pixels"].get<long long>(), 320LL * 320);
    EXPECT_GT(j["stats"]["sky_pixels"].get<long long>(), 0);
    EXPECT_EQ(tempLeftovers(dir), std::vector<std::string>{});
}

// The settings a --report records for these flags (room.exr, its sidecar's camera).
nlohmann::json reportedSettings(const std::vector<std::string>& flags) {
    const fs::path dir = testDir();
    const fs::path out = dir / "room_ao.exr", report = dir / "r.json";
    std::vector<std::string> args = {kRoom, "-o", out.string(), "--report", report.string(), "--quiet"};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliResult r = cli(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return fs::exists(report) ? nlohmann::json::parse(fileBytes(report))["settings"] : nlohmann::json{};
}

// --quality sets what the flags do not, wherever it stands; ssdo's levels are its sample counts
// (the report's presets) and keep its blur as wide as the interleaving block.
TEST(CliSamples, QualityLevelsUnderTheFlags) {
    for (const auto& [level, samples] : std::vector<std::pair<std::string, int>>{{"low", 16}, {"medium", 64},
                                                                                {"high", 256}, {"ultra", 1024}}) {
        const nlohmann::json s = reportedSettings({"--method", "ssdo", "--quality", level});
        EXPECT_EQ(s["ssdo"]["samples"].get<int>(), samples) << level;
        EXPECT_EQ(s["blur"].get<int>(), 2) << level << ": the interleaving block, not hbao's level blur";
    }
    EXPECT_EQ(reportedSettings({"--quality", "low", "--method", "ssdo", "--samples", "32"})["ssdo"]["samples"], 32);
    EXPECT_EQ(reportedSettings({"--samples", "32", "--quality", "low", "--method", "ssdo"})["ssdo"]["samples"], 32);
    for (const auto& flags : std::vector<std::vector<std::string>>{{"--blur", "3", "--directions", "5", "--quality", "low"},
                                                                   {"--quality", "low", "--blur", "3", "--directions", "5"}}) {
        const nlohmann::json s = reportedSettings(flags);
        EXPECT_EQ(s["blur"].get<int>(), 3);
        EXPECT_EQ(s["directions"].get<int>(), 5);
        EXPECT_EQ(s["steps"].get<int>(), 4) << "the level's, where no flag was given";
    }
    EXPECT_EQ(reportedSettings({"--quality", "high"})["blur"].get<int>(), 0);
    EXPECT_EQ(reportedSettings({})["blur"].get<int>(), 1);
}

// The report records what the method reads: no hbao settings for ssdo, the bounce for hbao.
TEST(CliSamples, ReportHoldsWhatTheMethodReads) {
    const nlohmann::json ssdo = reportedSettings({"--method", "ssdo"});
    for (const char* key : {"directions", "steps", "weighting", "falloff", "thickness"})
        EXPECT_FALSE(ssdo.contains(key)) << key << " in " << ssdo.dump();
    const nlohmann::json lit = reportedSettings({"--bounce", "--bounce-source", "beauty"});
    EXPECT_TRUE(lit["bounce"].get<bool>()) << lit.dump();
    EXPECT_EQ(lit["bounce_source"].get<std::string>(), "beauty");
    EXPECT_FALSE(reportedSettings({})["bounce"].get<bool>());
}

// Run again on its own output, obscura says what becomes of the earlier AO: replaced (copy), or
// kept beside the new one (append); under another name nothing is said.
TEST(CliSamples, SaysWhenTheInputHoldsTheNewLayers) {
    const fs::path dir = testDir();
    const std::string first = (dir / "first.exr").string(), sidecar = (dir / "first.json").string();
    ASSERT_EQ(cli({kRoom, "-o", first, "--quiet"}).exitCode, 0);
    fs::copy_file(kData + "/room.json", sidecar);
    const CliResult copy = cli({first, "-o", (dir / "again.exr").string()});
    EXPECT_EQ(copy.exitCode, 0) << copy.err;
    EXPECT_NE(copy.err.find("warning: the input already holds obscura.AO.Y; the output's new layers replace them"),
              std::string::npos) << copy.err;
    const CliResult append = cli({first, "-o", (dir / "both.exr").string(), "--write", "append"});
    EXPECT_NE(append.err.find("the output holds both, in different parts"), std::string::npos)
        << append.err;
    // Copied again, the appended file's AO in the depth's part is replaced there and the one in
    // its own part stays beside it; run in place again and again (a farm's re-run), the file
    // keeps its parts and its two AOs.
    fs::copy_file(kData + "/room.json", dir / "both.json");
    const CliResult again = cli({(dir / "both.exr").string(), "-o", (dir / "third.exr").string()});
    EXPECT_NE(again.err.find("the output holds both"), std::string::npos) << again.err;
    auto shape = [](const std::string& path) {  // parts, and the parts holding an AO
        const ExrInfo info = readExrInfo(path);
        int aos = 0;
        for (const ExrPart& part : info.parts) aos += part.findChannel("obscura.AO.Y") >= 0 ? 1 : 0;
        return std::pair<size_t, int>{info.parts.size(), aos};
    };
    const std::string both = (dir / "both.exr").string();
    const std::pair<size_t, int> before = shape(both);
    EXPECT_EQ(before.second, 2);
    EXPECT_EQ(shape((dir / "third.exr").string()), before);
    for (int run = 0; run < 2; ++run) {
        const CliResult inPlace = cli({both, "-o", both, "--in-place", "--quiet"});
        ASSERT_EQ(inPlace.exitCode, 0) << inPlace.err;
        EXPECT_EQ(shape(both), before) << "run " << run << " in place added a part or an AO";
    }
    const CliResult apart = cli({first, "-o", (dir / "apart.exr").string(), "--out-layer", "ao=second"});
    EXPECT_EQ(apart.err.find("already holds"), std::string::npos) << apart.err;
    // A setting only deep input reads, on a flat file: said to be unread.
    const CliResult layers = cli({kRoom, "-o", (dir / "layers.exr").string(), "--deep-layers", "2"});
    EXPECT_EQ(layers.exitCode, 0) << layers.err;
    EXPECT_NE(layers.err.find("warning: the deep layers setting is read with deep input only"), std::string::npos)
        << layers.err;
}

TEST(CliSamples, InspectWritesNothing) {
    const fs::path dir = testDir();
    fs::copy_file(kRoom, dir / "room.exr");
    fs::copy_file(kData + "/room.json", dir / "room.json");
    const CliResult r = cli({(dir / "room.exr").string(), "--inspect"});
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    for (const char* layer : {"ViewLayer.Depth (Z)", "ViewLayer.Normal (X,Y,Z)", "ViewLayer.Position (X,Y,Z)",
                              "ViewLayer.Combined (R,G,B,A)", "ViewLayer.AO (R,G,B)", "ViewLayer.DiffInd"})
        EXPECT_TRUE(contains(r.out, layer)) << layer << " not in:\n" << r.out;
    EXPECT_TRUE(contains(r.out, "preset:  blender")) << r.out;
    EXPECT_TRUE(contains(r.out, "depth: ViewLayer.Depth.Z")) << r.out;
    EXPECT_TRUE(contains(r.out, "normal: ViewLayer.Normal.X, ViewLayer.Normal.Y, ViewLayer.Normal.Z")) << r.out;
    EXPECT_TRUE(contains(r.out, "position: ViewLayer.Position.X")) << r.out;
    EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(camera: +perspective, horizontal fov 50\.69[0-9]* deg, from sidecar:)")))
        << r.out;
    std::set<std::string> files;
    for (const auto& e : fs::directory_iterator(dir)) files.insert(e.path().filename().string());
    EXPECT_EQ(files, (std::set<std::string>{"room.exr", "room.json"}));
}

TEST(CliMisc, OutLayerName) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(32, 24);
    const std::string in = writeGeneric(dir, "in.exr", planesOf(s));
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string(), "--out-layer", "ao=MyAO"}, cameraFlags(s)));
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    const ChannelData* ao = fd.find(0, "MyAO.Y");
    ASSERT_NE(ao, nullptr);
    EXPECT_EQ(ao->type, Imf::HALF);
    EXPECT_EQ(fd.find(0, "obscura.AO.Y"), nullptr);
    expectChannelsKept(readAll(in), fd);
}

TEST(CliMisc, HelpMentionsEveryFlag) {
    const CliResult r = cli({"--help"});
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    for (const char* flag : {"-o", "--method", "--radius", "--directions", "--steps", "--weighting", "--falloff",
                             "--fov-deg", "--ortho-width", "--camera-to-world", "--depth", "--normals", "--layer",
                             "--out-layer", "--device", "--threads", "--report", "--reference"})
        EXPECT_TRUE(std::regex_search(r.out, std::regex(std::string("\n  ") + flag + "( |\n)")))
            << flag << " not in --help:\n" << r.out;
}

// ---------------------------------------------------------------------------
// 3. Presets end to end: the CLI's AO == runOperator on the same planes and camera
// ---------------------------------------------------------------------------

struct PresetCase {
    std::string preset;
    Naming naming;
    NormalSpace space;
    bool leftHanded;
};

std::ostream& operator<<(std::ostream& os, const PresetCase& c) { return os << c.preset; }

class CliPresets : public ::testing::TestWithParam<PresetCase> {};

TEST_P(CliPresets, AoMatchesOperator) {
    const PresetCase& pc = GetParam();
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    Planes file = planesOf(s);
    Image opNormals = file.normal;
    if (pc.space == NormalSpace::Camera) {
        opNormals = toCameraNormals(file.normal, s.camera);
        file.normal = opNormals;
        if (pc.leftHanded)
            for (size_t i = 2; i < file.normal.pixels.size(); i += 3) file.normal.pixels[i] = -file.normal.pixels[i];
    }
    const std::string in = (dir / "in.exr").string();
    writeFixture(in, {makePart(file, pc.naming)});

    const CliResult inspect = cli({in, "--inspect"});
    ASSERT_EQ(inspect.exitCode, 0) << describe(inspect);
    EXPECT_TRUE(contains(inspect.out, "preset:  " + pc.preset + "\n")) << inspect.out;

    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat(cat({in, "-o", out.string()}, cameraFlags(s)), kOpFlags));
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    expectChannelsKept(readAll(in), fd);
    const ChannelData* ao = fd.find(0, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    expectAoEquals(*ao, expectedAo(file, opNormals, pc.space, s, opSettings()), file.depth);
}

INSTANTIATE_TEST_SUITE_P(
    Renderers, CliPresets,
    ::testing::Values(
        PresetCase{"generic", kGeneric, NormalSpace::World, false},
        PresetCase{"blender",
                   {"ViewLayer.Depth.Z",
                    {"ViewLayer.Normal.X", "ViewLayer.Normal.Y", "ViewLayer.Normal.Z"},
                    {"ViewLayer.Position.X", "ViewLayer.Position.Y", "ViewLayer.Position.Z"},
                    {"ViewLayer.Combined.R", "ViewLayer.Combined.G", "ViewLayer.Combined.B", "ViewLayer.Combined.A"},
                    {{"software", "Blender 3.4.1"}}},
                   NormalSpace::World, false},
        PresetCase{"arnold",
                   {"Z", {"N.R", "N.G", "N.B"}, {"P.R", "P.G", "P.B"}, {"R", "G", "B", "A"},
                    {{"arnold/version", "7.1.4"}}},
                   NormalSpace::World, false},
        PresetCase{"renderman",
                   {"z", {"Nn.r", "Nn.g", "Nn.b"}, {"__Pworld.r", "__Pworld.g", "__Pworld.b"}, {"Ci.r", "Ci.g", "Ci.b"},
                    {{"software", "RenderMan 25"}}},
                   NormalSpace::Camera, true},
        PresetCase{"vray",
                   {"Z", {"VRayNormals.R", "VRayNormals.G", "VRayNormals.B"}, {}, {"R", "G", "B"},
                    {{"software", "vray 6"}}},
                   NormalSpace::Camera, false},
        PresetCase{"karma",
                   {"depth.Z", {"N.X", "N.Y", "N.Z"}, {"P.X", "P.Y", "P.Z"}, {"C.R", "C.G", "C.B", "C.A"},
                    {{"software", "Houdini Karma"}}},
                   NormalSpace::World, false}),
    [](const ::testing::TestParamInfo<PresetCase>& i) { return i.param.preset; });

TEST(CliFileLayout, MultipartTiledHalf) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    Planes file = planesOf(s);
    roundToHalf(file.depth);
    roundToHalf(file.normal);
    roundToHalf(file.position);
    FixturePart beauty;
    beauty.name = "rgba";
    beauty.displayWindow = beauty.dataWindow = toImath(file.data);
    beauty.channels = {{"R", Imf::HALF, 1, 1, {}}, {"G", Imf::HALF, 1, 1, {}}, {"B", Imf::HALF, 1, 1, {}}};
    Naming aux = kGeneric;
    aux.beauty.clear();
    FixturePart aovs = makePart(file, aux, Imf::HALF);
    aovs.name = "aovs";
    aovs.tiled = true;
    aovs.tileWidth = 16;
    aovs.tileHeight = 16;
    aovs.compression = Imf::PIZ_COMPRESSION;
    const std::string in = (dir / "in.exr").string();
    writeFixture(in, {beauty, aovs});

    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat(cat({in, "-o", out.string()}, cameraFlags(s)), kOpFlags));
    expectSuccess(r, out);
    const FileData before = readAll(in), fd = readAll(out.string());
    expectChannelsKept(before, fd);
    ASSERT_EQ(fd.tiled, (std::vector<bool>{false, true}));
    EXPECT_EQ(fd.find(0, "obscura.AO.Y"), nullptr) << "AO belongs in the part holding depth";
    const ChannelData* ao = fd.find(1, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    expectAoEquals(*ao, expectedAo(file, file.normal, NormalSpace::World, s, opSettings()), file.depth);
}

TEST(CliFileLayout, OverscanDataWindow) {
    const fs::path dir = testDir();
    const Box2i display{0, 0, 64, 48}, data{-8, -6, 72, 54};
    const SceneBuffers s = cornerScene(display, data);
    const Planes file = planesOf(s);
    const std::string in = writeGeneric(dir, "in.exr", file);

    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat(cat({in, "-o", out.string()}, cameraFlags(s)), kOpFlags));
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    expectChannelsKept(readAll(in), fd);
    EXPECT_EQ(fd.dataWindows[0], toImath(data));
    EXPECT_EQ(fd.displayWindows[0], toImath(display));
    const ChannelData* ao = fd.find(0, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    ASSERT_EQ(ao->width, data.width());
    ASSERT_EQ(ao->height, data.height());
    expectAoEquals(*ao, expectedAo(file, file.normal, NormalSpace::World, s, opSettings()), file.depth);
    // Computed in the overscan band too, not only inside the display window.
    long long overscanOccluded = 0, overscanSurface = 0;
    const std::vector<float> v = ao->floats();
    for (int y = 0; y < data.height(); ++y)
        for (int x = 0; x < data.width(); ++x) {
            if (display.contains(x + data.x0, y + data.y0) || *file.depth.at(x, y) >= 1e9f) continue;
            ++overscanSurface;
            if (v[(size_t)y * data.width() + x] < 0.95f) ++overscanOccluded;
        }
    EXPECT_GT(overscanSurface, 0);
    EXPECT_GT(overscanOccluded, 0) << "no occlusion computed outside the display window";
}

// ---------------------------------------------------------------------------
// 4. --layer overrides
// ---------------------------------------------------------------------------

const Naming kOdd = {"CamDist.Y", {"Nrm.X", "Nrm.Y", "Nrm.Z"}, {}, {"R", "G", "B"}, {}};

TEST(CliLayers, OverrideFindsNonStandardNames) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(64, 48);
    const Planes file = planesOf(s);
    const std::string in = (dir / "in.exr").string();
    writeFixture(in, {makePart(file, kOdd)});
    const fs::path out = dir / "out.exr";

    // Without the overrides there is no depth.
    expectCleanFailure(cli(cat({in, "-o", out.string()}, cameraFlags(s))), 1, out, {"no depth layer", "CamDist"});

    const CliResult r = cli(cat(cat({in, "-o", out.string(), "--layer", "depth=CamDist", "--layer", "normal=Nrm"},
                                    cameraFlags(s)),
                                kOpFlags));
    expectSuccess(r, out);
    const FileData fd = readAll(out.string());
    expectChannelsKept(readAll(in), fd);
    const ChannelData* ao = fd.find(0, "obscura.AO.Y");
    ASSERT_NE(ao, nullptr);
    expectAoEquals(*ao, expectedAo(file, file.normal, NormalSpace::World, s, opSettings()), file.depth);
}

TEST(CliLayers, BadOverrideNamesTheLayersFound) {
    const fs::path dir = testDir();
    const SceneBuffers s = cornerScene(16, 12);
    const std::string in = (dir / "in.exr").string();
    writeFixture(in, {makePart(planesOf(s), kOdd)});
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string(), "--layer", "depth=Distance", "--layer", "normal=Nrm"},
                                cameraFlags(s)));
    expectCleanFailure(r, 1, out, {"--layer depth=Distance", "CamDist", "Nrm"});
    // An unknown role is a usage error.
    expectCleanFailure(cli(cat({in, "-o", out.string(), "--layer", "dpeth=CamDist"}, cameraFlags(s))), 2, out,
                       {"dpeth"});
}

} // namespace

// OpenImageIO (and the ~255 libraries it pulls in) is loaded only by the runs that read an
// environment map, write a preview or read deep input: loading it cost every process ~0.45 s of
// CPU at start. The dynamic loader's trace lists what the executable itself needs.
TEST(CliStartup, OpenImageIOIsNotLoadedAtStart) {
    ASSERT_EQ(::setenv("LD_TRACE_LOADED_OBJECTS", "1", 1), 0);
    const CliResult r = cli({"--help"});
    ::unsetenv("LD_TRACE_LOADED_OBJECTS");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("libOpenColorIO"), std::string::npos) << "no loader trace:\n" << r.out;
    EXPECT_EQ(r.out.find("libOpenImageIO"), std::string::npos) << r.out;
}
