// How outputs are written. --write new: a file holding only the computed layers, with the
// input's windows, camera and colour attributes and a lossless codec, and values equal to what
// --write copy adds. Copy mode with a lossy input codec: the layers in a lossless part of their own.
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/studio_render.h"
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
using namespace obscura::test;

namespace {

// The studio render (tests/support/studio_render.h) under generic names, with the attributes a
// renderer leaves: camera matrices, V-Ray-style camera values, chromaticities, a cryptomatte
// manifest, plus beauty channels that --write new must not carry.
const Imath::M44f kWorldToNdc(2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 1, 0, 0, -0.1f, 0);

using Scene = obscura::test::StudioRender;

FixturePart geometryPart(Imf::Compression compression) {
    FixturePart part = studioGeometryPart(compression);
    part.stringAttributes = {{"cryptomatte/abc1234/manifest", "{}"}, {"renderer", "test"}};
    part.floatAttributes = {{"cameraFov", 52.5f}, {"cameraFocalLength", 35.0f}};
    part.editHeader = [](Imf::Header& h) {
        Imf::addWorldToCamera(h, kStudioWorldToCamera);
        Imf::addWorldToNDC(h, kWorldToNdc);
        Imf::addChromaticities(h, kAcesCgPrimaries);
    };
    return part;
}

FixturePart beautyPart(Imf::Compression compression) {
    FixturePart part;
    part.displayWindow = kStudioDisplay;
    part.dataWindow = kStudioData;
    part.compression = compression;
    for (const char* c : {"R", "G", "B", "A"}) part.channels.push_back({c, Imf::HALF, 1, 1, {}});
    return part;
}

// One part holding geometry and beauty.
std::string writeSinglePart(const fs::path& dir, Imf::Compression compression) {
    FixturePart part = geometryPart(compression);
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
    const CliResult rc = runObscura(copyArgs), rn = runObscura(newArgs);
    EXPECT_EQ(rc.exitCode, 0) << outcome(rc);
    EXPECT_EQ(rn.exitCode, 0) << outcome(rn);
    if (rc.exitCode || rn.exitCode) return fresh;

    const std::vector<PartData> parts = partsOf(fresh);
    EXPECT_EQ(parts.size(), 1u);
    std::vector<std::string> want = layers;
    std::sort(want.begin(), want.end());
    EXPECT_EQ(parts[0].channels, want);  // OpenEXR lists channels sorted
    for (const std::string& name : layers) {
        const std::vector<float> a = partChannel(copy, depthPart, name), b = partChannel(fresh, 0, name);
        EXPECT_EQ(a, b) << name << " differs between --write copy and --write new";
    }
    return fresh;
}

TEST(WriteNew, HoldsOnlyTheAoWithTheInputsWindowsAndCameraAttributes) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studioRender();
    const std::string in = writeSinglePart(dir, Imf::PIZ_COMPRESSION);
    const std::string out = expectNewEqualsCopy(dir, s, in, 0, {}, {"obscura.AO.Y"});
    if (HasFailure()) return;

    const Imf::Header h = partsOf(out)[0].header;
    EXPECT_EQ(h.displayWindow(), kStudioDisplay);
    EXPECT_EQ(h.dataWindow(), kStudioData);
    EXPECT_EQ(h.compression(), Imf::PIZ_COMPRESSION);
    ASSERT_TRUE(Imf::hasWorldToCamera(h));
    EXPECT_EQ(Imf::worldToCamera(h), kStudioWorldToCamera);
    ASSERT_TRUE(Imf::hasWorldToNDC(h));
    EXPECT_EQ(Imf::worldToNDC(h), kWorldToNdc);
    ASSERT_TRUE(Imf::hasChromaticities(h));
    EXPECT_EQ(Imf::chromaticities(h).red, kAcesCgPrimaries.red);
    EXPECT_EQ(Imf::chromaticities(h).white, kAcesCgPrimaries.white);
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
    const Scene s = studioRender();
    const std::string in = writeSinglePart(dir, Imf::ZIPS_COMPRESSION);
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
    const Scene s = studioRender();
    const std::string in = writeSinglePart(dir, Imf::DWAA_COMPRESSION), out = (dir / "new.exr").string();
    const CliResult r = runObscura(withCamera(s, {in, "-o", out, "--write", "new", "--report", (dir / "new.json").string()}));
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_EQ(partsOf(out)[0].header.compression(), Imf::ZIP_COMPRESSION);
    const std::string description = readJson(dir / "new.json")["write"]["description"];
    EXPECT_NE(description.find("zip (the input's dwaa is lossy)"), std::string::npos) << description;
}

