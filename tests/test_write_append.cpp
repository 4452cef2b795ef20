// --write append: the input's parts copied as compressed chunks (compared chunk by chunk, raw,
// not as pixels), every attribute kept, every channel reading back equal, and the AO in one
// new part with the input's windows, camera attributes and colour tags. Single-part with
// overscan, multipart, tiled (mip-mapped), lossy and deep inputs; a corrupt chunk table; the
// chunk table check on every layout.
#include "base/error.h"
#include "io/exr_chunk_table.h"
#include "io/exr_file.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/studio_render.h"
#include "support/scenes.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepScanLineOutputPart.h>
#include <OpenEXR/ImfDeepTiledOutputPart.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfInputPart.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStandardAttributes.h>
#include <OpenEXR/ImfStdIO.h>
#include <OpenEXR/ImfTiledInputPart.h>
#include <OpenEXR/ImfTiledOutputPart.h>
#include <OpenEXR/ImfVersion.h>
#include <OpenEXR/openexr.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
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

// Geometry (Z, N) and a half beauty with a subsampled channel, camera and colour attributes.
FixturePart renderPart(Imf::Compression compression, bool beauty = true) {
    FixturePart part = studioGeometryPart(compression);
    if (beauty) {
        for (const char* c : {"R", "G", "B", "A"}) part.channels.push_back({c, Imf::HALF, 1, 1, {}});
        part.channels.push_back({"crypto", Imf::UINT, 1, 1, {}});
    }
    part.stringAttributes = {{"renderer", "test"}, {"cryptomatte/abc1234/manifest", "{}"}};
    part.floatAttributes = {{"cameraFov", 52.5f}};
    part.editHeader = [](Imf::Header& h) {
        Imf::addWorldToCamera(h, kStudioWorldToCamera);
        Imf::addChromaticities(h, kAcesCgPrimaries);
    };
    return part;
}

// ---- what a file holds, read independently of obscura's writer ----

// Every chunk of a part as stored, in chunk-table order (OpenEXR's core API): leader sizes,
// the deep sample-count table and the packed bytes.
std::vector<std::string> rawChunks(const std::string& path, int part) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_context_t ctx = nullptr;
    EXPECT_EQ(exr_start_read(&ctx, path.c_str(), &init), EXR_ERR_SUCCESS) << path;
    std::vector<std::string> chunks;
    auto take = [&](const exr_chunk_info_t& c) {
        std::string packed(c.packed_size, '\0'), table(c.sample_count_table_size, '\0');
        const bool deep = c.type == EXR_STORAGE_DEEP_SCANLINE || c.type == EXR_STORAGE_DEEP_TILED;
        EXPECT_EQ(deep ? exr_read_deep_chunk(ctx, part, &c, packed.data(), table.data())
                       : exr_read_chunk(ctx, part, &c, packed.data()),
                  EXR_ERR_SUCCESS);
        chunks.push_back(std::to_string(c.unpacked_size) + "|" + table + "|" + packed);
    };
    exr_storage_t storage;
    exr_get_storage(ctx, part, &storage);
    exr_chunk_info_t c;
    if (storage == EXR_STORAGE_SCANLINE || storage == EXR_STORAGE_DEEP_SCANLINE) {
        exr_attr_box2i_t dw;
        int32_t lines = 1;
        exr_get_data_window(ctx, part, &dw);
        exr_get_scanlines_per_chunk(ctx, part, &lines);
        for (int y = dw.min.y; y <= dw.max.y; y += lines)
            if (exr_read_scanline_chunk_info(ctx, part, y, &c) == EXR_ERR_SUCCESS) take(c);
    } else {
        int32_t levels = 0;
        exr_get_tile_levels(ctx, part, &levels, nullptr);
        uint32_t tw = 1, th = 1;
        exr_tile_level_mode_t mode;
        exr_tile_round_mode_t round;
        exr_get_tile_descriptor(ctx, part, &tw, &th, &mode, &round);
        for (int l = 0; l < levels; ++l) {  // mip levels (the fixtures make no rip-maps)
            int32_t w = 0, h = 0;
            exr_get_level_sizes(ctx, part, l, l, &w, &h);
            for (int ty = 0; ty < (int)((h + th - 1) / th); ++ty)
                for (int tx = 0; tx < (int)((w + tw - 1) / tw); ++tx)
                    if (exr_read_tile_chunk_info(ctx, part, tx, ty, l, l, &c) == EXR_ERR_SUCCESS) take(c);
        }
    }
    exr_finish(&ctx);
    return chunks;
}

