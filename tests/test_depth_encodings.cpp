// Every depth encoding compositors meet (--depth planar|radial|inverse|normalized,
// --depth-range A,B), a position pass without a depth, and every way files write the sky: each
// gives the planar file's depth and AO for the same scene; what cannot be decoded is one clear
// line naming the file, with nothing written; --inspect describes the depth as stored.
#include "core/operator.h"
#include "io/depth_encoding.h"
#include "io/frame_job.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

constexpr int kW = 64, kH = 48;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kNear = 0.5, kFar = 50.0;  // --depth-range of the normalised files: the scene lies within

const SceneBuffers& planarScene() {
    static const SceneBuffers sb = renderScene(studioScene(), studioCamera(kW, kH), kW, kH);
    return sb;
}

bool sky(float planar) { return !(planar < 1e9f); }

std::string num(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
}

// The camera as flags: the field of view and the pose.
std::vector<std::string> cameraFlags() {
    const Camera& cam = planarScene().camera;
    std::string m;
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) m += (m.empty() ? "" : ",") + num(cam.cameraToWorld[c][r]);
    return {"--fov-deg", num(cam.horizontalFovRad(kW) * 180.0 / M_PI), "--camera-to-world", m};
}

// A generic-named file of the scene: N (world normals), A, and `depth` (x, y -> stored Z) or,
// when `channel` is "P", the world positions (0, 0, 0 on the sky) and no Z.
std::string writeScene(const fs::path& dir, const std::string& name, const std::function<float(int, int)>& depth,
                       const std::string& channel = "Z", const Image* normalsFrom = nullptr) {
    using namespace fixtures;
    const SceneBuffers& sb = planarScene();
    const Image& normal = normalsFrom ? *normalsFrom : sb.normal;
    FixturePart part;
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(kW - 1, kH - 1));
    for (int c = 0; c < 3; ++c)
        part.channels.push_back({std::string("N.") + "XYZ"[c], Imf::FLOAT, 1, 1,
                                 [&normal, c](int x, int y) { return normal.at(x, y)[c]; }});
    part.channels.push_back({"A", Imf::HALF, 1, 1, [&sb](int x, int y) { return sky(*sb.depth.at(x, y)) ? 0.0f : 1.0f; }});
    if (channel == "P") {
        for (int c = 0; c < 3; ++c)
            part.channels.push_back({std::string("P.") + "XYZ"[c], Imf::FLOAT, 1, 1, [&sb, c](int x, int y) {
                                         return sky(*sb.depth.at(x, y)) ? 0.0f : sb.position.at(x, y)[c];
                                     }});
    } else {
        part.channels.push_back({"Z", Imf::FLOAT, 1, 1, depth});
    }
    const std::string path = (dir / (name + ".exr")).string();
    writeFixture(path, {part});
    return path;
}

float planarAt(int x, int y) { return *planarScene().depth.at(x, y); }

// The depth the job's passes hold once read and decoded.
Image decodedDepth(const std::string& path, const std::vector<std::string>& flags) {
    FrameJob job;
    job.input = path;
    for (size_t i = 0; i < flags.size(); ++i) {
        DepthEncoding e;
        if (flags[i] == "--depth" && parse(flags[i + 1], e)) job.depthEncoding = e;
        if (flags[i] == "--depth-range") {
            double a = 0, b = 0;
            std::sscanf(flags[i + 1].c_str(), "%lf,%lf", &a, &b);
            job.depthRange = std::array<double, 2>{a, b};
        }
    }
    const std::vector<std::string> cam = cameraFlags();
    job.camera.fovDeg = std::stod(cam[1]);
    std::array<double, 16> rows{};
    std::sscanf(cam[3].c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf,%lf", &rows[0], &rows[1],
                &rows[2], &rows[3], &rows[4], &rows[5], &rows[6], &rows[7], &rows[8], &rows[9], &rows[10], &rows[11],
                &rows[12], &rows[13], &rows[14], &rows[15]);
    job.camera.cameraToWorld = rows;
    return loadFramePasses(job, {}).depth;
}

