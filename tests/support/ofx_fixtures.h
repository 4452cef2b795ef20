// What the OpenFX plugin's tests (test_ofx*.cpp) share: the studio scene as EXR planes for the
// CLI and as OFX clips for the plugin, the CLI's result on them, and loading, instantiating and
// setting up the plugin in the test host (tests/ofx_host). Header-only: OBSCURA_OFX_BUNDLE,
// OBSCURA_CLI_PATH, OBSCURA_PYTHON* and OBSCURA_TEST_TMP are the including test's definitions
// (tests/CMakeLists.txt gives every test_ofx* target the same ones).
#pragma once
#include "base/image.h"
#include "core/camera.h"
#include "core/methods.h"
#include "ofx_host/ofx_host.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

namespace obscura::test {

using ofxhost::Host;
using ofxhost::HostImage;
using ofxhost::Instance;
using ofxhost::ProjectSetup;

inline const std::string kBundle = OBSCURA_OFX_BUNDLE;

inline std::filesystem::path testDir() { return obscura::test::testDir("ofx"); }

// 17 significant digits: the plugin and the CLI parse the same doubles.
inline std::string num(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
inline std::string rowsOf(const glm::dmat4& m) {
    std::string s;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) s += (s.empty() ? "" : ",") + num(m[c][r]);
    return s;
}

// ---------------------------------------------------------------------------
// A scene as EXR planes (for the CLI) and as OFX clip images (for the plugin)
// ---------------------------------------------------------------------------

struct Config {
    std::string name;
    bool orthographic = false;
    DepthKind depth = DepthKind::Planar;
    NormalSpace normals = NormalSpace::World;
    int overscan = 0;               // data window margin beyond the display window
    double radius = 0.5;
    int directions = 8, steps = 8;
    bool cosine = false, noFalloff = false;
    int blur = 0;
    double maxScreenRadius = 256;   // the plugin's cap (0 = automatic, the CLI's rule)
    int method = 0;                 // index into the Method choice: 0 hbao, 1 ssdo (the CLI's run), 2 ssao, 3 rtao, 4 discs
    int ssaoSamples = 16;
    double thickness = -1;          // hbao's and rtao's; -1: auto (the number OFX stores for it)
    int rtaoGrid = 1;
    bool filmBack = false;          // the lens as a focal length and horizontal aperture, not a field of view
    std::string stored = "";        // how Depth is stored when not as `depth`: "inverse" or "normalized" (kStoredRange)
};

// normalized's range in the configs that store it: white is near (the reversed form).
inline constexpr double kStoredRange[2] = {30.0, 1.0};
inline constexpr double kFocalMm = 35.0, kApertureMm = 24.576;

// The planar depth `z` as Config::stored writes it; sky (z at or past 1e9) as each encoding writes it.
inline float storedDepth(const Config& c, float z) {
    const bool sky = !(z < 1e9f);
    if (c.stored == "inverse") return sky ? 0.0f : 1.0f / z;
    if (c.stored == "normalized") return sky ? 0.0f : (float)((z - kStoredRange[0]) / (kStoredRange[1] - kStoredRange[0]));
    return z;
}

// gtest names a parameter by its config's name.
inline void PrintTo(const Config& c, std::ostream* os) { *os << c.name; }

inline constexpr int kW = 96, kH = 64;

struct Scene {
    SceneBuffers buf;
    Camera cam;
    double fovDeg = 0, orthoWidth = 0;
    HostImage depthClip, normalClip, beautyClip;  // OFX pixel coordinates, y up
};

// The scene seen by a w x h camera (kW x kH unless a test needs another size).
inline Scene makeScene(const Config& c, int w = kW, int h = kH) {
    Scene s;
    const glm::dvec3 eye(3.5, 3.0, 6.5), target(-1.0, 0.6, -1.0);
    if (c.orthographic) {
        s.orthoWidth = 11.0;
        s.cam = test::lookAtOrthographic(eye, target, s.orthoWidth, w, h);
    } else {
        s.fovDeg = c.filmBack ? 2.0 * std::atan(0.5 * kApertureMm / kFocalMm) * 180 / 3.14159265358979323846 : 65.0;
        s.cam = test::lookAtPerspective(eye, target, s.fovDeg * 3.14159265358979323846 / 180, w, h);
    }
    const Box2i display{0, 0, w, h};
    const Box2i data{-c.overscan, -c.overscan, w + c.overscan, h + c.overscan};
    s.buf = test::renderScene(test::studioScene(), s.cam, display, data, c.depth);
    if (c.normals == NormalSpace::Camera) {
        const glm::dmat3 toCam = glm::dmat3(s.cam.worldToCamera());
        for (int y = 0; y < data.height(); ++y)
            for (int x = 0; x < data.width(); ++x) {
                float* n = s.buf.normal.at(x, y);
                const glm::dvec3 v = toCam * glm::dvec3(n[0], n[1], n[2]);
                n[0] = (float)v.x, n[1] = (float)v.y, n[2] = (float)v.z;
            }
    }
    // OFX rows are y up: OFX y = H - 1 - display y.
    const OfxRectI b{data.x0, h - data.y1, data.x1, h - data.y0};
    s.depthClip = HostImage(b, 1);
    s.normalClip = HostImage(b, 4);
    s.beautyClip = HostImage(b, 4);
    for (int dy = data.y0; dy < data.y1; ++dy)
        for (int dx = data.x0; dx < data.x1; ++dx) {
            const int oy = h - 1 - dy;
            const float* n = s.buf.normal.at(dx - data.x0, dy - data.y0);
            s.depthClip.at(dx, oy)[0] = storedDepth(c, *s.buf.depth.at(dx - data.x0, dy - data.y0));
            float* o = s.normalClip.at(dx, oy);
            o[0] = n[0], o[1] = n[1], o[2] = n[2], o[3] = 1.0f;
            float* bt = s.beautyClip.at(dx, oy);
            bt[0] = 0.25f + 0.5f * (dx & 7) / 8.0f, bt[1] = 0.75f, bt[2] = 0.125f * (dy & 7), bt[3] = (dx & 1) ? 1.0f : 0.5f;
        }
    return s;
}

// The interpreter's environment for the Python module: its directory, and in a sanitizer build the
// runtime preloaded as python.* tests have it (OBSCURA_PYTHON_PRELOAD: "NAME=value" entries
// separated by '|', empty otherwise): an instrumented module cannot load into a plain interpreter.
inline std::vector<std::string> pythonChildEnvironment() {
    std::vector<std::string> env{std::string("PYTHONPATH=") + OBSCURA_PYTHON_MODULE_DIR};
    const std::string preload = OBSCURA_PYTHON_PRELOAD;
    for (size_t start = 0; start < preload.size();) {
        const size_t end = std::min(preload.find('|', start), preload.size());
        env.push_back(preload.substr(start, end - start));
        start = end + 1;
    }
    return env;
}

// The CLI's AO (or `channels`, interleaved) over the data window, y down (EXR rows), from
// --out-type float; `extra` flags follow the scene's. viaPython: the same command line through
// the Python module's process() (tests/support/cli_as_python.py).
inline std::vector<float> runCli(const Config& c, const Scene& s, const std::filesystem::path& dir,
                                 const std::vector<std::string>& extra = {},
                                 const std::vector<std::string>& channels = {"obscura.AO.Y"}, bool viaPython = false) {
    using namespace fixtures;
    const Box2i data = s.buf.data;
    FixturePart part;
    part.displayWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(kW - 1, kH - 1));
    part.dataWindow = Imath::Box2i(Imath::V2i(data.x0, data.y0), Imath::V2i(data.x1 - 1, data.y1 - 1));
    auto channel = [&](const char* name, const Image& img, int k) {
        FixtureChannel ch;
        ch.name = name;
        ch.type = Imf::FLOAT;
        ch.value = [&img, k, data](int x, int y) { return img.at(x - data.x0, y - data.y0)[k]; };
        return ch;
    };
    part.channels = {channel("Z", s.buf.depth, 0), channel("N.X", s.buf.normal, 0), channel("N.Y", s.buf.normal, 1),
                     channel("N.Z", s.buf.normal, 2)};
    const auto depthValue = part.channels[0].value;
    part.channels[0].value = [&c, depthValue](int x, int y) { return storedDepth(c, depthValue(x, y)); };
    const std::filesystem::path in = dir / "planes.exr", out = dir / (viaPython ? "ao_python.exr" : "ao.exr");
    writeFixture(in.string(), {part});

