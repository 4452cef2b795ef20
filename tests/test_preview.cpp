// --preview: one display encoding (the sRGB OETF of clamped linear values, 8 bits) for AO and
// SSDO; SSDO shows its relit layer when written, else its DO; --preview-exposure scales the
// linear values by 2^EV before encoding; without it SSDO is exposed so that its 99th
// percentile stays below clipping.
#include "io/exr_file.h"
#include "io/png_file.h"
#include "io/preview.h"
#include "support/cli_fixtures.h"
#include "support/cli_runner.h"
#include "support/scratch.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

const std::string kRoom = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";

struct Png {
    int width = 0, height = 0, channels = 0;
    std::vector<std::uint8_t> bytes;
    int at(int x, int y, int c) const { return bytes[((size_t)y * width + x) * channels + c]; }
};

Png readPng(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << path << ": " << OIIO::geterror();
    Png p;
    if (!in) return p;
    const OIIO::ImageSpec& spec = in->spec();
    p.width = spec.width, p.height = spec.height, p.channels = spec.nchannels;
    p.bytes.resize((size_t)p.width * p.height * p.channels);
    EXPECT_TRUE(in->read_image(0, 0, 0, p.channels, OIIO::TypeDesc::UINT8, p.bytes.data()));
    return p;
}

// A layer's channels (e.g. {"Relit.R", "Relit.G", "Relit.B"}) interleaved into one image.
Image readLayer(const std::string& path, const std::vector<std::string>& names) {
    const ExrInfo info = readExrInfo(path);
    std::vector<ChannelRef> wanted;
    for (const std::string& n : names) wanted.push_back({0, n});
    const std::vector<Image> planes = readExrChannels(path, info, wanted, false, nullptr);
    Image img(planes[0].width, planes[0].height, (int)planes.size());
    for (size_t i = 0; i < planes[0].pixels.size(); ++i)
        for (size_t c = 0; c < planes.size(); ++c) img.pixels[i * planes.size() + c] = planes[c].pixels[i];
    return img;
}

std::vector<std::string> rgb(const std::string& layer) { return {layer + ".R", layer + ".G", layer + ".B"}; }

// The encoding written out here from IEC 61966-2-1, not taken from obscura.
int encoded(double linear) {
    const double v = std::clamp(std::isnan(linear) ? 0.0 : linear, 0.0, 1.0);
    return (int)std::lround(255.0 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055));
}

// The largest difference, in 8-bit steps, between the PNG and `img` x 2^ev encoded.
int maxStepsFrom(const Png& png, const Image& img, double ev) {
    EXPECT_EQ(png.width, img.width);
    EXPECT_EQ(png.height, img.height);
    EXPECT_EQ(png.channels, std::min(img.channels, 3));
    int worst = 0;
    for (int y = 0; y < png.height; ++y)
        for (int x = 0; x < png.width; ++x)
            for (int c = 0; c < png.channels; ++c)
                worst = std::max(worst, std::abs(png.at(x, y, c) - encoded(img.at(x, y)[c] * std::exp2(ev))));
    return worst;
}

// Runs the CLI on the room with `flags`, writing OUT.exr and OUT.png in `dir`.
void runRoom(const fs::path& dir, const std::string& name, std::vector<std::string> flags) {
    flags.insert(flags.begin(), {kRoom, "-o", (dir / (name + ".exr")).string(), "--preview",
                                 (dir / (name + ".png")).string(), "--out-type", "float", "--quiet"});
    const CliResult r = runProgram(OBSCURA_CLI_PATH, flags);
    ASSERT_EQ(r.exitCode, 0) << r.err;
}

// DO alone, and with the bounce (which writes GI and relit too).
const std::vector<std::string> kSsdo = {"--method", "ssdo", "--samples", "16"};
const std::vector<std::string> kSsdoBounce = {"--method", "ssdo", "--samples", "16", "--bounce"};

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

} // namespace

