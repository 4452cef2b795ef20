// The obscura command line, end to end: the built binary is run as a subprocess on
// synthetic and real EXRs, and its exit code, stderr/stdout and output file are checked.
#include "core/camera.h"
#include "core/operator.h"
#include "io/camera_sources.h"
#include "support/scratch.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <Imath/half.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using obscura::test::CliResult;
using obscura::test::Rect;
using obscura::test::SceneBuffers;

namespace {

// ---------------------------------------------------------------------------
// Scratch space and running the CLI
// ---------------------------------------------------------------------------

fs::path testDir() { return obscura::test::testDir("cli"); }

const std::string kData = OBSCURA_TEST_DATA_DIR;
const std::string kRoom = kData + "/room.exr";

CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

std::string describe(const CliResult& r) {
    return "exit " + std::to_string(r.exitCode) + "\n--- stdout ---\n" + r.out + "--- stderr ---\n" + r.err;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::vector<std::string> tempLeftovers(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (contains(e.path().filename().string(), ".tmp-")) out.push_back(e.path().string());
    return out;
}

// A failed run: the exit code, exactly one stderr line "obscura: ..." naming every `mentions`,
// no output file and no temp file left in the output's directory.
void expectCleanFailure(const CliResult& r, int exitCode, const fs::path& output,
                        std::initializer_list<std::string> mentions = {}) {
    EXPECT_EQ(r.exitCode, exitCode) << describe(r);
    EXPECT_EQ(r.err.rfind("obscura: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not exactly one line:\n" << describe(r);
    if (exitCode == 1) {  // a failure (not a usage error) names the file at fault first
        EXPECT_TRUE(std::regex_search(r.err, std::regex("^obscura: '[^\n]+': [^\n]+\n$"))) << describe(r);
    }
    EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << describe(r);
    for (const std::string& m : mentions) EXPECT_TRUE(contains(r.err, m)) << "'" << m << "' not in: " << r.err;
    if (!output.empty()) {
        EXPECT_FALSE(fs::exists(output)) << output << " was written";
        const fs::path dir = output.parent_path();
        if (fs::is_directory(dir)) {
            EXPECT_EQ(tempLeftovers(dir), std::vector<std::string>{});
        }
    }
}

void expectSuccess(const CliResult& r, const fs::path& output) {
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    ASSERT_TRUE(fs::exists(output)) << describe(r);
    EXPECT_EQ(tempLeftovers(output.parent_path()), std::vector<std::string>{});
}

std::string fileBytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// ---------------------------------------------------------------------------
// Reading an EXR back with OpenEXR directly (not through obscura's reader)
// ---------------------------------------------------------------------------

struct ChannelData {
    Imf::PixelType type = Imf::FLOAT;
    int width = 0, height = 0;
    std::vector<char> bytes;  // tightly packed, native type

    float at(size_t i) const {
        if (type == Imf::HALF) {
            half h;
            std::memcpy(&h, bytes.data() + i * 2, 2);
            return float(h);
        }
        if (type == Imf::UINT) {
            unsigned u;
            std::memcpy(&u, bytes.data() + i * 4, 4);
            return float(u);
        }
        float f;
        std::memcpy(&f, bytes.data() + i * 4, 4);
        return f;
    }
    std::vector<float> floats() const {
        std::vector<float> v((size_t)width * height);
        for (size_t i = 0; i < v.size(); ++i) v[i] = at(i);
        return v;
    }
};

struct FileData {
    std::vector<Imath::Box2i> dataWindows, displayWindows;
    std::vector<bool> tiled;
    std::map<std::string, ChannelData> channels;  // "part:name"

    const ChannelData* find(int part, const std::string& name) const {
        auto it = channels.find(std::to_string(part) + ":" + name);
        return it == channels.end() ? nullptr : &it->second;
    }
};

FileData readAll(const std::string& path) {
    FileData fd;
    Imf::MultiPartInputFile file(path.c_str());
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        const Imath::Box2i dw = h.dataWindow();
        const int w = dw.max.x - dw.min.x + 1, hgt = dw.max.y - dw.min.y + 1;
        fd.dataWindows.push_back(dw);
        fd.displayWindows.push_back(h.displayWindow());
        Imf::FrameBuffer fb;
        std::vector<ChannelData*> slots;
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
            EXPECT_EQ(it.channel().xSampling, 1);
            EXPECT_EQ(it.channel().ySampling, 1);
            ChannelData& cd = fd.channels[std::to_string(p) + ":" + it.name()];
            cd.type = it.channel().type;
            cd.width = w;
            cd.height = hgt;
            const size_t bps = cd.type == Imf::HALF ? 2 : 4;
            cd.bytes.assign((size_t)w * hgt * bps, 0);
            fb.insert(it.name(), Imf::Slice::Make(cd.type, cd.bytes.data(), dw, bps, bps * w));
        }
        fd.tiled.push_back(h.hasTileDescription());
        obscura::test::readPart(file, p, fb);
    }
    return fd;
}

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

// Every channel of `in` is in `out`, same part, type and bytes.
void expectChannelsKept(const FileData& in, const FileData& out) {
    ASSERT_EQ(in.dataWindows.size(), out.dataWindows.size());
    for (size_t p = 0; p < in.dataWindows.size(); ++p) EXPECT_EQ(in.dataWindows[p], out.dataWindows[p]);
    for (const auto& [key, ch] : in.channels) {
        auto it = out.channels.find(key);
        ASSERT_NE(it, out.channels.end()) << "channel " << key << " lost";
        EXPECT_EQ(it->second.type, ch.type) << key;
        EXPECT_TRUE(it->second.bytes == ch.bytes) << "channel " << key << " changed";
    }
}

// ---------------------------------------------------------------------------
// Synthetic frames: an analytic scene written under a renderer's channel names
// ---------------------------------------------------------------------------

constexpr double kFovDeg = 70.0;

// Floor, back wall, left wall and a box: corners to occlude, sky above the wall.
SceneBuffers cornerScene(Box2i display, Box2i data) {
    const std::vector<Rect> rects = {
        obscura::test::planeRect({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50),
        Rect{{-4, 0, -4}, {8, 0, 0}, {0, 2.5, 0}},
        Rect{{-2, 0, -4}, {0, 0, 8}, {0, 2.5, 0}},
        Rect{{0.2, 0, -1.5}, {0.8, 0, 0}, {0, 0.8, 0}},
        Rect{{0.2, 0.8, -2.3}, {0.8, 0, 0}, {0, 0, 0.8}},
        Rect{{0.2, 0, -2.3}, {0, 0, 0.8}, {0, 0.8, 0}},
    };
    const Camera cam = obscura::test::lookAtPerspective({0.4, 1.7, 2.5}, {-0.3, 0.5, -3}, kFovDeg * M_PI / 180,
                                                        display.width(), display.height());
    return obscura::test::renderScene(rects, cam, display, data);
}
SceneBuffers cornerScene(int w, int h) { return cornerScene(Box2i{0, 0, w, h}, Box2i{0, 0, w, h}); }

// Row-major, OpenGL convention, 17 significant digits (round-trips exactly).
std::array<double, 16> rowMajor(const glm::dmat4& m) {
    std::array<double, 16> a{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a[r * 4 + c] = m[c][r];
    return a;
}
std::string joinNumbers(const std::array<double, 16>& a) {
    std::string s;
    char buf[40];
    for (double v : a) {
        std::snprintf(buf, sizeof buf, "%.17g", v);
        s += (s.empty() ? "" : ",") + std::string(buf);
    }
    return s;
}
std::vector<std::string> cameraFlags(const SceneBuffers& s) {
    return {"--fov-deg", "70", "--camera-to-world", joinNumbers(rowMajor(s.camera.cameraToWorld))};
}

// The planes as a file holds them.
struct Planes {
    Box2i display, data;
    Image depth, normal, position;
};

Planes planesOf(const SceneBuffers& s) { return {s.display, s.data, s.depth, s.normal, s.position}; }

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

Imath::Box2i toImath(const Box2i& b) { return Imath::Box2i(Imath::V2i(b.x0, b.y0), Imath::V2i(b.x1 - 1, b.y1 - 1)); }

// A channel whose values come from channel `c` of `img` (EXR coords -> data-window index).
FixtureChannel planeChannel(const std::string& name, const Image& img, int c, const Box2i& data, Imf::PixelType type) {
    FixtureChannel ch;
    ch.name = name;
    ch.type = type;
    const Image* src = &img;
    ch.value = [src, c, data](int x, int y) { return src->at(x - data.x0, y - data.y0)[c]; };
    return ch;
}

struct Naming {
    std::string depth;                         // full channel name
    std::array<std::string, 3> normal;         // full channel names, x, y, z
    std::array<std::string, 3> position;       // empty: no position pass
    std::vector<std::string> beauty;           // pattern-filled pass-through channels
    std::map<std::string, std::string> attrs;  // header hints
};

FixturePart makePart(const Planes& p, const Naming& n, Imf::PixelType type = Imf::FLOAT) {
    FixturePart part;
    part.displayWindow = toImath(p.display);
    part.dataWindow = toImath(p.data);
    part.stringAttributes = n.attrs;
    part.channels.push_back(planeChannel(n.depth, p.depth, 0, p.data, type));
    for (int c = 0; c < 3; ++c) part.channels.push_back(planeChannel(n.normal[c], p.normal, c, p.data, type));
    if (!n.position[0].empty())
        for (int c = 0; c < 3; ++c) part.channels.push_back(planeChannel(n.position[c], p.position, c, p.data, type));
    for (const std::string& b : n.beauty) part.channels.push_back({b, Imf::HALF, 1, 1, {}});
    return part;
}

const Naming kGeneric = {"Z", {"N.X", "N.Y", "N.Z"}, {"P.X", "P.Y", "P.Z"}, {"R", "G", "B"}, {}};

// Writes `planes` under generic names (float) and returns the path.
std::string writeGeneric(const fs::path& dir, const std::string& name, const Planes& planes) {
    const std::string path = (dir / name).string();
    writeFixture(path, {makePart(planes, kGeneric)});
    return path;
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

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
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
    const std::vector<std::string> cam = cameraFlags(s);
    struct Case {
        std::vector<std::string> args;
        std::string file, what;
    };
    const std::vector<Case> cases = {
        {{missing, "-o", out}, missing, "cannot open: no such file"},
        {{dir.string(), "-o", out}, dir.string(), "cannot open: it is a directory"},
        {{notExr, "-o", out}, notExr, "not an OpenEXR file"},
        {cat({cut, "-o", out}, cam), cut, "truncated or corrupt"},
        {cat({in, "-o", noDir + "/o.exr"}, cam), noDir + "/o.exr", "cannot write: directory"},
        {cat({in, "-o", out, "--report", noDir + "/r.json"}, cam), noDir + "/r.json", "cannot write: directory"},
        {cat({in, "-o", out, "--preview", noDir + "/p.png"}, cam), noDir + "/p.png", "cannot write: directory"},
        {{in, "-o", out, "--camera", json}, json, "camera sidecar"},
        {{in, "-o", out, "--camera", missing}, missing, "cannot open the camera sidecar"},
        {cat({in, "-o", out, "--method", "ssdo", "--env", missing}, cam), missing, "cannot read the environment map"},
        {cat({in, "-o", out, "--layer", "normal=nope"}, cam), in, "--layer normal=nope: no layer or channel 'nope'"},
        {cat({in, "-o", out, "--reference", "nope"}, cam), in, "no reference layer 'nope'"},
        {cat({in, "-o", out, "--method", "ssdo", "--bounce"}, cam), in, "no direct-diffuse layer for the bounce"},
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
};

TEST(CliBadInput, NanDepthErrorsByDefault) {
    const fs::path dir = testDir();
    BrokenFrame f;
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::quiet_NaN();
    const std::string in = writeGeneric(dir, "nan.exr", f.planes);
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string()}, cameraFlags(f.scene)));
    expectCleanFailure(r, 1, out, {"NaN", std::to_string(f.x) + "," + std::to_string(f.y), "--bad-pixels skip"});
}

TEST(CliBadInput, NanDepthSkipped) {
    const fs::path dir = testDir();
    BrokenFrame f;
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::quiet_NaN();
    *f.planes.depth.at(f.x + 1, f.y) = std::numeric_limits<float>::quiet_NaN();
    const std::string in = writeGeneric(dir, "nan.exr", f.planes);
    const fs::path out = dir / "out.exr";
    const CliResult r =
        cli(cat({in, "-o", out.string(), "--bad-pixels", "skip", "--out-type", "float"}, cameraFlags(f.scene)));
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
    const std::string in = writeGeneric(dir, "neg.exr", f.planes);
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string()}, cameraFlags(f.scene)));
    expectCleanFailure(r, 1, out, {"negative", std::to_string(f.x) + "," + std::to_string(f.y)});
}

TEST(CliBadInput, InfiniteDepthIsSky) {
    const fs::path dir = testDir();
    BrokenFrame f;
    for (int y = 0; y < 32; ++y)
        if (*f.planes.depth.at(0, y) >= 1e9f) *f.planes.depth.at(0, y) = std::numeric_limits<float>::infinity();
    *f.planes.depth.at(f.x, f.y) = std::numeric_limits<float>::infinity();  // a hole in a surface
    const std::string in = writeGeneric(dir, "inf.exr", f.planes);
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string(), "--out-type", "float"}, cameraFlags(f.scene)));
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
    const std::string in = writeGeneric(dir, "zeron.exr", f.planes);
    const fs::path out = dir / "out.exr";
    const CliResult r = cli(cat({in, "-o", out.string()}, cameraFlags(f.scene)));
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
