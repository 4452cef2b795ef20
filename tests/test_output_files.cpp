// How outputs are written. --write new: a file holding only the computed layers, with the
// input's windows, camera and colour attributes and a lossless codec, and values equal to what
// --write copy adds. Copy mode with a lossy input codec: the layers in a lossless part of their own.
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using obscura::test::CliResult;

namespace {

CliResult cli(std::vector<std::string> args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

std::string describe(const CliResult& r) { return "exit " + std::to_string(r.exitCode) + "\n" + r.out + r.err; }

// The studio scene under generic names, with an overscan data window and the attributes a
// renderer leaves: camera matrices, V-Ray-style camera values, chromaticities, a cryptomatte
// manifest, plus beauty channels that --write new must not carry.
const Imath::Box2i kDisplay(Imath::V2i(0, 0), Imath::V2i(47, 35));
const Imath::Box2i kData(Imath::V2i(-4, -3), Imath::V2i(51, 38));
const Imath::M44f kWorldToCamera(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0.5f, -1.5f, 3, 1);
const Imath::M44f kWorldToNdc(2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 1, 0, 0, -0.1f, 0);
const Imf::Chromaticities kChroma(Imath::V2f(0.713f, 0.293f), Imath::V2f(0.165f, 0.830f),
                                  Imath::V2f(0.128f, 0.044f), Imath::V2f(0.32168f, 0.33767f));

struct Scene {
    obscura::test::SceneBuffers buffers;
    std::vector<std::string> cameraFlags;
};

Scene studio() {
    const int w = kDisplay.max.x + 1, h = kDisplay.max.y + 1;
    const Camera cam = obscura::test::studioCamera(w, h);
    Scene s{obscura::test::renderScene(obscura::test::studioScene(), cam, Box2i{0, 0, w, h},
                                       Box2i{kData.min.x, kData.min.y, kData.max.x + 1, kData.max.y + 1}),
            {}};
    std::string m;
    char buf[40];
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) {
            std::snprintf(buf, sizeof buf, "%.17g", cam.cameraToWorld[c][r]);
            m += (m.empty() ? "" : ",") + std::string(buf);
        }
    std::snprintf(buf, sizeof buf, "%.17g", cam.horizontalFovRad(w) * 180.0 / M_PI);
    s.cameraFlags = {"--fov-deg", buf, "--camera-to-world", m};
    return s;
}

FixtureChannel planeChannel(const std::string& name, const Image& img, int c) {
    return {name, Imf::FLOAT, 1, 1, [&img, c](int x, int y) { return img.at(x - kData.min.x, y - kData.min.y)[c]; }};
}

FixturePart geometryPart(const Scene& s, Imf::Compression compression) {
    FixturePart part;
    part.displayWindow = kDisplay;
    part.dataWindow = kData;
    part.compression = compression;
    part.channels.push_back(planeChannel("Z", s.buffers.depth, 0));
    for (int c = 0; c < 3; ++c) part.channels.push_back(planeChannel(std::string("N.") + "XYZ"[c], s.buffers.normal, c));
    part.stringAttributes = {{"cryptomatte/abc1234/manifest", "{}"}, {"renderer", "test"}};
    part.floatAttributes = {{"cameraFov", 52.5f}, {"cameraFocalLength", 35.0f}};
    part.editHeader = [](Imf::Header& h) {
        Imf::addWorldToCamera(h, kWorldToCamera);
        Imf::addWorldToNDC(h, kWorldToNdc);
        Imf::addChromaticities(h, kChroma);
    };
    return part;
}

FixturePart beautyPart(Imf::Compression compression) {
    FixturePart part;
    part.displayWindow = kDisplay;
    part.dataWindow = kData;
    part.compression = compression;
    for (const char* c : {"R", "G", "B", "A"}) part.channels.push_back({c, Imf::HALF, 1, 1, {}});
    return part;
}

// One part holding geometry and beauty.
std::string writeSinglePart(const fs::path& dir, const Scene& s, Imf::Compression compression) {
    FixturePart part = geometryPart(s, compression);
    for (const FixtureChannel& c : beautyPart(compression).channels) part.channels.push_back(c);
    const std::string path = (dir / "in.exr").string();
    writeFixture(path, {part});
    return path;
}

struct PartData {
    Imf::Header header;
    std::vector<std::string> channels;
};

std::vector<PartData> partsOf(const std::string& path) {
    Imf::MultiPartInputFile file(path.c_str());
    std::vector<PartData> parts;
    for (int p = 0; p < file.parts(); ++p) {
        PartData d{file.header(p), {}};
        for (auto it = d.header.channels().begin(); it != d.header.channels().end(); ++it) d.channels.push_back(it.name());
        parts.push_back(std::move(d));
    }
    return parts;
}

// One channel, converted to float by OpenEXR, over its part's data window.
std::vector<float> channelOf(const std::string& path, int part, const std::string& name) {
    Imf::MultiPartInputFile file(path.c_str());
    Imf::InputPart in(file, part);
    const Imath::Box2i dw = in.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::vector<float> v((size_t)w * h, -1.0f);
    Imf::FrameBuffer fb;
    fb.insert(name, Imf::Slice::Make(Imf::FLOAT, v.data(), dw));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return v;
}

nlohmann::json readJson(const fs::path& p) {
    std::ifstream f(p);
    return nlohmann::json::parse(f);
}

std::vector<std::string> withCamera(const Scene& s, std::vector<std::string> args) {
    args.insert(args.end(), s.cameraFlags.begin(), s.cameraFlags.end());
    return args;
}

// Runs copy and new on `in` with `extra`; expects the new file to hold exactly `layers`, each
// equal to the copy's channel of that name; returns the new file's path.
std::string expectNewEqualsCopy(const fs::path& dir, const Scene& s, const std::string& in, int depthPart,
                                const std::vector<std::string>& extra, const std::vector<std::string>& layers) {
    const std::string copy = (dir / "copy.exr").string(), fresh = (dir / "new.exr").string();
    std::vector<std::string> base = withCamera(s, {in, "--quiet", "--threads", "2"});
    base.insert(base.end(), extra.begin(), extra.end());
    std::vector<std::string> copyArgs = base, newArgs = base;
    copyArgs.insert(copyArgs.end(), {"-o", copy});
    newArgs.insert(newArgs.end(), {"-o", fresh, "--write", "new", "--report", (dir / "new.json").string()});
    const CliResult rc = cli(copyArgs), rn = cli(newArgs);
    EXPECT_EQ(rc.exitCode, 0) << describe(rc);
    EXPECT_EQ(rn.exitCode, 0) << describe(rn);
    if (rc.exitCode || rn.exitCode) return fresh;

    const std::vector<PartData> parts = partsOf(fresh);
    EXPECT_EQ(parts.size(), 1u);
    std::vector<std::string> want = layers;
    std::sort(want.begin(), want.end());
    EXPECT_EQ(parts[0].channels, want);  // OpenEXR lists channels sorted
    for (const std::string& name : layers) {
        const std::vector<float> a = channelOf(copy, depthPart, name), b = channelOf(fresh, 0, name);
        EXPECT_EQ(a, b) << name << " differs between --write copy and --write new";
    }
    return fresh;
}

TEST(WriteNew, HoldsOnlyTheAoWithTheInputsWindowsAndCameraAttributes) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studio();
    const std::string in = writeSinglePart(dir, s, Imf::PIZ_COMPRESSION);
    const std::string out = expectNewEqualsCopy(dir, s, in, 0, {}, {"obscura.AO.Y"});
    if (HasFailure()) return;

