// The same scene described in two colour spaces gives the same GI: the colour passes are
// converted into the working space before the bounce, whatever space the file is in, and the
// GI is written back in the file's space.
#include "core/operator.h"
#include "io/colour.h"
#include "io/exr_file.h"
#include "io/frame_job.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

// A Blender-named file of the studio scene with the given direct-diffuse and albedo passes.
void writeScene(const std::string& path, const SceneBuffers& sb, const Image& direct, const Image& albedo,
                const std::string& colourSpace) {
    fixtures::FixturePart part;
    auto channel = [&](const std::string& name, const Image& img, int c) {
        fixtures::FixtureChannel ch;
        ch.name = name;
        ch.value = [&img, c](int x, int y) { return img.at(x, y)[c]; };
        return ch;
    };
    part.channels.push_back(channel("ViewLayer.Depth.Z", sb.depth, 0));
    for (int c = 0; c < 3; ++c) {
        part.channels.push_back(channel(std::string("ViewLayer.Normal.") + "XYZ"[c], sb.normal, c));
        part.channels.push_back(channel(std::string("ViewLayer.DiffDir.") + "RGB"[c], direct, c));
        part.channels.push_back(channel(std::string("ViewLayer.DiffCol.") + "RGB"[c], albedo, c));
    }
    part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(sb.depth.width - 1, sb.depth.height - 1));
    part.stringAttributes["oiio:ColorSpace"] = colourSpace;
    fixtures::writeFixture(path, {part});
}

Image readRgb(const std::string& path, const std::string& layer) {
    const ExrInfo info = readExrInfo(path);
    std::vector<Image> planes = readExrChannels(path, info, {{0, layer + ".R"}, {0, layer + ".G"}, {0, layer + ".B"}}, false, nullptr);
    return interleavePlanes(planes, 0, 3);
}

} // namespace

TEST(ColourGi, Rec709AndAcescgDescriptionsGiveTheSameGi) {
    const fs::path dir = fs::path(OBSCURA_TEST_TMP) / ("colour-gi-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const int W = 96, H = 72;
    const SceneBuffers sb = renderScene(studioScene(), studioCamera(W, H), W, H);
    // Saturated colours per surface orientation, so the primaries matter.
    Image direct(W, H, 3), albedo(W, H, 3);
    for (int i = 0; i < W * H; ++i) {
        const float* n = &sb.normal.pixels[3 * i];
        direct.pixels[3 * i + 0] = 0.9f * std::abs(n[0]) + 0.05f;
        direct.pixels[3 * i + 1] = 0.8f * std::abs(n[1]) + 0.05f;
        direct.pixels[3 * i + 2] = 0.7f * std::abs(n[2]) + 0.05f;
        albedo.pixels[3 * i + 0] = 0.8f;
        albedo.pixels[3 * i + 1] = 0.2f + 0.5f * std::abs(n[2]);
        albedo.pixels[3 * i + 2] = 0.1f;
    }
    const ColourManager& cm = colourManager();
    Image directAp1 = direct, albedoAp1 = albedo;
    cm.convert(directAp1, "lin_rec709", "ACEScg");
    cm.convert(albedoAp1, "lin_rec709", "ACEScg");
    float differ = 0;
    for (size_t i = 0; i < direct.pixels.size(); ++i) differ = std::max(differ, std::abs(directAp1.pixels[i] - direct.pixels[i]));
    ASSERT_GT(differ, 0.05f) << "the two descriptions differ as numbers";

    const std::string a = (dir / "rec709.exr").string(), b = (dir / "acescg.exr").string();
    writeScene(a, sb, direct, albedo, "lin_rec709");
    writeScene(b, sb, directAp1, albedoAp1, "ACEScg");
    std::array<double, 16> rows{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) rows[r * 4 + c] = sb.camera.cameraToWorld[c][r];
    std::vector<Image> gi;
    for (const std::string& in : {a, b}) {
        FrameJob job;
        job.input = in;
        job.output = in + ".out.exr";
        job.camera.fovDeg = 65.0;
        job.camera.cameraToWorld = rows;
        job.settings.method = "ssdo";
        job.settings.radius = 0.8f;
        job.writeIndirect = true;
        job.aoFloat = true;  // all new layers in float
        const FrameReport report = runFrameJob(job);
        gi.push_back(readRgb(job.output, "obscura.GI"));
    }
    // Each file's GI is written in its own space: the ACEScg file's, back in Rec.709, is the other's.
    cm.convert(gi[1], "ACEScg", "lin_rec709");
    double worst = 0, peak = 0;
    for (size_t i = 0; i < gi[0].pixels.size(); ++i) {
        worst = std::max(worst, (double)std::abs(gi[0].pixels[i] - gi[1].pixels[i]));
        peak = std::max(peak, (double)gi[0].pixels[i]);
    }
    EXPECT_GT(peak, 0.05) << "the scene has a bounce to compare";
    // 1e-5 of the peak: the conversion is exact to float rounding, and GI is linear in its inputs.
    EXPECT_LE(worst, 1e-5 * std::max(1.0, peak));
    fs::remove_all(dir);
}
