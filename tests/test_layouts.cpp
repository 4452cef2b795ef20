// Every method with every output (AO, DO, GI, relit) on the layouts production files come in:
// a part per layer (as Nuke writes them), a tiled mip-mapped part, lossy codecs (DWAA, B44),
// and a multipart file with a lossy codec. Each run writes; every input channel is kept (its
// values exactly where the codec is lossless); the parts of the output agree on the
// attributes OpenEXR requires them to share; and the colour tags of the new layers name the
// space the file's chromaticities describe.
#include "core/methods.h"
#include "io/colour.h"
#include "io/exr_file.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/studio_render.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;

namespace {

constexpr int kW = 48, kH = 36;
const Imath::Box2i kWindow(Imath::V2i(0, 0), Imath::V2i(kW - 1, kH - 1));
const Imf::Chromaticities kAP1(Imath::V2f(0.713f, 0.293f), Imath::V2f(0.165f, 0.830f), Imath::V2f(0.128f, 0.044f),
                               Imath::V2f(0.32168f, 0.33767f));

struct Layout {
    const char* name;
    bool partPerLayer;          // a part per layer, else one part
    bool tiled;
    Imf::Compression codec;
    bool ap1;                   // the file's chromaticities are ACEScg's; else absent (Rec.709)
};

const obscura::test::SceneBuffers& scene() {
    static const auto sb = obscura::test::renderScene(obscura::test::studioScene(),
                                                      obscura::test::studioCamera(kW, kH), kW, kH);
    return sb;
}

std::vector<std::string> cameraFlags() { return obscura::test::cliCameraFlags(scene().camera, kW); }

FixtureChannel channel(const std::string& name, Imf::PixelType type, int c, const Image* img, float scale = 1) {
    return {name, type, 1, 1, [img, c, scale](int x, int y) { return scale * std::abs(img->at(x, y)[c]) + 0.05f; }};
}

// Beauty (R, G, B, A), depth, normals and albedo, grouped into parts as the layout says.
std::vector<FixturePart> layoutParts(const Layout& l) {
    const auto& sb = scene();
    FixtureChannel depth{"Z", Imf::FLOAT, 1, 1, [&sb](int x, int y) { return sb.depth.at(x, y)[0]; }};
    std::vector<std::vector<FixtureChannel>> groups(4);
    for (int c = 0; c < 3; ++c) {
        groups[0].push_back(channel(std::string(1, "RGB"[c]), Imf::HALF, c, &sb.normal, 0.8f));
        groups[2].push_back({std::string("N.") + "XYZ"[c], Imf::FLOAT, 1, 1,
                             [&sb, c](int x, int y) { return sb.normal.at(x, y)[c]; }});
        groups[3].push_back(channel(std::string("albedo.") + "RGB"[c], Imf::HALF, 2 - c, &sb.normal, 0.5f));
    }
    groups[0].push_back({"A", Imf::HALF, 1, 1, [](int, int) { return 1.0f; }});
    groups[1].push_back(depth);
    const char* names[] = {"rgba", "depth", "N", "albedo"};
    std::vector<FixturePart> parts;
    for (size_t g = 0; g < groups.size(); ++g) {
        if (!l.partPerLayer && g > 0) {
            parts[0].channels.insert(parts[0].channels.end(), groups[g].begin(), groups[g].end());
            continue;
        }
        FixturePart part;
        part.name = l.partPerLayer ? names[g] : "";
        part.channels = groups[g];
        part.displayWindow = part.dataWindow = kWindow;
        part.compression = l.codec;
        part.tiled = l.tiled;
        part.levelMode = l.tiled ? Imf::MIPMAP_LEVELS : Imf::ONE_LEVEL;
        const bool ap1 = l.ap1;
        part.editHeader = [ap1](Imf::Header& h) {
            Imf::addTimeCode(h, Imf::TimeCode(1, 2, 3, 4));
            if (ap1) Imf::addChromaticities(h, kAP1);
        };
        parts.push_back(std::move(part));
    }
    return parts;
}


std::string stringAttr(const Imf::Header& h, const std::string& name) {
    const auto* a = h.findTypedAttribute<Imf::StringAttribute>(name);
    return a ? a->value() : "<missing>";
}

// Every channel of every input part, in the output's part of the same index, with its type and
// its values, exactly: a part that takes new layers has a lossless codec (they go to a part of
// their own otherwise), and a part that takes none is copied chunk for chunk, so a lossy codec
// loses nothing more and a mip-mapped part keeps its levels.
void expectInputKept(const std::string& in, const std::string& out) {
    const ExrInfo a = readExrInfo(in), b = readExrInfo(out);
    ASSERT_GE(b.parts.size(), a.parts.size());
    for (size_t p = 0; p < a.parts.size(); ++p) {
        for (const ExrChannel& ch : a.parts[p].channels) {
            const int i = b.parts[p].findChannel(ch.name);
            ASSERT_GE(i, 0) << ch.name << " of part " << p << " was dropped";
            EXPECT_EQ(b.parts[p].channels[i].type, ch.type) << ch.name;
            const std::vector<float> va = obscura::test::partChannel(in, (int)p, ch.name), vb = obscura::test::partChannel(out, (int)p, ch.name);
            for (size_t k = 0; k < va.size(); ++k) ASSERT_EQ(vb[k], va[k]) << ch.name << " at " << k;
        }
        const Imf::Header &ha = a.parts[p].header, &hb = b.parts[p].header;
        if (b.parts[p].channels.size() == a.parts[p].channels.size() && ha.hasTileDescription()) {
            EXPECT_EQ(hb.tileDescription().mode, ha.tileDescription().mode) << "part " << p << " took nothing new";
        }
    }
}

// The attributes OpenEXR requires parts to share are the first part's in every part.
void expectSharedAttributesAgree(const std::string& out) {
    Imf::MultiPartInputFile file(out.c_str());
    const Imf::Header& first = file.header(0);
    for (int p = 1; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        EXPECT_EQ(h.displayWindow(), first.displayWindow()) << "part " << p;
        EXPECT_EQ(h.pixelAspectRatio(), first.pixelAspectRatio()) << "part " << p;
        ASSERT_EQ(Imf::hasChromaticities(h), Imf::hasChromaticities(first)) << "part " << p;
        if (Imf::hasChromaticities(h)) {
            EXPECT_EQ(Imf::chromaticities(h).red, Imf::chromaticities(first).red);
            EXPECT_EQ(Imf::chromaticities(h).white, Imf::chromaticities(first).white);
        }
        ASSERT_EQ(Imf::hasTimeCode(h), Imf::hasTimeCode(first)) << "part " << p;
        if (Imf::hasTimeCode(h)) {
            EXPECT_EQ(Imf::timeCode(h).timeAndFlags(), Imf::timeCode(first).timeAndFlags());
        }
    }
}

// The part holding `channel`, or -1.
int partHolding(const std::string& path, const std::string& channel) {
    const ExrInfo info = readExrInfo(path);
    for (size_t p = 0; p < info.parts.size(); ++p)
        if (info.parts[p].findChannel(channel) >= 0) return (int)p;
    return -1;
}

// The new layers: AO finite in [0, 1]; DO, GI and relit finite (a colour the file's primaries hold but
// the working space's do not is negative there, and albedo x light need not come back), each tagged
// with the space the part's own chromaticities describe.
void expectNewLayers(const std::string& out, const std::vector<std::string>& colourLayers) {
    const int part = partHolding(out, "obscura.AO.Y");
    ASSERT_GE(part, 0) << "no AO written";
    for (float v : obscura::test::partChannel(out, part, "obscura.AO.Y")) ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
    const Imf::Header h = Imf::MultiPartInputFile(out.c_str()).header(part);
    const std::string fileSpace = colourManager().detectColourSpace(h).name;
    for (const std::string& layer : colourLayers) {
        for (const char* c : {".R", ".G", ".B"}) {
            ASSERT_NE(h.channels().findChannel(layer + c), nullptr) << layer << c << " not written";
            for (float v : obscura::test::partChannel(out, part, layer + c)) ASSERT_TRUE(std::isfinite(v)) << layer << c;
        }
        EXPECT_EQ(stringAttr(h, "obscura/" + layer + "/colorspace"), fileSpace) << layer;
    }
}

class Layouts : public ::testing::TestWithParam<Layout> {};

TEST_P(Layouts, EveryMethodAndOutputWritesAndKeepsTheInput) {
    const Layout& l = GetParam();
    const fs::path dir = obscura::test::testDir("layouts");
    const std::string in = (dir / "in.exr").string();
    writeFixture(in, layoutParts(l));
    for (const MethodInfo& m : methods()) {
        SCOPED_TRACE(m.name);
        const std::string out = (dir / (std::string(m.name) + ".exr")).string();
        std::vector<std::string> args = {in, "-o", out, "--threads", "2", "--method", m.name};
        // Every output the method table lists: a method that writes GI runs with its bounce.
        std::vector<std::string> colourLayers;
        if (methodOutputs(m.name, "do")) {
            args.insert(args.end(), {"--samples", "8"});
            colourLayers.push_back("obscura.DO");
        }
        if (methodOutputs(m.name, "gi")) {
            args.insert(args.end(), {"--bounce", "--bounce-source", "beauty"});
            colourLayers.insert(colourLayers.end(), {"obscura.GI", "obscura.relit"});
        }
        for (const std::string& f : cameraFlags()) args.push_back(f);
        const obscura::test::CliResult r = obscura::test::runProgram(OBSCURA_CLI_PATH, args);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        // A mip-mapped part takes no new layers (it would be encoded again at level 0 only): they
        // go to a part of their own, and every input part keeps its levels.
        const ExrInfo input = readExrInfo(in), output = readExrInfo(out);
        if (l.tiled) {
            EXPECT_GE(partHolding(out, "obscura.AO.Y"), (int)input.parts.size());
        }
        EXPECT_EQ(r.err.find("is mip-mapped"), std::string::npos) << r.err;
        for (size_t p = 0; p < input.parts.size(); ++p) {
            const Imf::Header &a = input.parts[p].header, &b = output.parts[p].header;
            ASSERT_EQ(b.hasTileDescription(), a.hasTileDescription()) << "part " << p;
            if (a.hasTileDescription()) {
                EXPECT_EQ(b.tileDescription().mode, a.tileDescription().mode) << "part " << p;
            }
        }
        expectInputKept(in, out);
        expectSharedAttributesAgree(out);
        expectNewLayers(out, colourLayers);
        // Run again in place (a farm's re-run), the layers replace the earlier run's where they
        // are: no part is added, one part holds the AO (a lossy or mip-mapped depth part gained a
        // part each run).
        for (int again = 0; again < 2; ++again) {
            std::vector<std::string> rerun = args;
            rerun[0] = out;
            rerun.insert(rerun.end(), {"--in-place", "--quiet"});
            const obscura::test::CliResult r2 = obscura::test::runProgram(OBSCURA_CLI_PATH, rerun);
            ASSERT_EQ(r2.exitCode, 0) << r2.err;
            const ExrInfo after = readExrInfo(out);
            EXPECT_EQ(after.parts.size(), output.parts.size()) << "run " << again << " in place added a part";
            int aoParts = 0;
            for (const ExrPart& part : after.parts) aoParts += part.findChannel("obscura.AO.Y") >= 0 ? 1 : 0;
            EXPECT_EQ(aoParts, 1);
        }
        expectNewLayers(out, colourLayers);
    }
}

INSTANTIATE_TEST_SUITE_P(
    Files, Layouts,
    ::testing::Values(Layout{"part_per_layer", true, false, Imf::ZIP_COMPRESSION, false},
                      Layout{"part_per_layer_ap1", true, false, Imf::PIZ_COMPRESSION, true},
                      Layout{"tiled_mipmapped_ap1", false, true, Imf::ZIP_COMPRESSION, true},
                      Layout{"part_per_layer_tiled_mipmapped", true, true, Imf::PIZ_COMPRESSION, false},
                      Layout{"dwaa", false, false, Imf::DWAA_COMPRESSION, false},
                      Layout{"b44_ap1", false, false, Imf::B44_COMPRESSION, true},
                      Layout{"part_per_layer_dwab", true, false, Imf::DWAB_COMPRESSION, false}),
    [](const ::testing::TestParamInfo<Layout>& info) { return std::string(info.param.name); });

} // namespace