    const Imf::Header h = partsOf(out)[0].header;
    EXPECT_EQ(h.displayWindow(), kDisplay);
    EXPECT_EQ(h.dataWindow(), kData);
    EXPECT_EQ(h.compression(), Imf::PIZ_COMPRESSION);
    ASSERT_TRUE(Imf::hasWorldToCamera(h));
    EXPECT_EQ(Imf::worldToCamera(h), kWorldToCamera);
    ASSERT_TRUE(Imf::hasWorldToNDC(h));
    EXPECT_EQ(Imf::worldToNDC(h), kWorldToNdc);
    ASSERT_TRUE(Imf::hasChromaticities(h));
    EXPECT_EQ(Imf::chromaticities(h).red, kChroma.red);
    EXPECT_EQ(Imf::chromaticities(h).white, kChroma.white);
    ASSERT_NE(h.findTypedAttribute<Imf::FloatAttribute>("cameraFov"), nullptr);
    EXPECT_EQ(h.typedAttribute<Imf::FloatAttribute>("cameraFov").value(), 52.5f);
    ASSERT_NE(h.findTypedAttribute<Imf::StringAttribute>("renderer"), nullptr);
    EXPECT_EQ(h.findTypedAttribute<Imf::StringAttribute>("cryptomatte/abc1234/manifest"), nullptr)
        << "a manifest of channels the file does not hold was carried";
    EXPECT_NE(h.findTypedAttribute<Imf::StringAttribute>("obscura/version"), nullptr);
    EXPECT_NE(h.findTypedAttribute<Imf::StringAttribute>("obscura/obscura.AO.Y/colorspace"), nullptr);