std::vector<float> aoOf(const std::string& path) { return obscura::test::partChannel(path, 0, "obscura.AO.Y"); }

CliResult run(const std::string& in, const std::string& out, std::vector<std::string> flags) {
    std::vector<std::string> args = {in, "-o", out, "--out-type", "float", "--quiet", "--threads", "2"};
    args.insert(args.end(), flags.begin(), flags.end());
    for (const std::string& f : cameraFlags()) args.push_back(f);
    return runProgram(OBSCURA_CLI_PATH, args);
}

struct Encoded {
    const char* name;
    std::function<float(int, int)> stored;  // the file's Z at (x, y)
    std::vector<std::string> flags;
};

std::vector<Encoded> encodings() {
    const std::string range = num(kNear) + "," + num(kFar), reversed = num(kFar) + "," + num(kNear);
    auto normalised = [](double a, double b) {
        return [a, b](int x, int y) {
            const double z = planarAt(x, y);
            return sky((float)z) ? (float)((b > a) ? 1.0 : 0.0) : (float)((z - a) / (b - a));
        };
    };
    return {
        {"planar_sky_plus_inf", [](int x, int y) { return sky(planarAt(x, y)) ? kInf : planarAt(x, y); }, {}},
        {"planar_sky_minus_inf", [](int x, int y) { return sky(planarAt(x, y)) ? -kInf : planarAt(x, y); }, {}},
        {"planar_sky_zero_alpha_zero", [](int x, int y) { return sky(planarAt(x, y)) ? 0.0f : planarAt(x, y); }, {}},
        {"inverse", [](int x, int y) { return sky(planarAt(x, y)) ? 0.0f : 1.0f / planarAt(x, y); }, {"--depth", "inverse"}},
        {"normalized", normalised(kNear, kFar), {"--depth", "normalized", "--depth-range", range}},
        {"normalized_reversed", normalised(kFar, kNear), {"--depth", "normalized", "--depth-range", reversed}},
    };
}

} // namespace

// The closed forms: inverse 1/v, normalised A + v (B - A); every sky +inf; invalid stays invalid.
TEST(DepthEncodings, DecodeToPlanarWithEveryKindOfSkyAtInfinity) {
    Image d(7, 1, 1);
    d.pixels = {2.0f, 0.5f, 0.0f, kInf, -kInf, NAN, -1.0f};
    decodeDepth(d, {DepthEncoding::Inverse, std::nullopt});
    EXPECT_EQ(d.pixels[0], 0.5f);
    EXPECT_EQ(d.pixels[1], 2.0f);
    for (int i : {2, 3, 4}) EXPECT_EQ(d.pixels[i], kInf) << i;
    EXPECT_TRUE(std::isnan(d.pixels[5]));
    EXPECT_LT(d.pixels[6], 0.0f);

    Image n(5, 1, 1);
    n.pixels = {0.0f, 0.25f, 1.0f, 1.5f, -kInf};
    Image r = n;
    decodeDepth(n, {DepthEncoding::Normalized, std::array<double, 2>{2.0, 10.0}});
    EXPECT_EQ(n.pixels[0], 2.0f);
    EXPECT_EQ(n.pixels[1], 4.0f);
    for (int i : {2, 3, 4}) EXPECT_EQ(n.pixels[i], kInf) << i;  // the far end and beyond are sky
    decodeDepth(r, {DepthEncoding::Normalized, std::array<double, 2>{10.0, 2.0}});  // white near
    EXPECT_EQ(r.pixels[0], kInf);
    EXPECT_EQ(r.pixels[1], 8.0f);
    EXPECT_EQ(r.pixels[2], 2.0f);
    EXPECT_THROW(decodeDepth(r, {DepthEncoding::Normalized, std::nullopt}), Error);
}