std::vector<Imf::Header> headersOf(const std::string& path) {
    Imf::MultiPartInputFile file(path.c_str());
    std::vector<Imf::Header> headers;
    for (int p = 0; p < file.parts(); ++p) headers.push_back(file.header(p));
    return headers;
}

std::string attributeBytes(const Imf::Attribute& a) {
    Imf::StdOSStream os;
    a.writeValueTo(os, Imf::EXR_VERSION);
    return std::string(a.typeName()) + ":" + os.str();
}

std::vector<std::string> channelNames(const Imf::Header& h) {
    std::vector<std::string> names;
    for (auto it = h.channels().begin(); it != h.channels().end(); ++it) names.push_back(it.name());
    return names;
}

std::vector<float> aoOf(const std::string& path, int part, const std::string& channel = "obscura.AO.Y") {
    return partChannel(path, part, channel);
}

// Runs `obscura in -o out --write append` with the studio camera; expects success.
void runAppend(const std::string& in, const std::string& out, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {in, "-o", out, "--write", "append", "--quiet", "--threads", "2"};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    args.insert(args.end(), extra.begin(), extra.end());
    const CliResult r = runObscura(args);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
}

// The input's parts come first, chunk for chunk and attribute for attribute (a single part
// gains the name and type a multipart file needs), each flat channel reading back equal; the
// last part is the AO's (channels `layers`, sorted), with `depthPart`'s windows and camera
// attributes and codec `aoCodec`.
void expectAppended(const std::string& in, const std::string& out, int depthPart, Imf::Compression aoCodec,
                    const std::vector<std::string>& layers = {"obscura.AO.Y"}, bool compareChunks = true) {
    const std::vector<Imf::Header> before = headersOf(in), after = headersOf(out);
    ASSERT_EQ(after.size(), before.size() + 1);
    for (size_t p = 0; p < before.size() && compareChunks; ++p) {
        EXPECT_TRUE(rawChunks(in, (int)p) == rawChunks(out, (int)p)) << "part " << p << "'s chunks differ";
        EXPECT_EQ(rawChunks(out, (int)p).size(), rawChunks(in, (int)p).size());
    }
    for (size_t p = 0; p < before.size(); ++p) {
        for (auto it = before[p].begin(); it != before[p].end(); ++it) {
            if (std::strcmp(it.name(), "chunkCount") == 0) continue;  // the writer's own
            const auto found = after[p].find(it.name());
            ASSERT_NE(found, after[p].end()) << "part " << p << " lost attribute " << it.name();
            EXPECT_EQ(attributeBytes(found.attribute()), attributeBytes(it.attribute())) << it.name();
        }
        const std::set<std::string> added = {"name", "type", "chunkCount"};  // what a multipart file needs
        for (auto it = after[p].begin(); it != after[p].end(); ++it)
            EXPECT_TRUE(before[p].find(it.name()) != before[p].end() || added.count(it.name()))
                << "part " << p << " gained attribute " << it.name();
    }
    // Every flat channel, decoded by OpenEXR from both files, in its own pixel type.
    ExrPixels a, b;
    const ExrInfo inInfo = readExrInfo(in, kDefaultMaxPixels, true), outInfo = readExrInfo(out, kDefaultMaxPixels, true);
    readExrChannels(in, inInfo, {}, true, &a);
    readExrChannels(out, outInfo, {}, true, &b);
    for (size_t p = 0; p < before.size(); ++p) {
        EXPECT_EQ(inInfo.parts[p].channels.size(), outInfo.parts[p].channels.size());
        EXPECT_TRUE(a.raw[p] == b.raw[p]) << "part " << p << "'s channels read back different";
    }

    const Imf::Header& ao = after.back();
    const Imf::Header& depth = before[depthPart];
    EXPECT_EQ(ao.name(), "obscura");
    EXPECT_EQ(channelNames(ao), layers);
    EXPECT_EQ(ao.compression(), aoCodec);
    EXPECT_EQ(ao.displayWindow(), depth.displayWindow());
    EXPECT_EQ(ao.dataWindow(), depth.dataWindow());
    EXPECT_EQ(ao.hasTileDescription(), depth.hasTileDescription());
    ASSERT_TRUE(Imf::hasWorldToCamera(ao));
    EXPECT_EQ(Imf::worldToCamera(ao), kStudioWorldToCamera);
    ASSERT_TRUE(Imf::hasChromaticities(ao));  // the input's: a file has one
    EXPECT_EQ(Imf::chromaticities(ao).red, kAcesCgPrimaries.red);
    EXPECT_NE(ao.findTypedAttribute<Imf::FloatAttribute>("cameraFov"), nullptr);
    EXPECT_EQ(ao.findTypedAttribute<Imf::StringAttribute>("cryptomatte/abc1234/manifest"), nullptr);
    EXPECT_NE(ao.findTypedAttribute<Imf::StringAttribute>("obscura/version"), nullptr);
    EXPECT_NE(ao.findTypedAttribute<Imf::StringAttribute>("obscura/settings"), nullptr);
    const auto* tag = ao.findTypedAttribute<Imf::StringAttribute>("obscura/obscura.AO.Y/colorspace");
    ASSERT_NE(tag, nullptr);
    EXPECT_EQ(tag->value(), "raw");
}