    const nlohmann::json report = readJson(dir / "new.json");
    EXPECT_EQ(report["write"]["mode"], "new");
    EXPECT_NE(report["write"]["description"].get<std::string>().find("piz"), std::string::npos) << report["write"];
    EXPECT_EQ(report["written"], nlohmann::json::array({"obscura.AO.Y"}));
}

TEST(WriteNew, SsdoLayersEqualTheCopys) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studio();
    const std::string in = writeSinglePart(dir, s, Imf::ZIPS_COMPRESSION);
    const std::string out = expectNewEqualsCopy(
        // GI without relit (--bounce would add relit, which needs an albedo pass this file lacks).
        dir, s, in, 0,
        {"--method", "ssdo", "--out-type", "float", "--samples", "8", "--out-layer", "gi=obscura.GI", "--bounce-source",
         "beauty"},
        {"obscura.AO.Y", "obscura.DO.R", "obscura.DO.G", "obscura.DO.B", "obscura.GI.R", "obscura.GI.G", "obscura.GI.B"});
    if (HasFailure()) return;
    EXPECT_EQ(partsOf(out)[0].header.compression(), Imf::ZIPS_COMPRESSION);
}

TEST(WriteNew, LossyCodecsBecomeZip) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studio();
    const std::string in = writeSinglePart(dir, s, Imf::DWAA_COMPRESSION), out = (dir / "new.exr").string();
    const CliResult r = cli(withCamera(s, {in, "-o", out, "--write", "new", "--report", (dir / "new.json").string()}));
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_EQ(partsOf(out)[0].header.compression(), Imf::ZIP_COMPRESSION);
    const std::string description = readJson(dir / "new.json")["write"]["description"];
    EXPECT_NE(description.find("zip (the input's dwaa is lossy)"), std::string::npos) << description;
}

// The beauty part is cut short: --write new never decodes it, --write copy must and fails.
TEST(WriteNew, DecodesOnlyThePartsItNeeds) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studio();
    FixturePart geometry = geometryPart(s, Imf::ZIP_COMPRESSION), beauty = beautyPart(Imf::NO_COMPRESSION);
    geometry.name = "geometry";
    beauty.name = "beauty";
    const std::string whole = (dir / "whole.exr").string(), in = (dir / "in.exr").string();
    writeFixture(whole, {geometry, beauty});  // beauty's chunks come last
    truncatedCopy(whole, in, fileSize(whole) - 200);

    const CliResult copy = cli(withCamera(s, {in, "-o", (dir / "copy.exr").string()}));
    EXPECT_EQ(copy.exitCode, 1) << describe(copy);
    EXPECT_NE(copy.err.find("truncated or corrupt"), std::string::npos) << copy.err;
    const std::string out = (dir / "new.exr").string();
    const CliResult fresh = cli(withCamera(s, {in, "-o", out, "--write", "new", "--quiet"}));
    ASSERT_EQ(fresh.exitCode, 0) << describe(fresh);
    EXPECT_EQ(partsOf(out)[0].channels, std::vector<std::string>{"obscura.AO.Y"});
    EXPECT_EQ(partsOf(out)[0].header.dataWindow(), kData);
}

TEST(WriteNew, InspectSaysWhichModeWouldRun) {
    const fs::path dir = obscura::test::testDir("write-new");
    const std::string in = writeSinglePart(dir, studio(), Imf::B44_COMPRESSION);
    const CliResult copy = cli({in, "--inspect"}), fresh = cli({in, "--inspect", "--write", "new"});
    ASSERT_EQ(copy.exitCode, 0) << describe(copy);
    ASSERT_EQ(fresh.exitCode, 0) << describe(fresh);
    EXPECT_NE(copy.out.find("write:   copy"), std::string::npos) << copy.out;
    EXPECT_NE(fresh.out.find("write:   new: only the new layers, zip (the input's b44 is lossy)"), std::string::npos)
        << fresh.out;
}

// Every codec OpenEXR has, on input: the AO that --write copy adds is within half precision of
// the computed one (a float AO of --write new, itself checked against copy mode above), and
// a lossy part's codec never touches it.
class InputCodec : public ::testing::TestWithParam<Imf::Compression> {};