// Each encoding of the same scene decodes to the planar depth (to float rounding) and writes
// the planar file's AO, as does a position pass with no depth at all.
TEST(DepthEncodings, EachEncodingGivesThePlanarResult) {
    const fs::path dir = testDir("depth-encodings");
    const std::string planar = writeScene(dir, "planar", planarAt);
    ASSERT_EQ(run(planar, (dir / "planar_ao.exr").string(), {}).exitCode, 0);
    const std::vector<float> want = aoOf((dir / "planar_ao.exr").string());
    std::vector<Encoded> cases = encodings();
    cases.push_back({"position_only", nullptr, {}});
    for (const Encoded& e : cases) {
        SCOPED_TRACE(e.name);
        const std::string in = e.stored ? writeScene(dir, e.name, e.stored) : writeScene(dir, e.name, nullptr, "P");
        const Image depth = decodedDepth(in, e.flags);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
                const float z = planarAt(x, y), got = *depth.at(x, y);
                if (sky(z)) ASSERT_EQ(got, kInf) << x << "," << y;
                else ASSERT_NEAR(got, z, 2e-6 * std::max(1.0f, z)) << x << "," << y;
            }
        const std::string out = (dir / (std::string(e.name) + "_ao.exr")).string();
        const CliResult r = run(in, out, e.flags);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const std::vector<float> ao = aoOf(out);
        double worst = 0;
        for (size_t i = 0; i < ao.size(); ++i) worst = std::max(worst, (double)std::abs(ao[i] - want[i]));
        EXPECT_LE(worst, 1e-3) << "AO against the planar file's";
    }
}

