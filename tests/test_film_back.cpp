// Cameras as compositors give them (issue 28, item 3): a focal length and the horizontal film
// back (--focal-mm, --aperture-mm) beside the field of view, the pixel aspect ratio of an
// anamorphic plate, and a data window cropped inside the display window, whose principal point
// stays the display window's centre. Each through the CLI, on scenes ray-cast in the test.
#include "io/camera_sources.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/read_back.h"
#include "support/scenes.h"
#include "support/scratch.h"
#include "support/studio_render.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

using namespace obscura;
using namespace obscura::test;

namespace {

// Nuke's default camera back (24.576 mm across) behind a 35 mm lens.
constexpr double kFocal = 35.0, kAperture = 24.576;
const std::vector<std::string> kFilmBack = {"--focal-mm", "35", "--aperture-mm", "24.576"};

double filmBackFovRad() { return 2.0 * std::atan(0.5 * kAperture / kFocal); }

// studioCamera()'s pose with the film back's lens over a display `width` x `height`, pixels
// `pixelAspect` times wider than tall.
Camera filmBackCamera(int width, int height, double pixelAspect = 1.0) {
    Camera c = studioCamera(width, height);
    const Camera lens = Camera::perspectiveFromFilmBack(kFocal, kAperture, width, height, pixelAspect);
    c.fx = lens.fx, c.fy = lens.fy, c.cx = lens.cx, c.cy = lens.cy;
    return c;
}

// Depth (Z) and world normals (N.X, N.Y, N.Z) of `sb` over its data window, inside its display
// window, with the header's pixel aspect ratio.
std::string writePlate(const std::filesystem::path& path, const SceneBuffers& sb, float pixelAspect = 1.0f) {
    using namespace fixtures;
    FixturePart part;
    part.displayWindow = Imath::Box2i(Imath::V2i(sb.display.x0, sb.display.y0), Imath::V2i(sb.display.x1 - 1, sb.display.y1 - 1));
    part.dataWindow = Imath::Box2i(Imath::V2i(sb.data.x0, sb.data.y0), Imath::V2i(sb.data.x1 - 1, sb.data.y1 - 1));
    auto channel = [&sb](const std::string& name, const Image& img, int c) {
        return FixtureChannel{name, Imf::FLOAT, 1, 1,
                              [&sb, &img, c](int x, int y) { return img.at(x - sb.data.x0, y - sb.data.y0)[c]; }};
    };
    part.channels.push_back(channel("Z", sb.depth, 0));
    for (int c = 0; c < 3; ++c) part.channels.push_back(channel(std::string("N.") + "XYZ"[c], sb.normal, c));
    part.editHeader = [pixelAspect](Imf::Header& h) { h.pixelAspectRatio() = pixelAspect; };
    writeFixture(path.string(), {part});
    return path.string();
}

// The pose of `cam` as --camera-to-world's value.
std::string poseFlag(const Camera& cam, int width) { return cliCameraFlags(cam, width)[3]; }

// Runs the CLI on `in` with `flags` (cpu, float output) and returns its AO over the data window.
std::vector<float> aoOf(const std::string& in, const std::filesystem::path& out, std::vector<std::string> flags) {
    std::vector<std::string> args = {in, "-o", out.string(), "--device", "cpu", "--out-type", "float", "--quiet"};
    args.insert(args.end(), flags.begin(), flags.end());
    const CliResult r = runProgram(OBSCURA_CLI_PATH, args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    return partChannel(out.string(), 0, "obscura.AO.Y");
}

std::vector<std::string> with(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

} // namespace

// The film back is the field of view it spans: the same focal length in pixels (to the float
// the kernels get), and bit for bit the same AO through the CLI as --fov-deg with that angle.
TEST(FilmBack, IsTheFieldOfViewItSpans) {
    const int W = 96, H = 64;
    const Camera a = Camera::perspectiveFromFilmBack(kFocal, kAperture, W, H);
    const Camera b = Camera::perspectiveFromFov(filmBackFovRad(), W, H);
    EXPECT_NEAR(a.fx, W * kFocal / kAperture, 1e-12);
    EXPECT_EQ((float)a.fx, (float)b.fx);
    EXPECT_EQ((float)a.fy, (float)b.fy);
    EXPECT_EQ(a.cx, b.cx);
    EXPECT_EQ(a.cy, b.cy);
    EXPECT_NEAR(a.horizontalFovRad(W), filmBackFovRad(), 1e-14);

    const auto dir = testDir("film-back");
    const SceneBuffers sb = renderScene(studioScene(), filmBackCamera(W, H), W, H);
    const std::string in = writePlate(dir / "plate.exr", sb);
    const std::vector<std::string> pose = {"--camera-to-world", poseFlag(sb.camera, W)};
    char fov[40];
    std::snprintf(fov, sizeof fov, "%.17g", filmBackFovRad() * 180.0 / M_PI);
    const std::vector<float> byFilmBack = aoOf(in, dir / "a.exr", with(kFilmBack, pose));
    const std::vector<float> byFov = aoOf(in, dir / "b.exr", with({"--fov-deg", fov}, pose));
    ASSERT_EQ(byFilmBack.size(), (size_t)W * H);
    EXPECT_EQ(byFilmBack, byFov);
    EXPECT_LT(*std::min_element(byFilmBack.begin(), byFilmBack.end()), 0.8f) << "the scene must have occlusion";
}

// A plane seen through the film-back camera, with its true normals, is unoccluded (AO = 1):
// the reconstructed plane lies in the given tangent planes only if the lens is the one that
// rendered it. A wrong aperture tilts it against them, and the plane occludes itself.
TEST(FilmBack, PlaneIsUnoccludedThroughTheRightLens) {
    const int W = 96, H = 64;
    const auto dir = testDir("film-back");
    const Camera cam = filmBackCamera(W, H);
    const Rect plane = planeRect(glm::dvec3(0, 0, 0), glm::normalize(glm::dvec3(1, 0, 0.3)), glm::dvec3(0, 0.2, 1));
    const SceneBuffers sb = renderScene({plane}, cam, W, H);
    const std::string in = writePlate(dir / "plane.exr", sb);
    const std::vector<std::string> pose = {"--camera-to-world", poseFlag(cam, W), "--radius", "2"};
    const std::vector<float> right = aoOf(in, dir / "right.exr", with(kFilmBack, pose));
    ASSERT_EQ(right.size(), (size_t)W * H);
    EXPECT_GE(*std::min_element(right.begin(), right.end()), 1.0f - 1e-3f);
    const std::vector<float> depth = aoOf(in, dir / "depth.exr", with(kFilmBack, {"--normals", "depth"}));
    EXPECT_GE(*std::min_element(depth.begin(), depth.end()), 1.0f - 1e-3f);
    const std::vector<float> wrong =
        aoOf(in, dir / "wrong.exr", with({"--focal-mm", "35", "--aperture-mm", "16"}, pose));
    EXPECT_LT(*std::min_element(wrong.begin(), wrong.end()), 0.99f) << "a wrong lens must show";
}

// An anamorphic plate (pixels twice as wide as tall, pixelAspectRatio 2) gives the AO of the
// square-pixel render of the same frame at twice the width: each of its pixels that of the two
// square pixels it covers, up to the sampling of each. Read as square pixels (the header's ratio
// 1) the same plate is a squashed scene, several times farther off. rtao traces its rays in the
// scene, so it shows the camera alone; hbao marches a circle of pixels, which must reach the
// long axis of R's ellipse on the screen (R fy pixels tall): R fx pixels gave twice the error.
TEST(FilmBack, AnamorphicPlateMatchesTheSquarePixelRender) {
    const int W = 128, H = 64;
    const auto dir = testDir("film-back");
    const SceneBuffers square = renderScene(studioScene(), filmBackCamera(W, H), W, H);
    const SceneBuffers squeezed = renderScene(studioScene(), filmBackCamera(W / 2, H, 2.0), W / 2, H);
    ASSERT_DOUBLE_EQ(filmBackCamera(W / 2, H, 2.0).fy, filmBackCamera(W, H).fy);
    const std::string squareIn = writePlate(dir / "square.exr", square);
    const std::string par2In = writePlate(dir / "par2.exr", squeezed, 2.0f);
    const std::string par1In = writePlate(dir / "par1.exr", squeezed, 1.0f);
    const std::vector<std::string> pose = {"--camera-to-world", poseFlag(square.camera, W)};
    for (const auto& [method, within, ratio] : {std::tuple{"rtao", 0.008, 0.2}, {"hbao", 0.008, 0.2}}) {
        const std::vector<std::string> flags = with(kFilmBack, with(pose, {"--method", method}));
        const std::vector<float> full = aoOf(squareIn, dir / "square_ao.exr", flags);
        const std::vector<float> par2 = aoOf(par2In, dir / "par2_ao.exr", flags);
        const std::vector<float> par1 = aoOf(par1In, dir / "par1_ao.exr", flags);
        ASSERT_EQ(full.size(), (size_t)W * H);
        ASSERT_EQ(par2.size(), (size_t)W / 2 * H);
        double err2 = 0, err1 = 0;
        int n = 0;
        for (int y = 0; y < H; ++y)
            for (int x = 0; x < W / 2; ++x) {
                const float z = *squeezed.depth.at(x, y), zl = *square.depth.at(2 * x, y);
                const float zr = *square.depth.at(2 * x + 1, y);
                if (!(z < 1e9f && zl < 1e9f && zr < 1e9f) || std::fabs(zl - zr) > 0.05f * z) continue;
                const double expected = 0.5 * (full[y * W + 2 * x] + full[y * W + 2 * x + 1]);
                err2 += std::fabs(par2[y * (W / 2) + x] - expected);
                err1 += std::fabs(par1[y * (W / 2) + x] - expected);
                ++n;
            }
        ASSERT_GT(n, W * H / 4);
        err2 /= n, err1 /= n;
        std::printf("%s: mean |AO - square render's|: pixel aspect 2: %.4f, read as 1: %.4f (%d pixels)\n", method,
                    err2, err1, n);
        EXPECT_LT(err2, within) << method;
        EXPECT_LT(err2, ratio * err1) << method;
    }
}

// A plate whose data window is a crop inside the display window keeps the full frame's
// principal point (the display window's centre): in its pixels farther from the crop's edges
// than the AO reaches, its AO is the full frame's, bit for bit.
TEST(FilmBack, CroppedDataWindowGivesTheFullFramesAo) {
    const int W = 128, H = 96;
    const Box2i display{0, 0, W, H}, crop{36, 20, 116, 84};  // off centre: the crop's own centre is not the frame's
    const auto dir = testDir("film-back");
    const Camera cam = filmBackCamera(W, H);
    const SceneBuffers whole = renderScene(studioScene(), cam, display, display);
    const SceneBuffers part = renderScene(studioScene(), cam, display, crop);
    const std::vector<std::string> flags = with(kFilmBack, {"--camera-to-world", poseFlag(cam, W), "--radius", "0.25"});
    const std::vector<float> a = aoOf(writePlate(dir / "whole.exr", whole), dir / "whole_ao.exr", flags);
    const std::vector<float> b = aoOf(writePlate(dir / "crop.exr", part), dir / "crop_ao.exr", flags);
    ASSERT_EQ(b.size(), (size_t)crop.width() * crop.height());
    // R = 0.25 projects to at most fx R / z pixels; the studio's nearest surface is beyond z = 3.
    const int band = (int)std::ceil(cam.fx * 0.25 / 3.0) + 2;
    int compared = 0, occluded = 0;
    for (int y = crop.y0 + band; y < crop.y1 - band; ++y)
        for (int x = crop.x0 + band; x < crop.x1 - band; ++x) {
            if (!(*whole.depth.at(x, y) < 1e9f)) continue;
            const float inWhole = a[y * W + x], inCrop = b[(y - crop.y0) * crop.width() + (x - crop.x0)];
            ASSERT_EQ(inWhole, inCrop) << "display pixel " << x << "," << y;
            ++compared;
            occluded += inWhole < 0.95f;
        }
    EXPECT_GT(compared, 1000);
    EXPECT_GT(occluded, 50) << "the compared pixels must hold some occlusion";
}

// The plate a compositor is handed: half-float RGBA and Z, no normal pass, no camera in the
// header, its data window a crop inside the display window, background Z = 0 where alpha is 0.
// With only the film back it is written: every input channel kept as it was, the AO finite in
// [0, 1], and bit for bit the AO of --fov-deg at the matching angle.
TEST(FilmBack, HalfFloatRgbaZPlateIsWrittenWithTheFilmBackAlone) {
    const int W = 96, H = 64;
    const Box2i display{0, 0, W, H}, crop{10, 6, 90, 60};
    const auto dir = testDir("film-back");
    const SceneBuffers sb = renderScene(studioScene(), filmBackCamera(W, H), display, crop);
    using namespace fixtures;
    FixturePart part;
    part.displayWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(W - 1, H - 1));
    part.dataWindow = Imath::Box2i(Imath::V2i(crop.x0, crop.y0), Imath::V2i(crop.x1 - 1, crop.y1 - 1));
    auto sky = [&sb](int x, int y) { return !(*sb.depth.at(x - sb.data.x0, y - sb.data.y0) < 1e9f); };
    part.channels.push_back({"Z", Imf::HALF, 1, 1, [&sb, sky](int x, int y) {
                                 return sky(x, y) ? 0.0f : *sb.depth.at(x - sb.data.x0, y - sb.data.y0);
                             }});
    for (const char* c : {"R", "G", "B"}) part.channels.push_back({c, Imf::HALF, 1, 1, {}});
    part.channels.push_back({"A", Imf::HALF, 1, 1, [sky](int x, int y) { return sky(x, y) ? 0.0f : 1.0f; }});
    const std::string in = (dir / "plate.exr").string();
    writeFixture(in, {part});
    char fov[40];
    std::snprintf(fov, sizeof fov, "%.17g", filmBackFovRad() * 180.0 / M_PI);
    const std::vector<float> ao = aoOf(in, dir / "film.exr", kFilmBack);
    ASSERT_EQ(ao.size(), (size_t)crop.width() * crop.height());
    EXPECT_EQ(ao, aoOf(in, dir / "fov.exr", {"--fov-deg", fov}));
    int occluded = 0;
    for (float v : ao) {
        ASSERT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f) << v;
        occluded += v < 0.9f;
    }
    EXPECT_GT(occluded, 20);
    for (const FixtureChannel& ch : part.channels) {
        const std::vector<float> kept = partChannel((dir / "film.exr").string(), 0, ch.name);
        ASSERT_EQ(kept.size(), ao.size()) << ch.name;
        for (int y = crop.y0; y < crop.y1; ++y)
            for (int x = crop.x0; x < crop.x1; ++x)
                ASSERT_EQ(kept[(y - crop.y0) * crop.width() + (x - crop.x0)], storedValue(ch, x, y)) << ch.name;
    }
}

// The lens flags go together and alone: a focal length without its film back, or two lenses,
// is a usage error naming the flags, and nothing is written.
TEST(FilmBack, LensFlagsAreRefusedApart) {
    const auto dir = testDir("film-back");
    const std::string in = writePlate(dir / "plate.exr", renderScene(studioScene(), filmBackCamera(32, 24), 32, 24));
    const std::filesystem::path out = dir / "never.exr";
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
        {{"--focal-mm", "35"}, "--focal-mm needs --aperture-mm"},
        {{"--aperture-mm", "36"}, "--aperture-mm needs --focal-mm"},
        {{"--focal-mm", "35", "--aperture-mm", "36", "--fov-deg", "40"}, "give either --fov-deg or --focal-mm/--aperture-mm, not both"},
        {{"--focal-mm", "35", "--aperture-mm", "36", "--ortho-width", "4"}, "not both"},
    };
    for (const auto& [flags, words] : cases) {
        std::vector<std::string> args = {in, "-o", out.string(), "--normals", "depth"};
        args.insert(args.end(), flags.begin(), flags.end());
        const CliResult r = runProgram(OBSCURA_CLI_PATH, args);
        EXPECT_EQ(r.exitCode, 2) << r.err;
        EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
}
