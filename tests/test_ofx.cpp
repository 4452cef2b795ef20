// The OpenFX plugin, through a test host (tests/ofx_host) that loads the built bundle with
// dlopen as Nuke, Natron or Resolve would and drives describe / describeInContext /
// createInstance / getRegionsOfInterest / isIdentity / render over tiles. Its output is
// compared with the command line on the same planes: identical pixels, whole frame and tiled.
#include "core/devices.h"
#include "core/methods.h"
#include "ofx_host/ofx_host.h"
#include "support/scratch.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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
using obscura::test::SceneBuffers;

namespace {

const std::string kBundle = OBSCURA_OFX_BUNDLE;

fs::path testDir() { return obscura::test::testDir("ofx"); }

std::string readText(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

// 17 significant digits: the plugin and the CLI parse the same doubles.
std::string num(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}
std::string rowsOf(const glm::dmat4& m) {
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
    int method = 0;                 // index into the Method choice: 0 hbao, 1 ssdo (the CLI's run), 2 ssao, 3 rtao
    int ssaoSamples = 16;
    double thickness = -1;          // hbao's and rtao's; -1: auto (the number OFX stores for it)
    int rtaoGrid = 1;
    bool filmBack = false;          // the lens as a focal length and horizontal aperture, not a field of view
    std::string stored = "";        // how Depth is stored when not as `depth`: "inverse" or "normalized" (kStoredRange)
};

// normalized's range in the configs that store it: white is near (the reversed form).
constexpr double kStoredRange[2] = {30.0, 1.0};
constexpr double kFocalMm = 35.0, kApertureMm = 24.576;

// The planar depth `z` as Config::stored writes it; sky (z at or past 1e9) as each encoding writes it.
float storedDepth(const Config& c, float z) {
    const bool sky = !(z < 1e9f);
    if (c.stored == "inverse") return sky ? 0.0f : 1.0f / z;
    if (c.stored == "normalized") return sky ? 0.0f : (float)((z - kStoredRange[0]) / (kStoredRange[1] - kStoredRange[0]));
    return z;
}

// gtest names a parameter by its config's name.
void PrintTo(const Config& c, std::ostream* os) { *os << c.name; }

constexpr int kW = 96, kH = 64;

struct Scene {
    SceneBuffers buf;
    Camera cam;
    double fovDeg = 0, orthoWidth = 0;
    HostImage depthClip, normalClip, beautyClip;  // OFX pixel coordinates, y up
};

// The scene seen by a w x h camera (kW x kH unless a test needs another size).
Scene makeScene(const Config& c, int w = kW, int h = kH) {
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

// The CLI's AO (or `channels`, interleaved) over the data window, y down (EXR rows), from
// --out-type float; `extra` flags follow the scene's. viaPython: the same command line through
// the Python module's process() (tests/support/cli_as_python.py).
std::vector<float> runCli(const Config& c, const Scene& s, const fs::path& dir, const std::vector<std::string>& extra = {},
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
    const fs::path in = dir / "planes.exr", out = dir / (viaPython ? "ao_python.exr" : "ao.exr");
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
    if (viaPython) {
        ::setenv("PYTHONPATH", OBSCURA_PYTHON_MODULE_DIR, 1);
        args.insert(args.begin(), std::string(OBSCURA_SOURCE_DIR) + "/tests/support/cli_as_python.py");
    }
    const test::CliResult r = test::runProgram(viaPython ? OBSCURA_PYTHON : OBSCURA_CLI_PATH, args);
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
Loaded instantiateIn(const Scene& s, const ProjectSetup& project, const std::vector<std::string>& clips,
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

ProjectSetup project(int w, int h, double par = 1.0, double renderScale = 1.0, int outputComponents = 4) {
    ProjectSetup p;
    p.width = w, p.height = h, p.pixelAspect = par, p.renderScale = renderScale, p.outputComponents = outputComponents;
    return p;
}

// A kW x kH project at square pixels and full resolution, over Depth and Normal (and Source).
Loaded instantiate(const Scene& s, bool withBeauty = false, int outputComponents = 4,
                   const std::string& bundle = kBundle) {
    std::vector<std::string> clips = {"Depth", "Normal"};
    if (withBeauty) clips.push_back("Source");
    return instantiateIn(s, project(kW, kH, 1.0, 1.0, outputComponents), clips, "", bundle);
}

void applyConfig(Instance& inst, const Config& c, const Scene& s) {
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

bool sameBits(const HostImage& a, const HostImage& b) {
    return a.bounds.x1 == b.bounds.x1 && a.bounds.y1 == b.bounds.y1 && a.bounds.x2 == b.bounds.x2 &&
           a.bounds.y2 == b.bounds.y2 && a.components == b.components &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
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

Config cfg(std::string name) {
    Config c;
    c.name = std::move(name);
    return c;
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

// ---------------------------------------------------------------------------
// SSDO outputs (DO, GI, relit): the operator's own result on the same planes
// ---------------------------------------------------------------------------

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
                              const Image* environment = nullptr) {
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
    st.method = "ssdo";
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
            const float* d = ref.directional.at(dx - data.x0, dy - data.y0);
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

Loaded instantiateSsdo(const Scene& s, const HostImage& albedo) {
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
        project, {{"Depth", &s.depthClip}, {"Normal", &s.normalClip}, {"Source", &s.beautyClip}, {"Albedo", &albedo}},
        &st);
    EXPECT_EQ(st, kOfxStatOK);
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
    ASSERT_FALSE(ref.indirect.empty());
    // The bounce is really there (the test would be weak on an all-black GI).
    double giSum = 0;
    for (float v : ref.indirect.pixels) giSum += v;
    EXPECT_GT(giSum, 0.0);

    Loaded l = instantiateSsdo(s, albedo);
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    applySsdo(*l.inst, o);
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

TEST(OfxSsdo, RegionsOfInterestFollowWhatEachOutputReads) {
    Config c;
    c.radius = 3.0, c.maxScreenRadius = 7.5;
    const Scene s = makeScene(c);
    const HostImage albedo = albedoClipOf(s);
    Loaded l = instantiateSsdo(s, albedo);
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

    for (int out : {kOutGi, kOutRelit}) {
        ASSERT_EQ(l.inst->setInt("output", out), kOfxStatOK);
        ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
        EXPECT_TRUE(same(rois["Depth"], grown)) << out;
        EXPECT_TRUE(same(rois["Source"], grown)) << out;  // the senders, within the apron
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
    EXPECT_TRUE(same(rois["Depth"], grown));

    // The interleave sets the blur, hence the apron; an explicit Blur replaces it.
    ASSERT_EQ(l.inst->setInt("interleave", 4), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x2, window.x2 + 8 + 2 + 4);
    ASSERT_EQ(l.inst->setInt("blur", 1), kOfxStatOK);
    ASSERT_EQ(l.inst->regionsOfInterest(window, rois), kOfxStatOK);
    EXPECT_EQ(rois["Depth"].x2, window.x2 + 8 + 2 + 1);

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
    Loaded l;
    l.host = std::make_unique<Host>(kBundle);
    ASSERT_EQ(l.host->error(), "");
    ASSERT_EQ(l.host->load(), kOfxStatOK);
    ASSERT_EQ(l.host->describe(), kOfxStatOK);
    ProjectSetup project;
    project.width = kW, project.height = kH;
    OfxStatus st = kOfxStatFailed;
    l.inst = l.host->createInstance(
        project, {{"Depth", &depth}, {"Normal", &normal}, {"Source", &beauty}, {"Albedo", &albedo}}, &st);
    ASSERT_EQ(st, kOfxStatOK);
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
    Loaded l = instantiateSsdo(s, albedo);
    if (!l.inst) return l;
    applyConfig(*l.inst, c, s);
    applySsdo(*l.inst, o);
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

// ---------------------------------------------------------------------------
// What a host built on the official HostSupport library checks (issue 13): pixel aspect
// ratio, render scale, required and optional clips, clip-preference slaves, OFX 1.5 colour
// ---------------------------------------------------------------------------

float maxAbsDiff(const HostImage& a, const HostImage& b) {
    EXPECT_EQ(a.pixels.size(), b.pixels.size());
    float worst = a.pixels.size() == b.pixels.size() ? 0.0f : INFINITY;
    for (size_t i = 0; i < std::min(a.pixels.size(), b.pixels.size()); ++i)
        worst = std::max(worst, std::fabs(a.pixels[i] - b.pixels[i]));
    return worst;
}

void expectBounds(const HostImage& img, int w, int h) {
    EXPECT_EQ(img.bounds.x1, 0);
    EXPECT_EQ(img.bounds.y1, 0);
    EXPECT_EQ(img.bounds.x2, w);
    EXPECT_EQ(img.bounds.y2, h);
}

TEST(OfxHostFindings, DeclaresWhatTheSpecificationNames) {
    Host host(kBundle);
    ASSERT_EQ(host.error(), "");
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    const PropertySet& d = host.descriptor().props;
    // Spelled as the specification spells them, not through ofx_api.h.
    EXPECT_EQ(d.integer("OfxImageEffectPropMultipleClipDepths", 0, -1), 0);
    EXPECT_EQ(d.integer("OfxImageEffectPropSupportsMultiResolution", 0, -1), 1);
    EXPECT_EQ(d.strings("OfxImageEffectPropClipPreferencesSlaveParam"), std::vector<std::string>{"output"});
    EXPECT_FALSE(d.has("OfxImageEffectPropColourManagementStyle"));  // a 1.4 host offered none
    // Only General is declared: any other context is a feature this host asks for in vain.
    EXPECT_EQ(host.describeInContext("OfxImageEffectContextFilter"), kOfxStatErrMissingHostFeature);
}

// Anamorphic project (PAR 2): canonical x is twice pixel x. With exact-region delivery,
// tiles only see what their RoI asked for, so a halved apron would show as seams.
TEST(OfxHostFindings, Par2TilesEqualWholeFrame) {
    Config c;
    c.maxScreenRadius = 12;  // a real apron: tiles do not read the whole frame
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH, 2.0), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    OfxRectD rod{};
    ASSERT_EQ(l.inst->regionOfDefinition(rod), kOfxStatOK);
    EXPECT_EQ(rod.x2, 2.0 * kW);  // canonical
    std::vector<std::string> p1, p2;
    const HostImage whole = l.inst->renderFrame(0, 0, 1, p1);
    const HostImage tiled = l.inst->renderFrame(20, 16, 2, p2);
    EXPECT_EQ(joined(p1) + joined(p2), "");
    expectBounds(whole, kW, kH);
    EXPECT_LE(maxAbsDiff(whole, tiled), 1e-6f);

    // The PAR reaches the camera: the same pixels in a square-pixel project give other AO.
    Loaded sq = instantiateIn(s, project(kW, kH, 1.0), {"Depth", "Normal"});
    applyConfig(*sq.inst, c, s);
    std::vector<std::string> p3;
    EXPECT_GT(maxAbsDiff(whole, sq.inst->renderFrame(0, 0, 1, p3)), 0.05f);
    EXPECT_EQ(joined(p3), "");
}

// A proxy render (render scale 0.5) of a kW x kH project over half-size inputs is the full
// render of a half-size project with the pixel-sized parameters (Blur, Max Screen Radius)
// halved: the camera's intrinsics and the pixel radii follow the scale. Tiles agree.
TEST(OfxHostFindings, RenderScaleHalfIsTheHalfSizeRender) {
    Config c;
    c.radius = 3, c.maxScreenRadius = 24, c.blur = 2;  // a radius the cap binds
    const Scene half = makeScene(c, kW / 2, kH / 2);
    Loaded proxy = instantiateIn(half, project(kW, kH, 1.0, 0.5), {"Depth", "Normal"});
    ASSERT_TRUE(proxy.inst);
    applyConfig(*proxy.inst, c, half);
    std::vector<std::string> p1, p2, p3;
    const HostImage whole = proxy.inst->renderFrame(0, 0, 1, p1);
    const HostImage tiled = proxy.inst->renderFrame(10, 12, 2, p2);
    EXPECT_EQ(joined(p1) + joined(p2), "");
    expectBounds(whole, kW / 2, kH / 2);
    EXPECT_LE(maxAbsDiff(whole, tiled), 1e-6f);

    Config ch = c;
    ch.maxScreenRadius = 12, ch.blur = 1;
    Loaded small = instantiateIn(half, project(kW / 2, kH / 2), {"Depth", "Normal"});
    applyConfig(*small.inst, ch, half);
    const HostImage ref = small.inst->renderFrame(0, 0, 1, p3);
    EXPECT_EQ(joined(p3), "");
    EXPECT_LE(maxAbsDiff(whole, ref), 1e-6f);
    float lo = 1;
    for (size_t i = 0; i < whole.pixels.size(); i += 4) lo = std::min(lo, whole.pixels[i]);
    EXPECT_LT(lo, 0.9f);  // the frame holds occlusion, not a constant
}

TEST(OfxHostFindings, MissingDepthFailsThroughTheMessageSuite) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, kW, kH}, frame), kOfxStatFailed);
    const auto msgs = l.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("OfxMessageError"), std::string::npos) << msgs[0];
    EXPECT_NE(msgs[0].find("Depth clip is not connected"), std::string::npos) << msgs[0];
    EXPECT_EQ(l.host->liveImages(), 0);
}

// Normalized depth with its range unset (both ends 0, the default) is refused through the
// message suite, in the words of the node's parameters, as the CLI refuses --depth normalized
// without --depth-range.
TEST(OfxHostFindings, NormalizedDepthWithoutARangeFails) {
    Config c;
    c.stored = "normalized";
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    ASSERT_EQ(l.inst->setDouble("depthRangeNear", 0.0), kOfxStatOK);
    ASSERT_EQ(l.inst->setDouble("depthRangeFar", 0.0), kOfxStatOK);
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, kW, kH}, frame), kOfxStatFailed);
    const auto msgs = l.host->messages();
    ASSERT_EQ(msgs.size(), 1u);
    EXPECT_NE(msgs[0].find("normalized depth needs Depth Near and Depth Far"), std::string::npos) << msgs[0];
    EXPECT_EQ(l.host->liveImages(), 0);
}

// Unconnected optional clips (Source, Position, Albedo) are neither asked for nor fetched.
TEST(OfxHostFindings, UnconnectedOptionalClipsAreNotRequested) {
    Config c;
    c.maxScreenRadius = 12;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"});
    ASSERT_TRUE(l.inst);
    applyConfig(*l.inst, c, s);
    std::map<std::string, OfxRectD> rois;
    ASSERT_EQ(l.inst->regionsOfInterest({0, 0, 16, 16}, rois), kOfxStatOK);
    for (const char* clip : {"Source", "Position", "Albedo"})
        EXPECT_TRUE(rois.count(clip) && rois[clip].x2 <= rois[clip].x1) << clip;
    EXPECT_EQ(rois["Depth"].x2, 16.0 + 12 + 2);  // the window plus the apron (cap + snapping)
    std::vector<ImageFetch> fetches;
    HostImage frame(OfxRectI{0, 0, kW, kH}, 4);
    EXPECT_EQ(l.inst->render({0, 0, 16, 16}, frame, &fetches, &rois), kOfxStatOK);
    for (const ImageFetch& f : fetches) EXPECT_TRUE(f.clip == "Depth" || f.clip == "Normal") << f.clip;
}

// An OFX 1.5 host with Basic colour management: the data clips are asked for in ofx_raw, and
// the output colourspace comes from GetOutputColourspace, re-asked when `output` changes.
TEST(OfxHostFindings, ColourManagedHostGetsTheOutputColourspace) {
    const Config c;
    const Scene s = makeScene(c);
    Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal", "Source"}, "OfxImageEffectColourManagementBasic");
    ASSERT_TRUE(l.inst);
    EXPECT_EQ(l.host->descriptor().props.string("OfxImageEffectPropColourManagementStyle"),
              "OfxImageEffectColourManagementBasic");
    EXPECT_EQ(l.host->descriptor().props.string("OfxImageEffectPropColourManagementAvailableConfigs"),
              "ofx-native-v1.5_aces-v1.3_ocio-v2.3");
    PropertySet prefs;
    ASSERT_EQ(l.inst->clipPreferences(prefs), kOfxStatOK);
    EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Depth"), "ofx_raw");
    EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Normal"), "ofx_raw");
    EXPECT_EQ(prefs.string("OfxImageClipPropDepth_Output"), kOfxBitDepthFloat);
    const Clip& out = *l.inst->effect().clip("Output");
    EXPECT_EQ(out.props.string("OfxImageClipPropColourspace"), "ofx_raw");
    EXPECT_EQ(out.props.string(kOfxImageEffectPropPreMultiplication), kOfxImageOpaque);

    // Output is a slave of the clip preferences: the host re-runs them (and the colourspace).
    const int runs = l.inst->clipPreferencesRuns;
    ASSERT_EQ(l.inst->setInt("output", 1), kOfxStatOK);  // Beauty x AO
    EXPECT_EQ(l.inst->clipPreferencesRuns, runs + 1);
    EXPECT_EQ(out.props.string("OfxImageClipPropColourspace"), "OfxColourspace_Source");
    EXPECT_EQ(out.props.string(kOfxImageEffectPropPreMultiplication), kOfxImagePreMultiplied);
    ASSERT_EQ(l.inst->setDouble("radius", 2.0), kOfxStatOK);  // not a slave
    EXPECT_EQ(l.inst->clipPreferencesRuns, runs + 1);
}

// A host that offers no colour management, or says None, gets no colourspaces at all.
TEST(OfxHostFindings, NoColourspacesWithoutColourManagement) {
    const Config c;
    const Scene s = makeScene(c);
    for (const std::string style : {"", "OfxImageEffectColourManagementNone"}) {
        Loaded l = instantiateIn(s, project(kW, kH), {"Depth", "Normal"}, style);
        ASSERT_TRUE(l.inst);
        EXPECT_FALSE(l.host->descriptor().props.has("OfxImageEffectPropColourManagementStyle")) << style;
        PropertySet prefs;
        ASSERT_EQ(l.inst->clipPreferences(prefs), kOfxStatOK);
        EXPECT_EQ(prefs.string("OfxImageClipPropPreferredColourspaces_Depth"), "") << style;
        std::string space;
        EXPECT_EQ(l.inst->outputColourspace({"ofx_scene_linear"}, space), kOfxStatReplyDefault) << style;
        EXPECT_FALSE(l.inst->effect().clip("Output")->props.has("OfxImageClipPropColourspace")) << style;
    }
}

} // namespace
