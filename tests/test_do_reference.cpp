// obscura's SSDO directional occlusion against the ray-traced ground truth of
// examples/reference (reference_render --env: Reference.DO = integral of L_env (1 - W) cos,
// W linear, through the same lat-long map, z-up world, same --env-rotate).
//
// Where the reference sees nothing within R (Reference.AO_cosine_linear == 1) both are the
// cosine-weighted irradiance of the unoccluded map, so they must agree closely: this pins the
// world -> environment axes and the rotation. Elsewhere SSDO only sees the depth buffer
// (no geometry behind the visible surface or off screen), so the whole image is held to a
// PSNR floor instead.
#include "support/reference_runs.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using obscura::test::referenceRenderPath;
using obscura::test::runProgram;

namespace {

std::string tmpPath(const std::string& name) { return (fs::path(OBSCURA_TEST_TMP) / ("do_reference_" + name)).string(); }

// 32x16 lat-long map, smooth in both angles and periodic in longitude: red and blue vary with
// azimuth (90 degrees apart), green with elevation, so a wrong axis or rotation shows.
void writeGradientMap(const std::string& path) {
    const int w = 32, h = 16;
    std::vector<float> px(size_t(w) * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = (x + 0.5) / w, v = (y + 0.5) / h;
            float* p = &px[(size_t(y) * w + x) * 3];
            p[0] = float(0.6 + 0.5 * std::cos(2 * M_PI * u));
            p[1] = float(0.2 + 0.8 * (1 - v));
            p[2] = float(0.6 + 0.5 * std::sin(2 * M_PI * u));
        }
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    ASSERT_TRUE(out->open(path, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    ASSERT_TRUE(out->close());
}

struct Exr {
    int width = 0, height = 0;
    std::vector<std::string> names;
    std::vector<float> data;  // interleaved
    std::string attribute(const std::string& name) const { return attributes.count(name) ? attributes.at(name) : ""; }
    std::map<std::string, std::string> attributes;
    std::vector<float> channel(const std::string& name) const {
        const auto it = std::find(names.begin(), names.end(), name);
        EXPECT_NE(it, names.end()) << "no channel " << name;
        std::vector<float> c(size_t(width) * height, 0.0f);
        if (it == names.end()) return c;
        const size_t k = size_t(it - names.begin()), n = names.size();
        for (size_t i = 0; i < c.size(); ++i) c[i] = data[i * n + k];
        return c;
    }
};

Exr readExr(const std::string& path) {
    Exr e;
    auto in = OIIO::ImageInput::open(path);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return e;
    const OIIO::ImageSpec& spec = in->spec();
    e.width = spec.width;
    e.height = spec.height;
    e.names = spec.channelnames;
    for (const auto& a : spec.extra_attribs)
        if (a.type() == OIIO::TypeDesc::STRING) e.attributes[a.name().string()] = a.get_string();
    e.data.resize(size_t(e.width) * e.height * spec.nchannels);
    EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, e.data.data()));
    return e;
}

// Measured (96x72, 256 reference rays, 256 SSDO samples, interleave 1): sphere-plane 33.6 dB,
// corner 34.3 dB; open pixels agree to a mean 0.05% / 0.12% and at most 1.8% / 1.5%.
// The remaining error is SSDO's screen-space limits, not the environment: occluders hidden
// behind the visible surface or off screen, depth-buffer thickness (a sample behind a surface
// counts as blocked however thin it is), and the prefiltered map. A wrong axis or rotation
// costs far more (--env-rotate 120 against 30: 19.6 dB / 11.2 dB, open pixels off by up to 190%).
constexpr double kPsnrFloorDb = 30.0;

struct Agreement {
    size_t openPixels = 0, surfacePixels = 0;
    double openMeanRel = 0, openMaxRel = 0;  // |obscura - reference| / reference, per channel
    double psnr = 0;                         // over surface pixels, RGB, peak = max reference DO
};

// Renders `scene` with the map rotated by 30 degrees, runs obscura with `obscuraRotate`, compares.
class DoReference : public ::testing::Test {
protected:
    // Files are per scene: ctest may run the two tests at once.
    static std::string mapPath(const std::string& scene) { return tmpPath(scene + "_map.exr"); }

