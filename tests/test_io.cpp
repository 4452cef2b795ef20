// File layer: EXR reading and writing (parts, tiles, windows, subsampling), and its errors.
// Renderer presets: test_presets.cpp.
#include "base/error.h"
#include "io/exr_file.h"
#include "io/layers.h"
#include "support/exr_fixtures.h"
#include "support/expect_error.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineOutputFile.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <Imath/half.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace obscura;
using namespace obscura::fixtures;
using obscura::test::expectError;

namespace {

std::string tmp(const std::string& name) {
    fs::path dir = fs::path(OBSCURA_TEST_TMP) / ("io-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return (dir / name).string();
}

// Scratch files go when every test passed; kept for inspection otherwise.
struct ScratchCleanup : ::testing::Environment {
    void TearDown() override {
        if (::testing::UnitTest::GetInstance()->Passed())
            fs::remove_all(fs::path(OBSCURA_TEST_TMP) / ("io-" + std::to_string(::getpid())));
    }
};
const auto* const kCleanup = ::testing::AddGlobalTestEnvironment(new ScratchCleanup);

const std::string kRoom = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";

std::string attrBytes(const Imf::Attribute& a) {
    Imf::StdOSStream os;
    a.writeValueTo(os, 2);
    return std::string(a.typeName()) + ":" + os.str();
}

unsigned char versionFlags(const std::string& path) {  // byte 5: 0x02 tiled, 0x08 deep, 0x10 multipart
    std::ifstream f(path, std::ios::binary);
    char b[8] = {};
    f.read(b, 8);
    return (unsigned char)b[5];
}

bool tempLeft(const std::string& out) {
    fs::path p(out);
    for (const auto& e : fs::directory_iterator(p.parent_path()))
        if (e.path().filename().string().rfind(p.filename().string() + ".tmp-", 0) == 0) return true;
    return false;
}

} // namespace

// ----------------------------------------------------------------- reading

namespace {

// Display (10,20)-(25,31); part 0 scanline with overscan, part 1 tiled half inside it.
std::vector<FixturePart> multipartFixture() {
    Imath::Box2i display(Imath::V2i(10, 20), Imath::V2i(25, 31));
    FixturePart a;
    a.name = "rgba";
    a.displayWindow = display;
    a.dataWindow = Imath::Box2i(Imath::V2i(7, 18), Imath::V2i(28, 33));
    a.lineOrder = Imf::DECREASING_Y;
    a.channels = {{"A", Imf::HALF, 1, 1, {}}, {"B", Imf::FLOAT, 1, 1, {}}, {"G", Imf::FLOAT, 1, 1, {}},
                  {"R", Imf::FLOAT, 1, 1, {}}, {"id", Imf::UINT, 1, 1, {}}};
    a.stringAttributes = {{"owner", "obscura tests"}, {"note", "keep me"}};
    a.floatAttributes = {{"exposure", 1.5f}};
    FixturePart b;
    b.name = "aux";
    b.displayWindow = display;
    b.dataWindow = Imath::Box2i(Imath::V2i(12, 21), Imath::V2i(22, 29));
    b.tiled = true;
    b.tileWidth = 4;
    b.tileHeight = 3;
    b.compression = Imf::PIZ_COMPRESSION;
    b.channels = {{"N.X", Imf::HALF, 1, 1, {}}, {"N.Y", Imf::HALF, 1, 1, {}}, {"N.Z", Imf::HALF, 1, 1, {}},
                  {"Z", Imf::FLOAT, 1, 1, {}}};
    b.stringAttributes = {{"partNote", "aux data"}};
    return {a, b};
}

// Every pixel of `img` equals the fixture channel at the part's EXR data window.
void expectPlane(const Image& img, const FixtureChannel& ch, const Imath::Box2i& dw) {
    ASSERT_EQ(img.channels, 1);
    ASSERT_EQ(img.width, dw.max.x - dw.min.x + 1);
    ASSERT_EQ(img.height, dw.max.y - dw.min.y + 1);
    int bad = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            bad += *img.at(x, y) != storedValue(ch, dw.min.x + x, dw.min.y + y);
    EXPECT_EQ(bad, 0) << ch.name;
}

} // namespace

TEST(ExrRead, MultipartTiledHalfOverscanWindows) {
    auto parts = multipartFixture();
    std::string path = tmp("multi.exr");
    writeFixture(path, parts);
    EXPECT_EQ(versionFlags(path) & 0x10, 0x10);
    ExrInfo info = readExrInfo(path);
    EXPECT_EQ(info.path, path);
    ASSERT_TRUE(info.multipart);
    ASSERT_EQ(info.parts.size(), 2u);
    EXPECT_EQ(info.parts[0].name, "rgba");
    EXPECT_EQ(info.parts[1].name, "aux");
    EXPECT_FALSE(info.parts[0].tiled);
    EXPECT_TRUE(info.parts[1].tiled);
    EXPECT_EQ(info.parts[0].displayWindow, (Box2i{0, 0, 16, 12}));
    EXPECT_EQ(info.parts[0].dataWindow, (Box2i{-3, -2, 19, 14}));  // overscan: negative origin
    EXPECT_EQ(info.parts[1].dataWindow, (Box2i{2, 1, 13, 10}));
    ASSERT_EQ(info.parts[0].channels.size(), 5u);
    EXPECT_EQ(info.parts[0].channels[0].name, "A");
    EXPECT_EQ(info.parts[0].channels[0].type, Imf::HALF);
    EXPECT_EQ(info.parts[0].channels[4].type, Imf::UINT);
    EXPECT_EQ(info.parts[1].findChannel("Z"), 3);

    std::vector<ChannelRef> wanted = {{0, "A"}, {0, "id"}, {1, "N.Y"}, {1, "Z"}, {0, "R"}};
    for (bool keepAll : {false, true}) {
        ExrPixels px;
        auto planes = readExrChannels(path, info, wanted, keepAll, keepAll ? &px : nullptr);
        ASSERT_EQ(planes.size(), wanted.size());
        expectPlane(planes[0], parts[0].channels[0], parts[0].dataWindow);
        expectPlane(planes[1], parts[0].channels[4], parts[0].dataWindow);
        expectPlane(planes[2], parts[1].channels[1], parts[1].dataWindow);
        expectPlane(planes[3], parts[1].channels[3], parts[1].dataWindow);
        expectPlane(planes[4], parts[0].channels[3], parts[0].dataWindow);
        if (keepAll) {
            ASSERT_EQ(px.raw.size(), 2u);
            EXPECT_EQ(px.raw[0][0].size(), 22u * 16u * 2u);  // half A over 22x16
            EXPECT_EQ(px.raw[1][3].size(), 11u * 9u * 4u);   // float Z over 11x9
        }
    }
    // The preset layer finds layers across parts.
    LayerPlan p = planLayers(info, "auto", {});
    EXPECT_EQ(p.find(Role::Depth)->part, 1);
    EXPECT_EQ(p.find(Role::Normal)->part, 1);
    EXPECT_EQ(p.find(Role::Beauty)->part, 0);
    auto lines = listLayers(info);
    EXPECT_NE(std::find(lines.begin(), lines.end(), "aux: N (X,Y,Z) half"), lines.end());
}

TEST(ExrRead, UnknownChannelIsNotCorruption) {
    std::string path = tmp("unknownch.exr");
    writeSimple(path, {"Z"});
    ExrInfo info = readExrInfo(path);
    expectError([&] { readExrChannels(path, info, {{0, "Q"}}, false, nullptr); }, {"no channel 'Q'", path});
}

TEST(ExrRead, MipmappedTiledKeepsItsLevelsUntouchedAndOneWithNewLayers) {
    FixturePart part;
    part.tiled = true;
    part.levelMode = Imf::MIPMAP_LEVELS;
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(20, 13));
    part.channels = {{"Y", Imf::HALF, 1, 1, {}}};
    std::string path = tmp("mip.exr"), out = tmp("mip-out.exr");
    writeFixture(path, {part});
    ExrInfo info = readExrInfo(path);
    ASSERT_TRUE(info.parts[0].tiled);
    EXPECT_EQ(info.parts[0].header.tileDescription().mode, Imf::MIPMAP_LEVELS);
    ExrPixels px;
    auto planes = readExrChannels(path, info, {{0, "Y"}}, true, &px);
    expectPlane(planes[0], part.channels[0], part.dataWindow);
    // Nothing new: the part is copied chunk for chunk, every level.
    writeExrWithNewChannels(out, px, {}, false);
    EXPECT_EQ(readExrInfo(out).parts[0].header.tileDescription().mode, Imf::MIPMAP_LEVELS);
    // A new channel: the part is encoded again, at level 0 only.
    writeExrWithNewChannels(out, px, {{0, "AO", Image(21, 14, 1, 0.5f), Imf::HALF}}, false);
    ExrInfo oi = readExrInfo(out);
    EXPECT_TRUE(oi.parts[0].tiled);
    EXPECT_EQ(oi.parts[0].header.tileDescription().mode, Imf::ONE_LEVEL);
    EXPECT_EQ(oi.parts[0].header.tileDescription().xSize, 8u);
    expectPlane(readExrChannels(out, oi, {{0, "Y"}}, false, nullptr)[0], part.channels[0], part.dataWindow);
}

