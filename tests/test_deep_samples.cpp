// The deep sample reader (io/deep_samples.h) against files another library wrote: OpenImageIO's
// deep writer, scanline and tiled, half, float and uint channels, a data window cropped inside the
// display window and taller than one band of rows; and a file whose sample counts claim more
// than it holds, refused before anything is allocated.
#include "base/error.h"
#include "io/deep_samples.h"
#include "support/exr_fixtures.h"
#include "support/scratch.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenImageIO/deepdata.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <Imath/half.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

// The written file: 24 x 150 pixels at (3, 5) inside a 40 x 160 display window; pixel p holds
// (x + y) % 4 samples (display coordinates); channel c of sample s a value exact in half, and an
// object id as uint (as renderers write ids), too large for half.
constexpr int kX = 3, kY = 5, kW = 24, kH = 150;
const std::vector<std::string> kNames = {"A", "B", "G", "R", "Z", "ZBack", "id"};  // sorted, as OpenEXR lists them
constexpr int kId = 6;

int countAt(int x, int y) { return (x + y) % 4; }
float valueAt(int x, int y, int s, int c) {
    return c == kId ? (float)(100000 + (x * 7 + y * 3 + s * 11) % 1000) : (float)((x * 7 + y * 3 + s * 11 + c * 5) % 64) * 0.25f;
}

void writeDeep(const std::string& path, bool tiled, bool half, const std::string& compression) {
    OIIO::ImageSpec spec(kW, kH, (int)kNames.size(), half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelnames = kNames;
    spec.channelformats.assign(kNames.size(), half ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
    spec.channelformats[kId] = OIIO::TypeDesc::UINT;
    spec.x = kX;
    spec.y = kY;
    spec.full_x = spec.full_y = 0;
    spec.full_width = 40;
    spec.full_height = 160;
    spec.deep = true;
    spec.attribute("compression", compression);
    if (tiled) spec.tile_width = spec.tile_height = 16;
    OIIO::DeepData dd;
    dd.init(spec);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) dd.set_samples((int64_t)y * kW + x, countAt(x + kX, y + kY));
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            for (int s = 0; s < countAt(x + kX, y + kY); ++s)
                for (int c = 0; c < (int)kNames.size(); ++c) {
                    const float v = valueAt(x + kX, y + kY, s, c);
                    if (c == kId)
                        dd.set_deep_value((int64_t)y * kW + x, c, s, (uint32_t)v);
                    else
                        dd.set_deep_value((int64_t)y * kW + x, c, s, v);
                }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
    ASSERT_TRUE(out->write_deep_image(dd)) << out->geterror();
    ASSERT_TRUE(out->close());
}

void expectWindows(const DeepWindows& w) {
    EXPECT_EQ(w.fullWidth, 40);
    EXPECT_EQ(w.fullHeight, 160);
    EXPECT_EQ(w.x, kX);
    EXPECT_EQ(w.y, kY);
    ASSERT_EQ(w.width, kW);
    ASSERT_EQ(w.height, kH);
    ASSERT_EQ(w.counts.size(), (size_t)kW * kH);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x) ASSERT_EQ((int)w.counts[(size_t)y * kW + x], countAt(x + kX, y + kY)) << x << "," << y;
}

} // namespace