// The beauty part is cut short: --write new never decodes it, --write copy must and fails.
TEST(WriteNew, DecodesOnlyThePartsItNeeds) {
    const fs::path dir = obscura::test::testDir("write-new");
    const Scene s = studioRender();
    FixturePart geometry = geometryPart(Imf::ZIP_COMPRESSION), beauty = beautyPart(Imf::NO_COMPRESSION);
    geometry.name = "geometry";
    beauty.name = "beauty";
    const std::string whole = (dir / "whole.exr").string(), in = (dir / "in.exr").string();
    writeFixture(whole, {geometry, beauty});  // beauty's chunks come last
    truncatedCopy(whole, in, fileSize(whole) - 200);

    const CliResult copy = runObscura(withCamera(s, {in, "-o", (dir / "copy.exr").string()}));
    EXPECT_EQ(copy.exitCode, 1) << outcome(copy);
    EXPECT_NE(copy.err.find("truncated or corrupt"), std::string::npos) << copy.err;
    const std::string out = (dir / "new.exr").string();
    const CliResult fresh = runObscura(withCamera(s, {in, "-o", out, "--write", "new", "--quiet"}));
    ASSERT_EQ(fresh.exitCode, 0) << outcome(fresh);
    EXPECT_EQ(partsOf(out)[0].channels, std::vector<std::string>{"obscura.AO.Y"});
    EXPECT_EQ(partsOf(out)[0].header.dataWindow(), kStudioData);
}

TEST(WriteNew, InspectSaysWhichModeWouldRun) {
    const fs::path dir = obscura::test::testDir("write-new");
    const std::string in = writeSinglePart(dir, Imf::B44_COMPRESSION);
    const CliResult copy = runObscura({in, "--inspect"}), fresh = runObscura({in, "--inspect", "--write", "new"});
    ASSERT_EQ(copy.exitCode, 0) << outcome(copy);
    ASSERT_EQ(fresh.exitCode, 0) << outcome(fresh);
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
    const Scene s = studioRender();
    const Imf::Compression codec = GetParam();
    const bool lossy = codec >= Imf::PXR24_COMPRESSION;  // PXR24, B44, B44A, DWAA, DWAB
    const std::string in = writeSinglePart(dir, codec), copy = (dir / "copy.exr").string(),
                      exact = (dir / "exact.exr").string();
    const CliResult rc = runObscura(withCamera(s, {in, "-o", copy, "--report", (dir / "copy.json").string()}));
    const CliResult re = runObscura(withCamera(s, {in, "-o", exact, "--write", "new", "--out-type", "float"}));
    ASSERT_EQ(rc.exitCode, 0) << outcome(rc);
    ASSERT_EQ(re.exitCode, 0) << outcome(re);

    const std::vector<PartData> parts = partsOf(copy);
    ASSERT_EQ(parts.size(), lossy ? 2u : 1u);
    EXPECT_EQ(parts[0].channels.size(), lossy ? 8u : 9u);  // the input's, plus the AO unless lossy
    const int aoPart = lossy ? 1 : 0;
    EXPECT_EQ(parts[aoPart].header.compression(), lossy ? Imf::ZIP_COMPRESSION : codec);
    if (lossy) {
        EXPECT_EQ(parts[1].channels, std::vector<std::string>{"obscura.AO.Y"});
        EXPECT_EQ(parts[1].header.name(), "obscura");
        EXPECT_EQ(parts[1].header.dataWindow(), kStudioData);
        EXPECT_EQ(parts[0].header.compression(), codec);
        EXPECT_TRUE(Imf::hasWorldToCamera(parts[1].header));
    }
    const std::string description = readJson(dir / "copy.json")["write"]["description"];
    EXPECT_EQ(description.find("part of their own") != std::string::npos, lossy) << description;

    const std::vector<float> ao = partChannel(copy, aoPart, "obscura.AO.Y"), ref = partChannel(exact, 0, "obscura.AO.Y");
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
    const std::string in = writeSinglePart(dir, Imf::ZIP_COMPRESSION);
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{in, "-o", in, "--in-place", "--write", "new"}, "--write new and --in-place"},
        {{in, "-o", (dir / "o.exr").string(), "--write", "layers"}, "--write expects copy, new or append, got 'layers'"},
        {{in, "-o", (dir / "o.exr").string(), "--write"}, "--write needs a value"},
    };
    const auto before = fs::file_size(in);
    for (const auto& [args, message] : cases) {
        const CliResult r = runObscura(args);
        EXPECT_EQ(r.exitCode, 2) << outcome(r);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << outcome(r);
        EXPECT_EQ(r.err.rfind("obscura: ", 0), 0u) << outcome(r);
        EXPECT_NE(r.err.find(message), std::string::npos) << outcome(r);
    }
    EXPECT_FALSE(fs::exists(dir / "o.exr"));
    EXPECT_EQ(fs::file_size(in), before);
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    EXPECT_EQ(names, std::set<std::string>{"in.exr"});
}

} // namespace