TEST(ExrRead, SubsampledChannelRoundTrips) {
    FixturePart part;
    part.displayWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(15, 11));
    part.dataWindow = Imath::Box2i(Imath::V2i(-2, -4), Imath::V2i(15, 11));  // min divisible by sampling
    part.channels = {{"BY", Imf::HALF, 2, 2, {}}, {"Y", Imf::HALF, 1, 1, {}}};
    std::string path = tmp("sub.exr"), out = tmp("sub-out.exr");
    writeFixture(path, {part});
    ExrInfo info = readExrInfo(path);
    EXPECT_EQ(info.parts[0].channels[0].xSampling, 2);
    ExrPixels px;
    auto planes = readExrChannels(path, info, {{0, "BY"}}, true, &px);
    EXPECT_EQ(px.raw[0][0].size(), 9u * 8u * 2u);
    // Full-resolution plane: each pixel holds the sample of its 2x2 cell.
    const Image& by = planes[0];
    ASSERT_EQ(by.width, 18);
    for (int y = 0; y < by.height; ++y)
        for (int x = 0; x < by.width; ++x) {
            int ex = -2 + x, ey = -4 + y;
            int sx = ex >= 0 ? ex / 2 * 2 : -((-ex + 1) / 2) * 2, sy = ey >= 0 ? ey / 2 * 2 : -((-ey + 1) / 2) * 2;
            ASSERT_EQ(*by.at(x, y), storedValue(part.channels[0], sx, sy)) << x << "," << y;
        }
    writeExrWithNewChannels(out, px, {}, false);
    ExrPixels back;
    readExrChannels(out, readExrInfo(out), {}, true, &back);
    EXPECT_EQ(back.raw, px.raw);
    EXPECT_EQ(back.info.parts[0].channels[0].ySampling, 2);
}