// A deep scanline and a deep tiled part (Z only, 0 to 2 samples a pixel) after flat ones.
// versionEverywhere: a `version` attribute on the flat parts too, which OpenEXR 3.1's core API
// (rawChunks) wants in any file holding deep data, though OpenEXR's own writer leaves it out.
void writeWithDeepParts(const std::string& path, std::vector<FixturePart> flat, bool versionEverywhere = true) {
    std::vector<Imf::Header> headers;
    if (!flat.empty()) {
        writeFixture(path + ".flat.exr", flat);  // the flat parts' headers, as the fixtures make them
        headers = headersOf(path + ".flat.exr");
        fs::remove(path + ".flat.exr");
    }
    if (versionEverywhere)
        for (Imf::Header& h : headers) h.insert("version", Imf::IntAttribute(1));
    for (const std::string& type : {Imf::DEEPSCANLINE, Imf::DEEPTILE}) {
        Imf::Header h(kStudioDisplay, kStudioData);
        h.setName(type);
        h.setType(type);
        h.compression() = Imf::ZIPS_COMPRESSION;
        h.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        h.insert("version", Imf::IntAttribute(1));  // deep data version 1: OpenEXR's readers require it
        if (type == Imf::DEEPTILE) h.setTileDescription(Imf::TileDescription(16, 16));
        Imf::addChromaticities(h, kAcesCgPrimaries);
        headers.push_back(h);
    }
    Imf::MultiPartOutputFile file(path.c_str(), headers.data(), (int)headers.size());
    const int w = kStudioData.max.x - kStudioData.min.x + 1, h = kStudioData.max.y - kStudioData.min.y + 1;
    std::vector<unsigned> counts((size_t)w * h);
    std::vector<std::vector<float>> samples(counts.size());
    std::vector<float*> pointers(counts.size());
    for (size_t i = 0; i < counts.size(); ++i) {
        counts[i] = (unsigned)(i % 3);
        for (unsigned k = 0; k < counts[i]; ++k) samples[i].push_back(1.0f + (float)(i % 7) + (float)k);
        pointers[i] = samples[i].data();
    }
    Imf::DeepFrameBuffer fb;
    const size_t origin = (size_t)(-kStudioData.min.y) * w + (size_t)(-kStudioData.min.x);
    fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, (char*)(counts.data() + origin), 4, 4 * w));
    fb.insert("Z", Imf::DeepSlice(Imf::FLOAT, (char*)(pointers.data() + origin), sizeof(float*), sizeof(float*) * w, 4));
    for (size_t p = 0; p + 2 < headers.size(); ++p) {  // flat float parts: the fixture's values again
        const FixturePart& part = flat[p];
        Imf::FrameBuffer ffb;
        std::vector<std::vector<float>> planes;
        for (const FixtureChannel& ch : part.channels) {
            std::vector<float>& v = planes.emplace_back((size_t)w * h);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) v[(size_t)y * w + x] = storedValue(ch, x + kStudioData.min.x, y + kStudioData.min.y);
            ffb.insert(ch.name, Imf::Slice::Make(Imf::FLOAT, v.data(), kStudioData));
        }
        Imf::OutputPart out(file, (int)p);
        out.setFrameBuffer(ffb);
        out.writePixels(h);
    }
    Imf::DeepScanLineOutputPart scan(file, (int)headers.size() - 2);
    scan.setFrameBuffer(fb);
    scan.writePixels(h);
    Imf::DeepTiledOutputPart tiles(file, (int)headers.size() - 1);
    tiles.setFrameBuffer(fb);
    tiles.writeTiles(0, tiles.numXTiles(0) - 1, 0, tiles.numYTiles(0) - 1, 0, 0);
}

} // namespace