std::string codecName(const ::testing::TestParamInfo<Imf::Compression>& info) {
    static const char* const names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    return names[info.param];
}

TEST_P(InputCodec, CopyWritesTheAoWithinHalfPrecision) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studio();
    const Imf::Compression codec = GetParam();
    const bool lossy = codec >= Imf::PXR24_COMPRESSION;  // PXR24, B44, B44A, DWAA, DWAB
    const std::string in = writeSinglePart(dir, s, codec), copy = (dir / "copy.exr").string(),
                      exact = (dir / "exact.exr").string();
    const CliResult rc = cli(withCamera(s, {in, "-o", copy, "--report", (dir / "copy.json").string()}));
    const CliResult re = cli(withCamera(s, {in, "-o", exact, "--write", "new", "--out-type", "float"}));
    ASSERT_EQ(rc.exitCode, 0) << describe(rc);
    ASSERT_EQ(re.exitCode, 0) << describe(re);

    const std::vector<PartData> parts = partsOf(copy);
    ASSERT_EQ(parts.size(), lossy ? 2u : 1u);
    EXPECT_EQ(parts[0].channels.size(), lossy ? 8u : 9u);  // the input's, plus the AO unless lossy
    const int aoPart = lossy ? 1 : 0;
    EXPECT_EQ(parts[aoPart].header.compression(), lossy ? Imf::ZIP_COMPRESSION : codec);
    if (lossy) {
        EXPECT_EQ(parts[1].channels, std::vector<std::string>{"obscura.AO.Y"});
        EXPECT_EQ(parts[1].header.name(), "obscura");
        EXPECT_EQ(parts[1].header.dataWindow(), kData);
        EXPECT_EQ(parts[0].header.compression(), codec);
        EXPECT_TRUE(Imf::hasWorldToCamera(parts[1].header));
    }
    const std::string description = readJson(dir / "copy.json")["write"]["description"];
    EXPECT_EQ(description.find("part of their own") != std::string::npos, lossy) << description;

    const std::vector<float> ao = channelOf(copy, aoPart, "obscura.AO.Y"), ref = channelOf(exact, 0, "obscura.AO.Y");
    ASSERT_EQ(ao.size(), ref.size());
    float worst = 0;
    for (size_t i = 0; i < ao.size(); ++i) {
        ASSERT_LE(ao[i], 1.0f) << "at " << i;
        worst = std::max(worst, std::fabs(ao[i] - ref[i]) / std::max(std::fabs(ref[i]), 1e-3f));
    }
    EXPECT_LE(worst, 1.0f / 2048) << "relative error above half precision";  // half: 10-bit mantissa
}

INSTANTIATE_TEST_SUITE_P(AllCodecs, InputCodec,
                         ::testing::Values(Imf::NO_COMPRESSION, Imf::RLE_COMPRESSION, Imf::ZIPS_COMPRESSION,
                                           Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION, Imf::PXR24_COMPRESSION,
                                           Imf::B44_COMPRESSION, Imf::B44A_COMPRESSION, Imf::DWAA_COMPRESSION,
                                           Imf::DWAB_COMPRESSION),
                         codecName);

// One line, exit 2, nothing written.
TEST(WriteNew, BadCombinationsAreUsageErrors) {
    const fs::path dir = obscura::test::testDir("write-new");
    const std::string in = writeSinglePart(dir, studio(), Imf::ZIP_COMPRESSION);
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{in, "-o", in, "--in-place", "--write", "new"}, "--write new and --in-place"},
        {{in, "-o", (dir / "o.exr").string(), "--write", "layers"}, "--write expects copy, new or append, got 'layers'"},
        {{in, "-o", (dir / "o.exr").string(), "--write"}, "--write needs a value"},
    };
    const auto before = fs::file_size(in);
    for (const auto& [args, message] : cases) {
        const CliResult r = cli(args);
        EXPECT_EQ(r.exitCode, 2) << describe(r);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << describe(r);
        EXPECT_EQ(r.err.rfind("obscura: ", 0), 0u) << describe(r);
        EXPECT_NE(r.err.find(message), std::string::npos) << describe(r);
    }
    EXPECT_FALSE(fs::exists(dir / "o.exr"));
    EXPECT_EQ(fs::file_size(in), before);
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    EXPECT_EQ(names, std::set<std::string>{"in.exr"});
}

} // namespace