// ----------------------------------------------------------------- writing

TEST(ExrWrite, PassThroughKeepsEverythingAndAddsChannel) {
    auto parts = multipartFixture();
    std::string path = tmp("pass-in.exr"), out = tmp("pass-out.exr");
    writeFixture(path, parts);
    ExrInfo info = readExrInfo(path);
    ExrPixels px;
    readExrChannels(path, info, {}, true, &px);

    NewChannel ao;
    ao.part = 1;
    ao.name = "AO";
    ao.plane = Image(11, 9, 1);
    for (size_t i = 0; i < ao.plane.pixels.size(); ++i) ao.plane.pixels[i] = float(i % 97) / 96.0f;
    NewChannel z32{0, "aaa.depth", Image(22, 16, 1, 2.5f), Imf::FLOAT};
    writeExrWithNewChannels(out, px, {ao, z32}, false, {{1, "obscura/version", "test"}});
    EXPECT_FALSE(tempLeft(out));
    EXPECT_EQ(versionFlags(out) & 0x10, 0x10);

    ExrInfo oi = readExrInfo(out);
    ExrPixels back;
    auto planes = readExrChannels(out, oi, {{1, "AO"}, {0, "aaa.depth"}}, true, &back);
    ASSERT_EQ(oi.parts.size(), 2u);
    for (int p = 0; p < 2; ++p) {
        const Imf::Header& ih = info.parts[p].header;
        const Imf::Header& oh = oi.parts[p].header;
        EXPECT_EQ(oi.parts[p].name, info.parts[p].name);
        EXPECT_EQ(oi.parts[p].tiled, info.parts[p].tiled);
        EXPECT_EQ(oh.compression(), ih.compression());
        EXPECT_EQ(oh.lineOrder(), ih.lineOrder());
        EXPECT_EQ(oi.parts[p].dataWindow, info.parts[p].dataWindow);
        EXPECT_EQ(oi.parts[p].displayWindow, info.parts[p].displayWindow);
        for (auto it = ih.begin(); it != ih.end(); ++it) {  // every attribute, byte for byte
            if (std::string(it.name()) == "channels") continue;
            auto found = oh.find(it.name());
            ASSERT_TRUE(found != oh.end()) << it.name();
            EXPECT_EQ(attrBytes(found.attribute()), attrBytes(it.attribute())) << it.name();
        }
        // Every input channel bit-exact, same type.
        for (size_t c = 0; c < info.parts[p].channels.size(); ++c) {
            const ExrChannel& ch = info.parts[p].channels[c];
            int oc = oi.parts[p].findChannel(ch.name);
            ASSERT_GE(oc, 0) << ch.name;
            EXPECT_EQ(oi.parts[p].channels[oc].type, ch.type);
            EXPECT_TRUE(back.raw[p][oc] == px.raw[p][c]) << ch.name;
        }
        EXPECT_EQ(oi.parts[p].channels.size(), info.parts[p].channels.size() + 1);
    }
    EXPECT_EQ(oi.parts[1].header.tileDescription().xSize, 4u);
    EXPECT_EQ(oi.parts[1].header.tileDescription().ySize, 3u);
    EXPECT_EQ(oi.parts[1].header.typedAttribute<Imf::StringAttribute>("obscura/version").value(), "test");
    EXPECT_EQ(oi.parts[0].header.findTypedAttribute<Imf::StringAttribute>("obscura/version"), nullptr);
    EXPECT_EQ(oi.parts[0].header.typedAttribute<Imf::FloatAttribute>("exposure").value(), 1.5f);
    // New channels: type and values (half rounding for AO).
    EXPECT_EQ(oi.parts[1].channels[oi.parts[1].findChannel("AO")].type, Imf::HALF);
    EXPECT_EQ(oi.parts[0].channels[0].name, "A");  // sorted: "A" < "B" < ... < "aaa.depth"
    EXPECT_EQ(oi.parts[0].channels[oi.parts[0].findChannel("aaa.depth")].type, Imf::FLOAT);
    for (size_t i = 0; i < ao.plane.pixels.size(); ++i)
        ASSERT_EQ(planes[0].pixels[i], float(half(ao.plane.pixels[i])));
    for (float v : planes[1].pixels) ASSERT_EQ(v, 2.5f);
}