    std::vector<std::string> args = {in.string(), "-o", out.string(), "--out-type", "float", "--quiet",
                                     "--radius", num(c.radius), "--weighting", c.cosine ? "cosine" : "uniform",
                                     "--falloff", c.noFalloff ? "none" : "linear", "--blur", std::to_string(c.blur),
                                     "--depth", c.stored.empty() ? toString(c.depth) : c.stored.c_str(),
                                     "--normals", toString(c.normals),
                                     "--camera-to-world", rowsOf(s.cam.cameraToWorld), "--device", "cpu"};
    // Only what the method reads: the CLI refuses the rest (the node greys it out).
    if (c.method == 0)
        args.insert(args.end(), {"--directions", std::to_string(c.directions), "--steps", std::to_string(c.steps)});
    if (c.method == 1) {  // ssdo weighs and fades its samples its own way
        args.erase(std::find(args.begin(), args.end(), "--weighting"), std::find(args.begin(), args.end(), "--blur"));
        args.insert(args.end(), {"--method", "ssdo"});
    }
    if (c.method == 2) args.insert(args.end(), {"--method", "ssao", "--ssao-samples", std::to_string(c.ssaoSamples)});
    if (c.method == 3)
        args.insert(args.end(), {"--method", "rtao", "--rtao-grid", std::to_string(c.rtaoGrid)});
    if (c.method == 4) args.insert(args.end(), {"--method", "discs"});
    if (c.method != 1 && c.method != 2)
        args.insert(args.end(), {"--thickness", c.thickness < 0 ? "auto" : num(c.thickness)});
    if (c.stored == "normalized")
        args.insert(args.end(), {"--depth-range", num(kStoredRange[0]) + "," + num(kStoredRange[1])});
    if (c.orthographic) {
        args.insert(args.end(), {"--ortho-width", num(s.orthoWidth)});
    } else if (c.filmBack) {
        args.insert(args.end(), {"--focal-mm", num(kFocalMm), "--aperture-mm", num(kApertureMm)});
    } else {
        args.insert(args.end(), {"--fov-deg", num(s.fovDeg)});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<std::string> env;
    if (viaPython) {
        args.insert(args.begin(), std::string(OBSCURA_SOURCE_DIR) + "/tests/support/cli_as_python.py");
        env = pythonChildEnvironment();
    }
    const test::CliResult r = test::runProgram(viaPython ? OBSCURA_PYTHON : OBSCURA_CLI_PATH, args, env);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    if (r.exitCode != 0) return {};

    Imf::InputFile file(out.string().c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    EXPECT_EQ(dw.min.x, data.x0);
    EXPECT_EQ(dw.max.y, data.y1 - 1);
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    const size_t n = channels.size();
    std::vector<float> ao((size_t)w * h * n);
    Imf::FrameBuffer fb;
    for (size_t k = 0; k < n; ++k) {
        EXPECT_NE(file.header().channels().findChannel(channels[k]), nullptr) << channels[k];
        EXPECT_EQ(file.header().channels().findChannel(channels[k])->type, Imf::FLOAT);
        fb.insert(channels[k], Imf::Slice::Make(Imf::FLOAT, ao.data() + k, dw, sizeof(float) * n, sizeof(float) * n * w));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return ao;
}

// ---------------------------------------------------------------------------
// Driving the plugin
// ---------------------------------------------------------------------------

struct Loaded {
    std::unique_ptr<Host> host;
    std::unique_ptr<Instance> inst;
    void reset() {  // the instance goes first: destroying it is an action of its host
        inst.reset();
        host.reset();
    }
};

// Loads, describes and instantiates the plugin in a host offering colour-management `style`
// ("" = an OFX 1.4 host), in `project`, with the scene's clips named in `clips` connected.
inline Loaded instantiateIn(const Scene& s, const ProjectSetup& project, const std::vector<std::string>& clips,
                            const std::string& style = "", const std::string& bundle = kBundle) {
    Loaded l;
    l.host = std::make_unique<Host>(bundle);
    EXPECT_EQ(l.host->error(), "");
    if (!l.host->plugin()) return l;
    l.host->setColourManagementStyle(style);
    EXPECT_EQ(l.host->load(), kOfxStatOK);
    EXPECT_EQ(l.host->describe(), kOfxStatOK);
    const std::map<std::string, const HostImage*> all = {
        {"Depth", &s.depthClip}, {"Normal", &s.normalClip}, {"Source", &s.beautyClip}};
    std::map<std::string, const HostImage*> inputs;
    for (const std::string& name : clips) inputs[name] = all.at(name);
    OfxStatus st = kOfxStatFailed;
    l.inst = l.host->createInstance(project, inputs, &st);
    EXPECT_EQ(st, kOfxStatOK);
    return l;
}

inline ProjectSetup project(int w, int h, double par = 1.0, double renderScale = 1.0, int outputComponents = 4) {
    ProjectSetup p;
    p.width = w, p.height = h, p.pixelAspect = par, p.renderScale = renderScale, p.outputComponents = outputComponents;
    return p;
}

// A kW x kH project at square pixels and full resolution, over Depth and Normal (and Source).
inline Loaded instantiate(const Scene& s, bool withBeauty = false, int outputComponents = 4,
                          const std::string& bundle = kBundle) {
    std::vector<std::string> clips = {"Depth", "Normal"};
    if (withBeauty) clips.push_back("Source");
    return instantiateIn(s, project(kW, kH, 1.0, 1.0, outputComponents), clips, "", bundle);
}

inline void applyConfig(Instance& inst, const Config& c, const Scene& s) {
    EXPECT_EQ(inst.setDouble("radius", c.radius), kOfxStatOK);
    EXPECT_EQ(inst.setInt("directions", c.directions), kOfxStatOK);
    EXPECT_EQ(inst.setInt("steps", c.steps), kOfxStatOK);
    EXPECT_EQ(inst.setInt("method", c.method), kOfxStatOK);
    EXPECT_EQ(inst.setInt("ssao_samples", c.ssaoSamples), kOfxStatOK);
    EXPECT_EQ(inst.setDouble("thickness", c.thickness), kOfxStatOK);
    EXPECT_EQ(inst.setInt("rtao_grid", c.rtaoGrid), kOfxStatOK);
    EXPECT_EQ(inst.setInt("weighting", c.cosine ? 1 : 0), kOfxStatOK);
    EXPECT_EQ(inst.setInt("falloff", c.noFalloff ? 1 : 0), kOfxStatOK);
    EXPECT_EQ(inst.setInt("blur", c.blur), kOfxStatOK);
    EXPECT_EQ(inst.setInt("projection", c.orthographic ? 1 : c.filmBack ? 2 : 0), kOfxStatOK);
    if (c.orthographic) {
        EXPECT_EQ(inst.setDouble("orthoWidth", s.orthoWidth), kOfxStatOK);
    } else if (c.filmBack) {
        EXPECT_EQ(inst.setDouble("focalMm", kFocalMm), kOfxStatOK);
        EXPECT_EQ(inst.setDouble("apertureMm", kApertureMm), kOfxStatOK);
    } else {
        EXPECT_EQ(inst.setDouble("fovDeg", s.fovDeg), kOfxStatOK);
    }
    EXPECT_EQ(inst.setString("cameraToWorld", rowsOf(s.cam.cameraToWorld)), kOfxStatOK);
    const int depthKind = c.stored == "inverse" ? 2 : c.stored == "normalized" ? 3 : c.depth == DepthKind::Radial ? 1 : 0;
    EXPECT_EQ(inst.setInt("depthKind", depthKind), kOfxStatOK);
    if (c.stored == "normalized") {
        EXPECT_EQ(inst.setDouble("depthRangeNear", kStoredRange[0]), kOfxStatOK);
        EXPECT_EQ(inst.setDouble("depthRangeFar", kStoredRange[1]), kOfxStatOK);
    }
    EXPECT_EQ(inst.setInt("normalSpace", c.normals == NormalSpace::Camera ? 1 : c.normals == NormalSpace::Depth ? 2 : 0),
              kOfxStatOK);
    EXPECT_EQ(inst.setDouble("maxScreenRadius", c.maxScreenRadius), kOfxStatOK);
    EXPECT_EQ(inst.setInt("device", 0), kOfxStatOK);  // cpu: the CLI runs on the CPU too
}

inline bool sameBits(const HostImage& a, const HostImage& b) {
    return a.bounds.x1 == b.bounds.x1 && a.bounds.y1 == b.bounds.y1 && a.bounds.x2 == b.bounds.x2 &&
           a.bounds.y2 == b.bounds.y2 && a.components == b.components &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

// The largest difference of two images' values (infinite when their sizes differ).
inline float maxAbsDiff(const HostImage& a, const HostImage& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    float worst = a.pixels.size() == b.pixels.size() ? 0.0f : INFINITY;
    for (size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
        worst = std::max(worst, std::fabs(a.pixels[i] - b.pixels[i]));
    return worst;
}

inline std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
}

inline Config cfg(std::string name) {
    Config c;
    c.name = std::move(name);
    return c;
}

} // namespace obscura::test