// The AO preview is the AO through the sRGB OETF (0.5 -> 188), not linear data (0.5 -> 128),
// with or without an exposure.
TEST(Preview, AoIsSrgbEncoded) {
    const fs::path dir = testDir("preview");
    runRoom(dir, "ao", {});
    runRoom(dir, "ao_up", {"--preview-exposure", "1"});
    const Image ao = readLayer((dir / "ao.exr").string(), {"obscura.AO.Y"});
    EXPECT_LE(maxStepsFrom(readPng((dir / "ao.png").string()), ao, 0.0), 1);
    EXPECT_LE(maxStepsFrom(readPng((dir / "ao_up.png").string()), ao, 1.0), 1);
    EXPECT_EQ(encoded(0.5), 188);
}

// ssdo previews the relit layer when it is written, else the DO layer; the two differ enough
// that matching one is not matching the other.
TEST(Preview, SsdoShowsRelitWhenWritten) {
    const fs::path dir = testDir("preview");
    runRoom(dir, "relit", with(kSsdoBounce, {"--out-layer", "relit=Relit", "--preview-exposure", "0"}));
    runRoom(dir, "do", with(kSsdo, {"--preview-exposure", "0"}));
    const Png relitPng = readPng((dir / "relit.png").string()), doPng = readPng((dir / "do.png").string());
    const Image relit = readLayer((dir / "relit.exr").string(), rgb("Relit"));
    const Image direct = readLayer((dir / "do.exr").string(), rgb("obscura.DO"));
    EXPECT_LE(maxStepsFrom(relitPng, relit, 0.0), 1);
    EXPECT_LE(maxStepsFrom(doPng, direct, 0.0), 1);
    EXPECT_GT(maxStepsFrom(relitPng, direct, 0.0), 16);
}

// --preview-exposure EV multiplies the linear values by 2^EV before the encoding.
TEST(Preview, ExposureScalesLinearValues) {
    const fs::path dir = testDir("preview");
    const Image* relit = nullptr;
    Image layer;
    for (double ev : {-1.5, 2.0}) {
        const std::string name = "ev" + std::to_string((int)(ev * 10));
        runRoom(dir, name, with(kSsdoBounce, {"--out-layer", "relit=Relit", "--preview-exposure", std::to_string(ev)}));
        if (!relit) layer = readLayer((dir / (name + ".exr")).string(), rgb("Relit")), relit = &layer;
        EXPECT_LE(maxStepsFrom(readPng((dir / (name + ".png")).string()), *relit, ev), 1) << ev;
    }
}

// Without --preview-exposure, ssdo's preview is exposed so that at most 1 % of its pixels reach
// white in any channel: a sunlit scene far above 1 no longer clips.
TEST(Preview, AutoExposureKeepsThe99thPercentileBelowClipping) {
    const fs::path dir = testDir("preview");
    // A light 20 times the sky's: the floor's DO is far above 1.
    runRoom(dir, "sun", with(kSsdo, {"--light", "0.3,-0.5,0.8,20,19,17"}));
    const Png png = readPng((dir / "sun.png").string());
    const Image direct = readLayer((dir / "sun.exr").string(), rgb("obscura.DO"));
    const double p99 = previewPercentile99(direct);
    ASSERT_GT(p99, 2.0) << "the test needs light above 1";
    std::vector<int> peaks;
    for (int y = 0; y < png.height; ++y)
        for (int x = 0; x < png.width; ++x)
            peaks.push_back(std::max({png.at(x, y, 0), png.at(x, y, 1), png.at(x, y, 2)}));
    std::sort(peaks.begin(), peaks.end());
    EXPECT_LT(peaks[(size_t)std::ceil(0.99 * peaks.size()) - 1], 255);
    // And it is the documented exposure: the 99th percentile at kAutoExposurePeak.
    EXPECT_LE(maxStepsFrom(png, direct, std::log2(kAutoExposurePeak / p99)), 1);
}