TEST(ExrWrite, SinglePartStaysSinglePartAndReplacesSameName) {
    std::string out = tmp("room-out.exr");
    ExrInfo info = readExrInfo(kRoom);
    ExrPixels px;
    readExrChannels(kRoom, info, {}, true, &px);
    NewChannel ao{0, "ViewLayer.AO.R", Image(320, 320, 1, 0.25f), Imf::HALF};  // replaces the float one
    writeExrWithNewChannels(out, px, {ao}, false);
    EXPECT_EQ(versionFlags(out) & 0x12, 0);  // not multipart, not tiled
    ExrInfo oi = readExrInfo(out);
    EXPECT_FALSE(oi.multipart);
    EXPECT_FALSE(oi.parts[0].header.hasName());
    EXPECT_EQ(oi.parts[0].channels.size(), info.parts[0].channels.size());
    EXPECT_EQ(oi.parts[0].header.compression(), Imf::ZIP_COMPRESSION);
    EXPECT_EQ(oi.parts[0].header.typedAttribute<Imf::StringAttribute>("BlenderMultiChannel").value(),
              "Blender V2.55.1 and newer");
    int c = oi.parts[0].findChannel("ViewLayer.AO.R");
    EXPECT_EQ(oi.parts[0].channels[c].type, Imf::HALF);
    ExrPixels back;
    auto planes = readExrChannels(out, oi, {{0, "ViewLayer.AO.R"}}, true, &back);
    for (float v : planes[0].pixels) ASSERT_EQ(v, 0.25f);
    for (size_t i = 0; i < info.parts[0].channels.size(); ++i)
        if ((int)i != c) {
            EXPECT_TRUE(back.raw[0][i] == px.raw[0][i]) << info.parts[0].channels[i].name;
        }
    EXPECT_EQ(planLayers(oi, "auto", {}).preset, "blender");
}