TEST(WriteAppend, SinglePartWithOverscanKeepsEveryChunkAndAddsTheAoPart) {
    const fs::path dir = obscura::test::testDir("write-append");
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string(), copy = (dir / "copy.exr").string();
    writeFixture(in, {renderPart(Imf::ZIP_COMPRESSION)});
    runAppend(in, out, {"--report", (dir / "out.json").string()});
    expectAppended(in, out, 0, Imf::ZIP_COMPRESSION);
    EXPECT_EQ(headersOf(out)[0].name(), "render");

    // The AO is the one --write copy computes.
    std::vector<std::string> args = {in, "-o", copy, "--quiet", "--threads", "2"};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    ASSERT_EQ(runObscura(args).exitCode, 0);
    EXPECT_EQ(aoOf(out, 1), aoOf(copy, 0));

    const nlohmann::json report = readJson(dir / "out.json");
    EXPECT_EQ(report["write"]["mode"], "append");
    EXPECT_NE(report["write"]["description"].get<std::string>().find("copied as compressed chunks"), std::string::npos);
    for (const char* stage : {"read", "compute", "copy", "append"}) EXPECT_TRUE(report["timings_s"].contains(stage)) << stage;
    EXPECT_FALSE(report["timings_s"].contains("write"));
}

TEST(WriteAppend, MultipartCopiesEveryPart) {
    const fs::path dir = obscura::test::testDir("write-append");
    FixturePart beauty = renderPart(Imf::PIZ_COMPRESSION), geometry = renderPart(Imf::RLE_COMPRESSION, false);
    beauty.name = "beauty";
    geometry.name = "geometry";
    beauty.channels.erase(beauty.channels.begin(), beauty.channels.begin() + 4);  // no Z, N: R, G, B, A, crypto
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    writeFixture(in, {beauty, geometry});
    runAppend(in, out);
    expectAppended(in, out, 1, Imf::RLE_COMPRESSION);  // the depth's part's codec
}

TEST(WriteAppend, TiledMipmappedInputGetsATiledPart) {
    const fs::path dir = obscura::test::testDir("write-append");
    FixturePart part = renderPart(Imf::ZIPS_COMPRESSION);
    part.tiled = true;
    part.tileWidth = 16;
    part.tileHeight = 8;
    part.levelMode = Imf::MIPMAP_LEVELS;
    part.lineOrder = Imf::RANDOM_Y;
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    writeFixture(in, {part});
    runAppend(in, out);
    expectAppended(in, out, 0, Imf::ZIPS_COMPRESSION);
    const Imf::Header ao = headersOf(out).back();
    ASSERT_TRUE(ao.hasTileDescription());
    EXPECT_EQ(ao.tileDescription().mode, Imf::ONE_LEVEL);
    EXPECT_GT(rawChunks(out, 0).size(), rawChunks(out, 1).size()) << "the input's lower mip levels were dropped";
}

// DWAA chunks are copied as they are (re-encoding would change them); the AO part is ZIP.
TEST(WriteAppend, LossyInputKeepsItsChunksAndTheAoIsZip) {
    const fs::path dir = obscura::test::testDir("write-append");
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    writeFixture(in, {renderPart(Imf::DWAA_COMPRESSION)});
    runAppend(in, out);
    expectAppended(in, out, 0, Imf::ZIP_COMPRESSION);
}

TEST(WriteAppend, DeepPartsAreCopiedAsTheyAre) {
    const fs::path dir = obscura::test::testDir("write-append");
    FixturePart geometry = renderPart(Imf::ZIP_COMPRESSION, false);
    geometry.name = "flat";
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    writeWithDeepParts(in, {geometry});
    // copy must decode every part to re-encode it, and refuses deep ones.
    std::vector<std::string> args = {in, "-o", (dir / "copy.exr").string()};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    const CliResult copy = runObscura(args);
    EXPECT_EQ(copy.exitCode, 1) << outcome(copy);
    EXPECT_NE(copy.err.find("deep data"), std::string::npos) << copy.err;

    runAppend(in, out);
    expectAppended(in, out, 0, Imf::ZIP_COMPRESSION);
    const std::vector<Imf::Header> parts = headersOf(out);
    ASSERT_EQ(parts.size(), 4u);
    EXPECT_EQ(parts[1].type(), Imf::DEEPSCANLINE);
    EXPECT_EQ(parts[2].type(), Imf::DEEPTILE);
    EXPECT_GT(rawChunks(out, 1).size(), 0u);

    // As OpenEXR's writer makes them: only the deep parts say `version`.
    writeWithDeepParts(in, {geometry}, false);
    runAppend(in, out);
    expectAppended(in, out, 0, Imf::ZIP_COMPRESSION, {"obscura.AO.Y"}, false);
}