// The automatic exposure on synthetic values: a percentile, not the maximum, so one hot pixel
// does not darken the frame, and of the largest channel, so a saturated colour does not clip.
TEST(Preview, AutoExposureIgnoresTheTopPercent) {
    Image img(100, 10, 3, 0.0f);
    for (int i = 0; i < 1000; ++i) {
        float* p = img.pixels.data() + (size_t)i * 3;
        p[0] = 4.0f * (i + 1) / 1000.0f, p[1] = p[0] / 4, p[2] = p[0] / 8;  // a red ramp up to 4
    }
    img.pixels[0] = 1e6f;                               // one hot pixel
    img.pixels[3] = img.pixels[4] = img.pixels[5] = std::nanf("");  // one NaN pixel, left out
    const float scale = std::exp2(autoExposureEv(img));
    int clipped = 0;
    for (int i = 2; i < 1000; ++i) clipped += img.pixels[(size_t)i * 3] * scale > 1.0f;
    EXPECT_LE(clipped, 10);                                 // at most 1 % of the finite pixels
    EXPECT_NEAR(4.0f * scale, kAutoExposurePeak, 0.01f);   // the ramp's top, in red, near the peak
    EXPECT_EQ(autoExposureEv(Image(4, 4, 3, 0.0f)), 0.0f);  // nothing to expose
}

// The flag asks for a preview and a sane number; without one it is a usage error.
TEST(Preview, ExposureFlagIsChecked) {
    const fs::path dir = testDir("preview");
    const std::string out = (dir / "x.exr").string(), png = (dir / "x.png").string();
    for (const auto& args : std::vector<std::vector<std::string>>{
             {kRoom, "-o", out, "--preview-exposure", "1"},
             {kRoom, "-o", out, "--preview", png, "--preview-exposure", "bright"},
             {kRoom, "-o", out, "--preview", png, "--preview-exposure", "99"}}) {
        const CliResult r = runProgram(OBSCURA_CLI_PATH, args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find("--preview-exposure"), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(png));
}

// The PNG writer against OpenImageIO's reader (libpng): every channel count, odd sizes, bytes
// that exercise every scanline filter, read back exactly; the colour tag as written.
TEST(PngFile, ReadsBackExactlyWithItsTag) {
    const fs::path dir = testDir("png");
    std::uint32_t state = 12345;
    for (int channels = 1; channels <= 4; ++channels) {
        const int width = 37 + channels, height = 11;
        std::vector<std::uint8_t> bytes((size_t)width * height * channels);
        for (size_t i = 0; i < bytes.size(); ++i) {
            state = state * 1664525u + 1013904223u;
            // Smooth ramps (Sub, Up, Paeth win) beside noise (None wins).
            bytes[i] = (i / channels) % width < (size_t)width / 2 ? (std::uint8_t)(i * 3) : (std::uint8_t)(state >> 24);
        }
        for (const std::string tag : {"sRGB", "", "ACEScg"}) {
            SCOPED_TRACE(std::to_string(channels) + " channels, tag '" + tag + "'");
            const std::string path = (dir / ("p" + std::to_string(channels) + tag + ".png")).string();
            ASSERT_EQ(writePngFile(path, width, height, channels, bytes.data(), tag), "");
            OIIO::ImageSpec config;
            config.attribute("oiio:UnassociatedAlpha", 1);  // the bytes as stored, alpha not multiplied in
            auto in = OIIO::ImageInput::open(path, &config);
            ASSERT_TRUE(in) << OIIO::geterror();
            const OIIO::ImageSpec& spec = in->spec();
            EXPECT_EQ(spec.width, width);
            EXPECT_EQ(spec.height, height);
            ASSERT_EQ(spec.nchannels, channels);
            std::vector<std::uint8_t> read(bytes.size());
            ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT8, read.data()));
            EXPECT_EQ(read, bytes);
            // Untagged: no colour chunk or text (OpenImageIO then assumes sRGB for 8 bits).
            const std::string file = fileBytes(path);
            if (tag.empty()) EXPECT_EQ(file.find("sRGB"), std::string::npos);
            else EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"), tag);
            EXPECT_EQ(file.find("gAMA") != std::string::npos, tag == "sRGB");
        }
    }
    EXPECT_NE(writePngFile((dir / "none" / "p.png").string(), 2, 2, 1, std::vector<std::uint8_t>(4).data(), ""), "");
}
