// The default AO is clean (issue 31): on a flat wall of a report scene, what changes from one
// pixel to the next is no more than in the ray-traced reference, plus less than a display step.
#include "io/exr_file.h"
#include "support/reference_runs.h"
#include "support/scratch.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using namespace obscura;
using namespace obscura::test;
namespace fs = std::filesystem;

namespace {

Image channel(const std::string& path, const std::string& name) {
    const ExrInfo info = readExrInfo(path);
    return std::move(readExrChannels(path, info, {{0, name}}, false, nullptr).at(0));
}

// reference_render's cornell box: the back wall (y = 2, facing -y) above both boxes and the
// light's height, clear of the side walls. Its AO is smooth: the ceiling and the side walls
// darken it gradually towards the edges, within the default radius.
std::vector<bool> backWall(const std::string& path) {
    const Image px = channel(path, "ViewLayer.Position.X"), py = channel(path, "ViewLayer.Position.Y"),
                pz = channel(path, "ViewLayer.Position.Z"), ny = channel(path, "ViewLayer.Normal.Y");
    std::vector<bool> in(px.pixels.size());
    for (size_t i = 0; i < in.size(); ++i)
        in[i] = ny.pixels[i] < -0.99f && std::abs(py.pixels[i] - 2.0f) < 1e-3f && px.pixels[i] > 0.1f &&
                px.pixels[i] < 1.9f && pz.pixels[i] > 1.3f && pz.pixels[i] < 1.9f;
    return in;
}

// The grain of `ao` over `region`: the standard deviation of each pixel's difference from the
// mean of its 3 x 3 neighbourhood (over pixels whose whole neighbourhood is in the region).
// Not the plain standard deviation: the wall's AO really changes across the region (0.099 in
// the reference, from the ceiling and side walls), more than any grain, so that would measure
// the shading, and be lowest for a method that darkens least. A linear gradient leaves 0 here.
double grain(const Image& ao, const std::vector<bool>& region) {
    double sum = 0, sum2 = 0;
    long n = 0;
    for (int y = 1; y + 1 < ao.height; ++y)
        for (int x = 1; x + 1 < ao.width; ++x) {
            double mean = 0;
            bool inside = true;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    inside = inside && region[(size_t)(y + dy) * ao.width + x + dx];
                    mean += *ao.at(x + dx, y + dy) / 9.0;
                }
            if (!inside) continue;
            const double d = *ao.at(x, y) - mean;
            sum += d, sum2 += d * d, ++n;
        }
    EXPECT_GT(n, 1000) << "the wall must cover enough pixels";
    return std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
}

double meanOver(const Image& ao, const std::vector<bool>& region) {
    double sum = 0;
    long n = 0;
    for (size_t i = 0; i < region.size(); ++i)
        if (region[i]) sum += ao.pixels[i], ++n;
    return sum / n;
}

// One 8-bit step of an sRGB-encoded preview at linear value v, in linear units: the inverse
// of the sRGB OETF's slope (its power segment), over 255.
double displayStep(double v) { return 1.0 / (255.0 * (1.055 / 2.4) * std::pow(v, 1.0 / 2.4 - 1.0)); }

} // namespace

// At the defaults (the `medium` preset: 8 x 8 and a 1-pixel blur), the grain on the wall is
// below the reference's own (its 256 rays' noise) plus half a display step at the wall's AO:
// grain that small mostly rounds away in an 8-bit preview and cannot read as speckle. The old
// default (8 x 8 with no blur) must exceed the same bound, or the figure tells nothing apart.
TEST(Grain, DefaultAoIsCleanOnAFlatWall) {
    const fs::path dir = testDir("grain");
    const std::string ref = (dir / "cornell.exr").string();
    // The reference at obscura's default radius (1), so every setting of the run is a default.
    const CliResult r = renderReferenceScene("cornell", ref, 200, 150, {"--radius", "1"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto aoOf = [&](const std::string& name, std::vector<std::string> flags) {
        const std::string out = (dir / (name + ".exr")).string();
        flags.insert(flags.begin(), {ref, "-o", out, "--write", "new", "--quiet"});
        const CliResult c = runProgram(OBSCURA_CLI_PATH, flags);
        EXPECT_EQ(c.exitCode, 0) << c.err;
        return channel(out, "obscura.AO.Y");
    };
    const std::vector<bool> wall = backWall(ref);
    const Image reference = channel(ref, "Reference.AO_uniform_linear.Y");  // the default weighting and falloff
    const double refGrain = grain(reference, wall), after = grain(aoOf("default", {}), wall),
                 before = grain(aoOf("blur0", {"--blur", "0"}), wall);
    const double bound = refGrain + 0.5 * displayStep(meanOver(reference, wall));
    std::printf("cornell back wall grain: reference %.4f, 8x8 blur 0 %.4f, default %.4f, bound %.4f\n", refGrain,
                before, after, bound);
    EXPECT_LT(after, bound);   // measured 0.0018 against 0.0050
    EXPECT_GT(before, bound);  // measured 0.0107
}