    // One render per test, shared by both rotations.
    static std::string renderReference(const std::string& scene) {
        fs::create_directories(OBSCURA_TEST_TMP);
        writeGradientMap(mapPath(scene));
        const std::string out = tmpPath(scene + "_ref.exr");
        const auto r = runProgram(referenceRenderPath(),
                                  {"--scene", scene, "-o", out, "--width", "96", "--height", "72", "--ao-rays", "256",
                                   "--gi-rays", "1", "--env", mapPath(scene), "--env-rotate", "30", "--quiet"});
        EXPECT_EQ(r.exitCode, 0) << referenceRenderPath() << ": " << r.err;
        return out;
    }

    static Agreement compare(const std::string& scene, const std::string& ref, const std::string& obscuraRotate) {
        Agreement a;
        const std::string out = tmpPath(scene + "_rot" + obscuraRotate + ".exr");
        const Exr reference = readExr(ref);
        const std::string radius = reference.attribute("reference/radius");
        EXPECT_FALSE(radius.empty());
        const auto r = runProgram(OBSCURA_CLI_PATH, {ref, "-o", out, "--method", "ssdo", "--env", mapPath(scene),
                                                     "--env-rotate", obscuraRotate, "--up", "z", "--radius", radius,
                                                     // 1024 points: 256 directions of 3 points (docs/ssdo.md)
                                                     "--samples", "1024", "--interleave", "1", "--out-type", "float",
                                                     "--quiet"});
        EXPECT_EQ(r.exitCode, 0) << r.err;
        if (r.exitCode != 0) return a;
        const Exr result = readExr(out);
        const std::vector<float> depth = reference.channel("ViewLayer.Depth.Z"),
                                 open = reference.channel("Reference.AO_cosine_linear.Y");
        const char* rgb[] = {"R", "G", "B"};
        std::vector<float> refDo[3], obsDo[3];
        for (int c = 0; c < 3; ++c) {
            refDo[c] = reference.channel(std::string("Reference.DO.") + rgb[c]);
            obsDo[c] = result.channel(std::string("obscura.DO.") + rgb[c]);
        }
        double peak = 0, sq = 0, relSum = 0;
        for (size_t i = 0; i < depth.size(); ++i) {
            if (!(depth[i] < 1e9f)) continue;
            ++a.surfacePixels;
            for (int c = 0; c < 3; ++c) {
                const double d = double(obsDo[c][i]) - refDo[c][i];
                peak = std::max(peak, double(refDo[c][i]));
                sq += d * d;
                if (open[i] == 1.0f) {
                    const double rel = std::abs(d) / std::max(1e-6, double(refDo[c][i]));
                    relSum += rel;
                    a.openMaxRel = std::max(a.openMaxRel, rel);
                }
            }
            if (open[i] == 1.0f) ++a.openPixels;
        }
        if (a.openPixels > 0) a.openMeanRel = relSum / (3.0 * a.openPixels);
        if (a.surfacePixels > 0) a.psnr = 10 * std::log10(peak * peak / std::max(1e-20, sq / (3.0 * a.surfacePixels)));
        std::printf("%s, obscura --env-rotate %s (reference 30): %zu open pixels, rel. error mean %.4f max %.4f; "
                    "%zu surface pixels, PSNR %.2f dB\n",
                    scene.c_str(), obscuraRotate.c_str(), a.openPixels, a.openMeanRel, a.openMaxRel, a.surfacePixels,
                    a.psnr);
        return a;
    }

    // `scene`'s DO under the light at 30 degrees matches the reference rendered under it (every open
    // pixel and channel within 3%), and not the reference under the light turned to 120 degrees.
    void expectMatchesItsOwnLight(const std::string& scene, size_t minOpenPixels) {
        const std::string ref = renderReference(scene);
        const Agreement same = compare(scene, ref, "30");
        ASSERT_GT(same.openPixels, minOpenPixels);
        EXPECT_LT(same.openMaxRel, 0.03);
        EXPECT_LT(same.openMeanRel, 0.005);
        EXPECT_GT(same.psnr, kPsnrFloorDb);
        const Agreement rotated = compare(scene, ref, "120");
        EXPECT_GT(rotated.openMeanRel, 10 * same.openMeanRel);
        EXPECT_GT(rotated.openMaxRel, 0.5);
    }
};

TEST_F(DoReference, SpherePlane) { expectMatchesItsOwnLight("sphere-plane", 200); }

TEST_F(DoReference, Corner) { expectMatchesItsOwnLight("corner", 100); }

} // namespace