TEST(ExrWrite, RefusesToOverwriteInputUnlessAllowed) {
    std::string path = tmp("inplace.exr");
    writeSimple(path, {"Z"});
    ExrInfo info = readExrInfo(path);
    ExrPixels px;
    readExrChannels(path, info, {}, true, &px);
    NewChannel ao{0, "AO", Image(16, 12, 1, 0.5f), Imf::HALF};
    auto before = fileSize(path);
    expectError([&] { writeExrWithNewChannels(path, px, {ao}, false); }, {"refusing to overwrite", path});
    // Same file through another spelling of the path.
    std::string other = (fs::path(path).parent_path() / "." / "inplace.exr").string();
    expectError([&] { writeExrWithNewChannels(other, px, {ao}, false); }, {"refusing to overwrite"});
    EXPECT_EQ(fileSize(path), before);
    EXPECT_EQ(readExrInfo(path).parts[0].channels.size(), 1u);
    writeExrWithNewChannels(path, px, {ao}, true);
    EXPECT_EQ(readExrInfo(path).parts[0].channels.size(), 2u);
    EXPECT_FALSE(tempLeft(path));
}

TEST(ExrWrite, FailuresLeaveNoTempFile) {
    std::string path = tmp("src.exr");
    writeSimple(path, {"Z"});
    ExrInfo info = readExrInfo(path);
    ExrPixels px;
    readExrChannels(path, info, {}, true, &px);
    std::string missingDir = tmp("no-such-dir") + "/out.exr";
    expectError([&] { writeExrWithNewChannels(missingDir, px, {}, false); }, {"does not exist", "out.exr"});
    EXPECT_FALSE(fs::exists(fs::path(missingDir).parent_path()));
    // The temp file is written, then the rename onto a directory fails: the temp must go.
    std::string dirTarget = tmp("a-directory");
    fs::create_directories(dirTarget);
    expectError([&] { writeExrWithNewChannels(dirTarget, px, {}, false); }, {"'" + dirTarget + "': cannot write"});
    EXPECT_FALSE(tempLeft(dirTarget));
    // A plane of the wrong size is refused before anything is written.
    std::string out = tmp("badplane.exr");
    expectError([&] { writeExrWithNewChannels(out, px, {{0, "AO", Image(3, 3, 1), Imf::HALF}}, false); },
                {"cannot add channel 'AO'", "16x12"});
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(tempLeft(out));
    // A part whose pixels were not kept cannot take new layers (it would be encoded again); with
    // none, it is copied chunk for chunk.
    ExrPixels partial;
    readExrChannels(path, info, {{0, "Z"}}, false, &partial);
    expectError([&] { writeExrWithNewChannels(out, partial, {{0, "AO", Image(16, 12, 1), Imf::HALF}}, false); },
                {"were not all kept"});
    EXPECT_FALSE(fs::exists(out));
    writeExrWithNewChannels(out, partial, {}, false);
    EXPECT_EQ(readExrInfo(out).parts[0].channels.size(), 1u);
}

// ----------------------------------------------------------------- errors

TEST(ExrErrors, MissingFile) {
    std::string path = tmp("does-not-exist.exr");
    expectError([&] { readExrInfo(path); }, {"'" + path + "': cannot open: no such file"});
}