// The deep input of --flat: the output is the flat file's parts plus the AO part.
TEST(WriteAppend, DeepInputWithFlatPasses) {
    const fs::path dir = obscura::test::testDir("write-append");
    const std::string deep = (dir / "deep.exr").string(), flat = (dir / "flat.exr").string(),
                      out = (dir / "out.exr").string();
    writeWithDeepParts(deep, {});
    writeFixture(flat, {renderPart(Imf::PIZ_COMPRESSION)});
    std::vector<std::string> args = {deep, "--flat", flat, "-o", out, "--write", "append", "--quiet"};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    const CliResult r = runObscura(args);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    expectAppended(flat, out, 0, Imf::PIZ_COMPRESSION);
}

// The AO part's colour layers (ssdo) sit beside an ACEScg render: the part keeps the file's
// chromaticities and each DO channel says what it is.
TEST(WriteAppend, ColourLayersAreTaggedPerChannel) {
    const fs::path dir = obscura::test::testDir("write-append");
    const std::string in = (dir / "in.exr").string(), out = (dir / "out.exr").string();
    writeFixture(in, {renderPart(Imf::ZIP_COMPRESSION)});
    runAppend(in, out, {"--method", "ssdo", "--samples", "4", "--colorspace", "lin_rec709"});
    expectAppended(in, out, 0, Imf::ZIP_COMPRESSION, {"obscura.AO.Y", "obscura.DO.B", "obscura.DO.G", "obscura.DO.R"});
    const Imf::Header ao = headersOf(out).back();
    EXPECT_EQ(Imf::chromaticities(ao).red, kAcesCgPrimaries.red);
    const auto* space = ao.findTypedAttribute<Imf::StringAttribute>("obscura/obscura.DO/colorspace");
    ASSERT_NE(space, nullptr);
    EXPECT_EQ(space->value(), "lin_rec709");
    EXPECT_NE(ao.findTypedAttribute<Imf::StringAttribute>("obscura/obscura.DO/chromaticities"), nullptr);
}