TEST(DeepSamples, EveryLayoutReadsAsWritten) {
    const fs::path dir = testDir("deep-samples");
    for (const bool tiled : {false, true})
        for (const bool half : {false, true})
            for (const std::string compression : {"none", "zips", "zip", "rle"}) {
                SCOPED_TRACE(std::string(tiled ? "tiled " : "scanline ") + (half ? "half " : "float ") + compression);
                const std::string path = (dir / "deep.exr").string();
                writeDeep(path, tiled, half, compression);
                const Imf::MultiPartInputFile file(path.c_str());
                const Imf::ChannelList& written = file.header(0).channels();
                ASSERT_EQ(written.findChannel("id")->type, Imf::UINT);
                ASSERT_EQ(written.findChannel("Z")->type, half ? Imf::HALF : Imf::FLOAT);
                const DeepChannels all = readDeepChannelSamples(path);
                ASSERT_EQ(all.names, kNames);
                expectWindows(all);
                const DeepSamples depths = readDeepDepthSamples(path, "Z", "ZBack");
                expectWindows(depths);
                ASSERT_TRUE(depths.hasZBack);
                size_t i = 0;
                for (int y = 0; y < kH; ++y)
                    for (int x = 0; x < kW; ++x)
                        for (int s = 0; s < countAt(x + kX, y + kY); ++s, ++i) {
                            for (int c = 0; c < (int)kNames.size(); ++c)
                                ASSERT_EQ(all.values[i * kNames.size() + c], valueAt(x + kX, y + kY, s, c));
                            ASSERT_EQ(depths.z[i], valueAt(x + kX, y + kY, s, 4));
                            ASSERT_EQ(depths.zBack[i], valueAt(x + kX, y + kY, s, 5));
                        }
                EXPECT_EQ(i * kNames.size(), all.values.size());
                EXPECT_EQ(i, depths.z.size());
                EXPECT_FALSE(readDeepDepthSamples(path, "Z", "no such").hasZBack);
            }
}

// OpenEXR's sample counts are a running total per scanline: one raised to 2^26 claims 1.6 GB of
// samples in a file of 150 kB. Refused in one line naming the file, before allocating.
TEST(DeepSamples, CountsBeyondTheFilesSizeAreRefused) {
    const fs::path dir = testDir("deep-samples-bomb");
    const std::string path = (dir / "bomb.exr").string();
    writeDeep(path, false, false, "none");
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // The first row's running totals, found in the file and raised at its last pixel.
    std::vector<int> totals;
    for (int x = 0, t = 0; x < kW; ++x) totals.push_back(t += countAt(x + kX, kY));
    const char* first = reinterpret_cast<const char*>(totals.data());
    const auto at = std::search(bytes.begin(), bytes.end(), first, first + totals.size() * sizeof(int));
    ASSERT_NE(at, bytes.end());
    const int huge = 1 << 26;
    std::memcpy(&*(at + (totals.size() - 1) * sizeof(int)), &huge, sizeof huge);
    // The chunk's unpacked size (the 8 bytes before the table) raised to match: OpenEXR checks
    // the counts against that claim, not against the file.
    const unsigned long long unpacked = 2000000000ull;  // OpenEXR's bound on a chunk: 2^31 - 1
    std::memcpy(&*(at - sizeof unpacked), &unpacked, sizeof unpacked);
    std::ofstream(path, std::ios::binary).write(bytes.data(), (std::streamsize)bytes.size());
    for (const bool depthsOnly : {false, true}) {
        try {
            if (depthsOnly)
                readDeepDepthSamples(path, "Z", "ZBack");
            else
                readDeepChannelSamples(path);
            ADD_FAILURE() << "read";
        } catch (const FileError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("bomb.exr"), std::string::npos) << what;
            EXPECT_NE(what.find("more than its size can hold"), std::string::npos) << what;
            EXPECT_EQ(what.find('\n'), std::string::npos) << what;
        }
    }
}

TEST(DeepSamples, FlatFileAndMissingZAreOneLineErrors) {
    const fs::path dir = testDir("deep-samples-errors");
    const std::string deep = (dir / "deep.exr").string(), flat = (dir / "flat.exr").string();
    writeDeep(deep, false, true, "zips");
    fixtures::FixturePart part;
    fixtures::FixtureChannel z;
    z.name = "Z";
    z.value = [](int, int) { return 1.0f; };
    part.channels.push_back(z);
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(3, 3));
    fixtures::writeFixture(flat, {part});
    const auto message = [](auto read) {
        try {
            read();
        } catch (const FileError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message([&] { readDeepChannelSamples(flat); }).find("not a deep image"), std::string::npos);
    EXPECT_NE(message([&] { readDeepDepthSamples(deep, "depth.Z", ""); }).find("without a depth.Z channel"), std::string::npos);
    EXPECT_NE(message([&] { readDeepDepthSamples((dir / "none.exr").string(), "Z", ""); }).find("no such file"),
              std::string::npos);
}