TEST(ExrErrors, NotAnExr) {
    std::string path = tmp("not.exr");
    std::ofstream(path) << "P6\n1 1\n255\nabc";
    expectError([&] { readExrInfo(path); }, {"'" + path + "': not an OpenEXR file"});
    std::string empty = tmp("empty.exr");
    std::ofstream(empty).close();
    expectError([&] { readExrInfo(empty); }, {"'" + empty + "': not an OpenEXR file"});
}

TEST(ExrErrors, DeepDataIsRefused) {
    std::string path = tmp("deep.exr");
    {
        Imf::Header h(4, 4);
        h.setType(Imf::DEEPSCANLINE);
        h.compression() = Imf::ZIPS_COMPRESSION;
        h.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        Imf::DeepScanLineOutputFile f(path.c_str(), h);
        std::vector<unsigned> counts(16, 0);
        std::vector<float*> ptrs(16, nullptr);
        Imf::DeepFrameBuffer fb;
        fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, (char*)counts.data(), 4, 16));
        fb.insert("Z", Imf::DeepSlice(Imf::FLOAT, (char*)ptrs.data(), sizeof(float*), sizeof(float*) * 4, 4));
        f.setFrameBuffer(fb);
        f.writePixels(4);
    }
    expectError([&] { readExrInfo(path); }, {"'" + path + "'", "deep data"});
}

TEST(ExrErrors, TruncatedFiles) {
    // Uncompressed scanline and tiled files, cut in their pixel data.
    for (bool tiled : {false, true}) {
        FixturePart part;
        part.tiled = tiled;
        part.compression = Imf::NO_COMPRESSION;
        part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(63, 63));
        part.channels = {{"Z", Imf::FLOAT, 1, 1, {}}};
        std::string full = tmp(tiled ? "full-t.exr" : "full-s.exr"), cut = tmp(tiled ? "cut-t.exr" : "cut-s.exr");
        writeFixture(full, {part});
        // 60% of the file cannot hold 64 x 64 uncompressed floats: refused from the header.
        truncatedCopy(full, cut, fileSize(full) * 6 / 10);
        expectError([&] { readExrInfo(cut); }, {"'" + cut + "': data window [0,0 - 63,63] decodes to 16384 bytes"});
        // Cut in its last chunk: the header passes, the pixels are found missing.
        truncatedCopy(full, cut, fileSize(full) - 100);
        ExrInfo info = readExrInfo(cut);  // header intact
        expectError([&] { readExrChannels(cut, info, {{0, "Z"}}, false, nullptr); },
                    {"'" + cut + "': truncated or corrupt"});
        ExrPixels px;
        expectError([&] { readExrChannels(cut, info, {}, true, &px); }, {"'" + cut + "': truncated or corrupt"});
    }
    // The real render, compressed, cut in half; and cut inside its header.
    std::string cut = tmp("room-cut.exr");
    truncatedCopy(kRoom, cut, fileSize(kRoom) / 2);
    ExrInfo info = readExrInfo(cut);
    expectError([&] { readExrChannels(cut, info, {{0, "ViewLayer.Depth.Z"}}, false, nullptr); },
                {"'" + cut + "': truncated or corrupt"});
    std::string head = tmp("room-head.exr");
    truncatedCopy(kRoom, head, 200);
    expectError([&] { readExrInfo(head); }, {"'" + head + "': truncated or corrupt", "header"});
}

// --threads 1 is the frame's own thread: no OpenEXR pool (count 0), which a threaded host's
// concurrent frames would otherwise share, one read or write at a time.
TEST(ExrThreads, OneThreadMeansTheCallersOwn) {
    obscura::setExrThreads(1);
    EXPECT_EQ(Imf::globalThreadCount(), 0);
    obscura::setExrThreads(3);
    EXPECT_EQ(Imf::globalThreadCount(), 3);
    obscura::setExrThreads(0);  // back to every core, as the other tests expect
    const int cores = (int)std::max(1u, std::thread::hardware_concurrency());
    EXPECT_EQ(Imf::globalThreadCount(), cores == 1 ? 0 : cores);
}