// Chunk tables pointing past the end, or at another chunk: one line naming the file, and no
// output or temp file.
TEST(WriteAppend, CorruptChunkTableIsRefusedAndNothingIsWritten) {
    const fs::path dir = obscura::test::testDir("write-append");
    const std::string good = (dir / "good.exr").string();
    FixturePart part = renderPart(Imf::ZIP_COMPRESSION);
    writeFixture(good, {part});
    std::ifstream f(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    // The table follows the header: its first entry is the offset right after it.
    const int chunks = (kStudioData.max.y - kStudioData.min.y + 1 + 15) / 16;  // ZIP: 16 lines a chunk
    size_t table = 0;
    for (size_t at = 8; at + 8 <= bytes.size() && !table; ++at) {
        uint64_t v;
        std::memcpy(&v, bytes.data() + at, 8);
        if (v == at + 8 * (size_t)chunks) table = at;
    }
    ASSERT_NE(table, 0u) << "chunk table not found";
    auto corrupted = [&](const std::string& name, auto edit) {
        std::string b = bytes;
        edit(reinterpret_cast<uint64_t*>(b.data() + table));
        const std::string path = (dir / name).string();
        std::ofstream(path, std::ios::binary) << b;
        return path;
    };
    const std::vector<std::string> inputs = {
        corrupted("past-end.exr", [&](uint64_t* t) { t[1] = bytes.size() + 4096; }),
        corrupted("swapped.exr", [](uint64_t* t) { std::swap(t[0], t[1]); }),
        corrupted("inside.exr", [](uint64_t* t) { t[1] += 6; }),
    };
    for (const std::string& in : inputs) {
        const std::string out = (dir / "out.exr").string();
        std::vector<std::string> args = {in, "-o", out, "--write", "append"};
        args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
        const CliResult r = runObscura(args);
        EXPECT_EQ(r.exitCode, 1) << outcome(r);
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << outcome(r);
        EXPECT_EQ(r.err.rfind("obscura: '" + in + "': truncated or corrupt", 0), 0u) << outcome(r);
        EXPECT_FALSE(fs::exists(out)) << in;
        for (const auto& e : fs::directory_iterator(dir))
            EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
    }
}

// A part's table entry OpenEXR would replace by scanning the file (here 0): append refuses it (above);
// copy, which copies the parts that take no new layer chunk for chunk where the tables allow it,
// decodes and encodes every part again, as it did before, says so, and the values come through; a
// mip-mapped part then keeps level 0 (a readable file, and a warning).
TEST(WriteAppend, CopyOfATableOpenExrRebuildsEncodesEveryPartAgain) {
    const fs::path dir = obscura::test::testDir("write-append");
    FixturePart geometry = renderPart(Imf::ZIP_COMPRESSION, false), beauty = renderPart(Imf::ZIP_COMPRESSION);
    geometry.name = "geometry";
    beauty.name = "beauty";
    beauty.channels.erase(beauty.channels.begin(), beauty.channels.begin() + 4);  // no Z, N: R, G, B, A, crypto
    FixturePart texture = beauty;
    texture.name = "texture";
    texture.tiled = true;
    texture.levelMode = Imf::MIPMAP_LEVELS;
    const std::string good = (dir / "three_parts.exr").string();
    writeFixture(good, {geometry, beauty, texture});
    std::ifstream f(good, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    const int chunks = (kStudioData.max.y - kStudioData.min.y + 1 + 15) / 16;  // ZIP: 16 lines a chunk
    int tiles = 0;
    {
        Imf::MultiPartInputFile file(good.c_str());
        Imf::TiledInputPart t(file, 2);
        for (int l = 0; l < t.numLevels(); ++l) tiles += t.numXTiles(l) * t.numYTiles(l);
    }
    size_t table = 0;  // the parts' tables, one after another; the first entry points past them all
    for (size_t at = 8; at + 8 <= bytes.size() && !table; ++at) {
        uint64_t v;
        std::memcpy(&v, bytes.data() + at, 8);
        if (v == at + 8 * (size_t)(2 * chunks + tiles)) table = at;
    }
    ASSERT_NE(table, 0u) << "chunk tables not found";
    std::memset(bytes.data() + table + 8 * (chunks + 1), 0, 8);  // the beauty's second entry
    const std::string in = (dir / "zero_entry.exr").string(), out = (dir / "zero_entry_ao.exr").string();
    std::ofstream(in, std::ios::binary) << bytes;
    std::vector<std::string> args = {in, "-o", out};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    const CliResult r = runObscura(args);
    ASSERT_EQ(r.exitCode, 0) << outcome(r);
    EXPECT_NE(r.err.find("the input's chunk tables are damaged"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("part 2 of the input is mip-mapped"), std::string::npos) << r.err;
    for (int part : {1, 2})
        for (const char* c : {"R", "G", "B", "A"}) EXPECT_EQ(partChannel(out, part, c), partChannel(good, part, c)) << c;
}

TEST(WriteAppend, FramesResumeAndInPlaceWorkAsWithCopy) {
    const fs::path dir = obscura::test::testDir("write-append");
    for (int f : {1, 2}) writeFixture((dir / ("in." + std::to_string(f) + ".exr")).string(), {renderPart(Imf::ZIP_COMPRESSION)});
    const std::string pattern = (dir / "in.#.exr").string(), outs = (dir / "out.#.exr").string();
    runAppend(pattern, outs, {"--frames", "1-2"});
    for (int f : {1, 2})
        expectAppended((dir / ("in." + std::to_string(f) + ".exr")).string(),
                       (dir / ("out." + std::to_string(f) + ".exr")).string(), 0, Imf::ZIP_COMPRESSION);
    const auto stamp = fs::last_write_time(dir / "out.1.exr");
    std::vector<std::string> args = {pattern, "-o", outs, "--write", "append", "--frames", "1-2", "--resume"};
    args.insert(args.end(), studioRender().cameraFlags.begin(), studioRender().cameraFlags.end());
    const CliResult again = runObscura(args);
    ASSERT_EQ(again.exitCode, 0) << outcome(again);
    EXPECT_EQ(fs::last_write_time(dir / "out.1.exr"), stamp) << "a finished frame was written again";

    // In place: the file becomes itself plus the AO part.
    const std::string in = (dir / "in.1.exr").string(), before = (dir / "before.exr").string();
    fs::copy_file(in, before);
    runAppend(in, in, {"--in-place"});
    expectAppended(before, in, 0, Imf::ZIP_COMPRESSION);
}

// The check walks every layout's table in OpenEXR's order: line blocks of each codec's height in
// either line order, mip levels, rip levels (y level outer), deep parts; a valid file passes,
// and an entry pointing at another tile is named.
TEST(AppendChunkTables, EveryLayoutPassesAndAMisplacedTileIsNamed) {
    const fs::path dir = obscura::test::testDir("write-append");
    std::vector<std::string> valid;
    for (Imf::Compression codec : {Imf::NO_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION, Imf::DWAB_COMPRESSION})
        for (Imf::LineOrder order : {Imf::INCREASING_Y, Imf::DECREASING_Y}) {
            FixturePart part = renderPart(codec, false);
            part.lineOrder = order;
            valid.push_back((dir / ("s" + std::to_string(codec) + "-" + std::to_string(order) + ".exr")).string());
            writeFixture(valid.back(), {part});
        }
    FixturePart mip = renderPart(Imf::ZIPS_COMPRESSION, false);
    mip.tiled = true;
    mip.levelMode = Imf::MIPMAP_LEVELS;
    valid.push_back((dir / "mip.exr").string());
    writeFixture(valid.back(), {mip});
    FixturePart flat = renderPart(Imf::RLE_COMPRESSION, false);
    flat.name = "flat";
    valid.push_back((dir / "deep.exr").string());
    writeWithDeepParts(valid.back(), {flat}, false);

    const std::string rip = (dir / "rip.exr").string();
    {
        Imf::Header h(kStudioDisplay, kStudioData);
        h.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        h.setTileDescription(Imf::TileDescription(8, 4, Imf::RIPMAP_LEVELS, Imf::ROUND_UP));
        h.setType(Imf::TILEDIMAGE);
        Imf::MultiPartOutputFile file(rip.c_str(), &h, 1);
        Imf::TiledOutputPart out(file, 0);
        for (int ly = 0; ly < out.numYLevels(); ++ly)
            for (int lx = 0; lx < out.numXLevels(); ++lx) {
                const Imath::Box2i w = out.dataWindowForLevel(lx, ly);
                std::vector<float> z((size_t)(w.max.x - w.min.x + 1) * (w.max.y - w.min.y + 1), 1.0f + lx + 10.0f * ly);
                Imf::FrameBuffer fb;
                fb.insert("Z", Imf::Slice::Make(Imf::FLOAT, z.data(), w));
                out.setFrameBuffer(fb);
                out.writeTiles(0, out.numXTiles(lx) - 1, 0, out.numYTiles(ly) - 1, lx, ly);
            }
    }
    valid.push_back(rip);
    for (const std::string& path : valid) {
        const ExrInfo info = readExrInfo(path, kDefaultMaxPixels, true);
        EXPECT_NO_THROW(checkChunkTables(path, info)) << path;
    }

    // The rip-mapped file's last entry pointed at its first tile.
    std::ifstream f(rip, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    size_t chunks = 0;
    {
        Imf::MultiPartInputFile file(rip.c_str());
        Imf::TiledInputPart in(file, 0);
        for (int ly = 0; ly < in.numYLevels(); ++ly)
            for (int lx = 0; lx < in.numXLevels(); ++lx) chunks += (size_t)in.numXTiles(lx) * in.numYTiles(ly);
    }
    size_t table = 0;  // the table follows the header; its first tile was written first
    for (size_t at = 8; at + 8 <= bytes.size() && !table; ++at) {
        uint64_t v;
        std::memcpy(&v, bytes.data() + at, 8);
        if (v == at + 8 * chunks) table = at;
    }
    ASSERT_NE(table, 0u);
    std::memcpy(bytes.data() + table + 8 * (chunks - 1), bytes.data() + table, 8);
    const std::string bad = (dir / "rip-bad.exr").string();
    std::ofstream(bad, std::ios::binary) << bytes;
    try {
        checkChunkTables(bad, readExrInfo(bad, kDefaultMaxPixels, true));
        ADD_FAILURE() << "a misplaced tile passed";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("leads to tile (0,0) of level (0,0)"), std::string::npos) << e.what();
    }
}