// A radial depth (distance to the eye) through --depth radial is the planar depth times the
// ray's length per unit of z, and the operator's radial mode runs on it as it is: the file gives
// the AO of the operator on the same radial planes. (That mode forms sample offsets as the
// difference of two points, common.glsl's viewOffset, where planar has a cancellation-free form,
// so its AO is not the planar file's to float rounding: 7e-3 apart at most on this scene.)
TEST(DepthEncodings, RadialIsTheOperatorsRadialMode) {
    const fs::path dir = testDir("depth-encodings");
    const SceneBuffers radial = renderScene(studioScene(), studioCamera(kW, kH), Box2i{0, 0, kW, kH},
                                            Box2i{0, 0, kW, kH}, DepthKind::Radial);
    const std::string in = writeScene(dir, "radial", [&radial](int x, int y) { return *radial.depth.at(x, y); });
    const Image depth = decodedDepth(in, {"--depth", "radial"});
    const Camera& cam = planarScene().camera;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) {
            const float z = planarAt(x, y);
            if (sky(z)) continue;
            const double rx = (x + 0.5 - cam.cx) / cam.fx, ry = (y + 0.5 - cam.cy) / cam.fy;
            ASSERT_NEAR(*depth.at(x, y), z * std::sqrt(1.0 + rx * rx + ry * ry), 2e-6 * z) << x << "," << y;
        }
    const CliResult r = run(in, (dir / "r.exr").string(), {"--depth", "radial"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    Settings s;
    s.threads = 2;
    const OperatorOutputs want = runOperator(radial.inputs(), s);
    const std::vector<float> got = aoOf((dir / "r.exr").string());
    for (size_t i = 0; i < got.size(); ++i) ASSERT_EQ(got[i], want.ao.pixels[i]) << i;
}

// What cannot be decoded: one line naming the file, nothing written; a range without
// --depth normalized is a usage error.
TEST(DepthEncodings, NormalizedWithoutARangeIsOneLineNamingTheFile) {
    const fs::path dir = testDir("depth-encodings");
    const std::string in = writeScene(dir, "normalized", encodings()[4].stored), out = (dir / "never.exr").string();
    const CliResult r = run(in, out, {"--depth", "normalized"});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("obscura: '" + in + "': ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find("--depth-range NEAR,FAR"), std::string::npos) << r.err;
    for (const auto& entry : fs::directory_iterator(dir))
        EXPECT_EQ(entry.path().filename().string().rfind("never", 0), std::string::npos) << entry.path();
    const CliResult range = run(in, out, {"--depth-range", "1,2"});
    EXPECT_EQ(range.exitCode, 2);
    EXPECT_NE(range.err.find("--depth-range is read by --depth normalized only"), std::string::npos) << range.err;
    const CliResult same = run(in, out, {"--depth", "normalized", "--depth-range", "3,3"});
    EXPECT_EQ(same.exitCode, 2);
    EXPECT_NE(same.err.find("two different ends"), std::string::npos) << same.err;
    EXPECT_FALSE(fs::exists(out));
}

// --inspect describes the depth as stored, and says when it looks like an inverse or normalised one.
TEST(DepthEncodings, InspectDescribesTheStoredDepth) {
    const fs::path dir = testDir("depth-encodings");
    long long skyPixels = 0;
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) skyPixels += sky(planarAt(x, y));
    ASSERT_GT(skyPixels, 0);
    char share[32];
    std::snprintf(share, sizeof share, "sky %.1f%%, float", 100.0 * skyPixels / (kW * kH));
    auto inspect = [&](const std::string& path) {
        std::vector<std::string> args = {path, "--inspect"};
        for (const std::string& f : cameraFlags()) args.push_back(f);  // the position pass needs the pose
        const CliResult r = runProgram(OBSCURA_CLI_PATH, args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return r.out;
    };
    const std::string planar = inspect(writeScene(dir, "planar", encodings()[0].stored));
    EXPECT_NE(planar.find(share), std::string::npos) << planar;
    EXPECT_EQ(planar.find("looks like"), std::string::npos) << planar;
    const std::string inverse = inspect(writeScene(dir, "inverse", encodings()[3].stored));
    EXPECT_NE(inverse.find(share), std::string::npos) << inverse;
    EXPECT_NE(inverse.find("looks like every value is in [0, 1]: an inverse (--depth inverse)"), std::string::npos) << inverse;
    const std::string normalized = inspect(writeScene(dir, "normalized", encodings()[4].stored));
    EXPECT_NE(normalized.find("looks like a normalised depth whose far end (1) is the sky"), std::string::npos) << normalized;
    const std::string position = inspect(writeScene(dir, "position_only", nullptr, "P"));
    EXPECT_NE(position.find("(from the position pass and camera)"), std::string::npos) << position;
}

// A run says what the depth's values say: one that looks inverse or normalised, read as a distance
// because no --depth was given, and one with no surface at all (AO 1 everywhere), each warned of
// while the run goes on; with the right --depth, nothing.
TEST(DepthEncodings, TheRunWarnsOfADepthThatIsNoDistance) {
    const fs::path dir = testDir("depth-encodings");
    const std::string out = (dir / "warned.exr").string();
    const auto warned = [&](const std::string& in, const std::vector<std::string>& flags) {
        std::vector<std::string> args = {in, "-o", out, "--threads", "2"};
        args.insert(args.end(), flags.begin(), flags.end());
        for (const std::string& f : cameraFlags()) args.push_back(f);
        const CliResult r = runProgram(OBSCURA_CLI_PATH, args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        return r.err;
    };
    const std::string inverse = writeScene(dir, "inverse_warned", encodings()[3].stored);
    EXPECT_NE(warned(inverse, {}).find("warning: the depth is read as a distance, though it looks like every value is in "
                                       "[0, 1]: an inverse (--depth inverse)"),
              std::string::npos);
    EXPECT_EQ(warned(inverse, {"--depth", "inverse"}).find("warning"), std::string::npos);
    const std::string zero = writeScene(dir, "zero", [](int, int) { return 0.0f; });
    EXPECT_NE(warned(zero, {}).find("warning: the depth holds no surface"), std::string::npos);
    EXPECT_EQ(warned(writeScene(dir, "planar_warned", encodings()[0].stored), {}).find("warning"), std::string::npos);
}
