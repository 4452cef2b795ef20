// The command line's end-to-end test helpers (cli_fixtures.h says what each is for).
#include "support/cli_fixtures.h"

#include "support/read_back.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

namespace fs = std::filesystem;

namespace obscura::test {

using namespace obscura::fixtures;

namespace {

std::string joinNumbers(const std::array<double, 16>& a) {
    std::string s;
    char buf[40];
    for (double v : a) {
        std::snprintf(buf, sizeof buf, "%.17g", v);
        s += (s.empty() ? "" : ",") + std::string(buf);
    }
    return s;
}

// A channel whose values come from channel `c` of `img` (EXR coords -> data-window index).
FixtureChannel planeChannel(const std::string& name, const Image& img, int c, const Box2i& data, Imf::PixelType type) {
    FixtureChannel ch;
    ch.name = name;
    ch.type = type;
    const Image* src = &img;
    ch.value = [src, c, data](int x, int y) { return src->at(x - data.x0, y - data.y0)[c]; };
    return ch;
}

} // namespace

std::string describe(const CliResult& r) {
    return "exit " + std::to_string(r.exitCode) + "\n--- stdout ---\n" + r.out + "--- stderr ---\n" + r.err;
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

std::vector<std::string> tempLeftovers(const fs::path& dir) {
    std::vector<std::string> out;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        if (contains(e.path().filename().string(), ".tmp-")) out.push_back(e.path().string());
    return out;
}

void expectCleanFailure(const CliResult& r, int exitCode, const fs::path& output,
                        std::initializer_list<std::string> mentions) {
    EXPECT_EQ(r.exitCode, exitCode) << describe(r);
    EXPECT_EQ(r.err.rfind("obscura: ", 0), 0u) << describe(r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not exactly one line:\n" << describe(r);
    if (exitCode == 1) {  // a failure (not a usage error) names the file at fault first
        EXPECT_TRUE(std::regex_search(r.err, std::regex("^obscura: '[^\n]+': [^\n]+\n$"))) << describe(r);
    }
    EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << describe(r);
    for (const std::string& m : mentions) EXPECT_TRUE(contains(r.err, m)) << "'" << m << "' not in: " << r.err;
    if (!output.empty()) {
        EXPECT_FALSE(fs::exists(output)) << output << " was written";
        const fs::path dir = output.parent_path();
        if (fs::is_directory(dir)) {
            EXPECT_EQ(tempLeftovers(dir), std::vector<std::string>{});
        }
    }
}

void expectSuccess(const CliResult& r, const fs::path& output) {
    ASSERT_EQ(r.exitCode, 0) << describe(r);
    ASSERT_TRUE(fs::exists(output)) << describe(r);
    EXPECT_EQ(tempLeftovers(output.parent_path()), std::vector<std::string>{});
}

std::string fileBytes(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    std::ostringstream ss;
    ss << f.rdbuf();
    return ss.str();
}

FileData readAll(const std::string& path) {
    FileData fd;
    Imf::MultiPartInputFile file(path.c_str());
    for (int p = 0; p < file.parts(); ++p) {
        const Imf::Header& h = file.header(p);
        const Imath::Box2i dw = h.dataWindow();
        const int w = dw.max.x - dw.min.x + 1, hgt = dw.max.y - dw.min.y + 1;
        fd.dataWindows.push_back(dw);
        fd.displayWindows.push_back(h.displayWindow());
        Imf::FrameBuffer fb;
        std::vector<ChannelData*> slots;
        for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
            EXPECT_EQ(it.channel().xSampling, 1);
            EXPECT_EQ(it.channel().ySampling, 1);
            ChannelData& cd = fd.channels[std::to_string(p) + ":" + it.name()];
            cd.type = it.channel().type;
            cd.width = w;
            cd.height = hgt;
            const size_t bps = cd.type == Imf::HALF ? 2 : 4;
            cd.bytes.assign((size_t)w * hgt * bps, 0);
            fb.insert(it.name(), Imf::Slice::Make(cd.type, cd.bytes.data(), dw, bps, bps * w));
        }
        fd.tiled.push_back(h.hasTileDescription());
        obscura::test::readPart(file, p, fb);
    }
    return fd;
}

void expectChannelsKept(const FileData& in, const FileData& out) {
    ASSERT_EQ(in.dataWindows.size(), out.dataWindows.size());
    for (size_t p = 0; p < in.dataWindows.size(); ++p) EXPECT_EQ(in.dataWindows[p], out.dataWindows[p]);
    for (const auto& [key, ch] : in.channels) {
        auto it = out.channels.find(key);
        ASSERT_NE(it, out.channels.end()) << "channel " << key << " lost";
        EXPECT_EQ(it->second.type, ch.type) << key;
        EXPECT_TRUE(it->second.bytes == ch.bytes) << "channel " << key << " changed";
    }
}

SceneBuffers cornerScene(Box2i display, Box2i data) {
    const std::vector<Rect> rects = {
        obscura::test::planeRect({0, 0, 0}, {1, 0, 0}, {0, 0, 1}, 50),
        Rect{{-4, 0, -4}, {8, 0, 0}, {0, 2.5, 0}},
        Rect{{-2, 0, -4}, {0, 0, 8}, {0, 2.5, 0}},
        Rect{{0.2, 0, -1.5}, {0.8, 0, 0}, {0, 0.8, 0}},
        Rect{{0.2, 0.8, -2.3}, {0.8, 0, 0}, {0, 0, 0.8}},
        Rect{{0.2, 0, -2.3}, {0, 0, 0.8}, {0, 0.8, 0}},
    };
    const Camera cam = obscura::test::lookAtPerspective({0.4, 1.7, 2.5}, {-0.3, 0.5, -3}, kFovDeg * M_PI / 180,
                                                        display.width(), display.height());
    return obscura::test::renderScene(rects, cam, display, data);
}

SceneBuffers cornerScene(int w, int h) { return cornerScene(Box2i{0, 0, w, h}, Box2i{0, 0, w, h}); }

std::array<double, 16> rowMajor(const glm::dmat4& m) {
    std::array<double, 16> a{};
    for (int r = 0; r < 4; ++r)
        for (int c = 0; c < 4; ++c) a[r * 4 + c] = m[c][r];
    return a;
}

std::vector<std::string> cameraFlags(const SceneBuffers& s) {
    return {"--fov-deg", "70", "--camera-to-world", joinNumbers(rowMajor(s.camera.cameraToWorld))};
}

Planes planesOf(const SceneBuffers& s) { return {s.display, s.data, s.depth, s.normal, s.position}; }

Imath::Box2i toImath(const Box2i& b) { return Imath::Box2i(Imath::V2i(b.x0, b.y0), Imath::V2i(b.x1 - 1, b.y1 - 1)); }

FixturePart makePart(const Planes& p, const Naming& n, Imf::PixelType type) {
    FixturePart part;
    part.displayWindow = toImath(p.display);
    part.dataWindow = toImath(p.data);
    part.stringAttributes = n.attrs;
    part.channels.push_back(planeChannel(n.depth, p.depth, 0, p.data, type));
    for (int c = 0; c < 3; ++c) part.channels.push_back(planeChannel(n.normal[c], p.normal, c, p.data, type));
    if (!n.position[0].empty())
        for (int c = 0; c < 3; ++c) part.channels.push_back(planeChannel(n.position[c], p.position, c, p.data, type));
    for (const std::string& b : n.beauty) part.channels.push_back({b, Imf::HALF, 1, 1, {}});
    return part;
}

const Naming kGeneric = {"Z", {"N.X", "N.Y", "N.Z"}, {"P.X", "P.Y", "P.Z"}, {"R", "G", "B"}, {}};

std::string writeGeneric(const fs::path& dir, const std::string& name, const Planes& planes) {
    const std::string path = (dir / name).string();
    writeFixture(path, {makePart(planes, kGeneric)});
    return path;
}

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

} // namespace obscura::test
