// What the command line's end-to-end tests (test_cli*.cpp) share: running the built obscura,
// checking a failed or successful run, reading an output back with OpenEXR directly, and the
// corner scene written as an EXR under a renderer's channel names.
// testDir() and cli() are inline: OBSCURA_TEST_TMP and OBSCURA_CLI_PATH are the including test
// executable's definitions (tests/support's own sources have neither).
#pragma once
#include "base/image.h"
#include "core/camera.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scenes.h"
#ifdef OBSCURA_CLI_PATH
#include "support/scratch.h"
#endif

#include <OpenEXR/ImfPixelType.h>
#include <Imath/ImathBox.h>
#include <Imath/half.h>
#include <glm/glm.hpp>

#include <array>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <vector>

namespace obscura::test {

// ---------------------------------------------------------------------------
// Scratch space and running the CLI
// ---------------------------------------------------------------------------

#ifdef OBSCURA_CLI_PATH
inline std::filesystem::path testDir() { return obscura::test::testDir("cli"); }

inline CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }
#endif

std::string describe(const CliResult& r);

bool contains(const std::string& s, const std::string& part);

std::vector<std::string> tempLeftovers(const std::filesystem::path& dir);

// A failed run: the exit code, exactly one stderr line "obscura: ..." naming every `mentions`,
// no output file and no temp file left in the output's directory.
void expectCleanFailure(const CliResult& r, int exitCode, const std::filesystem::path& output,
                        std::initializer_list<std::string> mentions = {});

void expectSuccess(const CliResult& r, const std::filesystem::path& output);

std::string fileBytes(const std::filesystem::path& p);

// ---------------------------------------------------------------------------
// Reading an EXR back with OpenEXR directly (not through obscura's reader)
// ---------------------------------------------------------------------------

struct ChannelData {
    Imf::PixelType type = Imf::FLOAT;
    int width = 0, height = 0;
    std::vector<char> bytes;  // tightly packed, native type

    float at(size_t i) const {
        if (type == Imf::HALF) {
            half h;
            std::memcpy(&h, bytes.data() + i * 2, 2);
            return float(h);
        }
        if (type == Imf::UINT) {
            unsigned u;
            std::memcpy(&u, bytes.data() + i * 4, 4);
            return float(u);
        }
        float f;
        std::memcpy(&f, bytes.data() + i * 4, 4);
        return f;
    }
    std::vector<float> floats() const {
        std::vector<float> v((size_t)width * height);
        for (size_t i = 0; i < v.size(); ++i) v[i] = at(i);
        return v;
    }
};

struct FileData {
    std::vector<Imath::Box2i> dataWindows, displayWindows;
    std::vector<bool> tiled;
    std::map<std::string, ChannelData> channels;  // "part:name"

    const ChannelData* find(int part, const std::string& name) const {
        auto it = channels.find(std::to_string(part) + ":" + name);
        return it == channels.end() ? nullptr : &it->second;
    }
};

FileData readAll(const std::string& path);

// Every channel of `in` is in `out`, same part, type and bytes.
void expectChannelsKept(const FileData& in, const FileData& out);

// ---------------------------------------------------------------------------
// Synthetic frames: an analytic scene written under a renderer's channel names
// ---------------------------------------------------------------------------

inline constexpr double kFovDeg = 70.0;

// Floor, back wall, left wall and a box: corners to occlude, sky above the wall.
SceneBuffers cornerScene(Box2i display, Box2i data);
SceneBuffers cornerScene(int w, int h);

// Row-major, OpenGL convention, 17 significant digits (round-trips exactly).
std::array<double, 16> rowMajor(const glm::dmat4& m);
std::vector<std::string> cameraFlags(const SceneBuffers& s);

// The planes as a file holds them.
struct Planes {
    Box2i display, data;
    Image depth, normal, position;
};

Planes planesOf(const SceneBuffers& s);

Imath::Box2i toImath(const Box2i& b);

struct Naming {
    std::string depth;                         // full channel name
    std::array<std::string, 3> normal;         // full channel names, x, y, z
    std::array<std::string, 3> position;       // empty: no position pass
    std::vector<std::string> beauty;           // pattern-filled pass-through channels
    std::map<std::string, std::string> attrs;  // header hints
};

fixtures::FixturePart makePart(const Planes& p, const Naming& n, Imf::PixelType type = Imf::FLOAT);

extern const Naming kGeneric;

// Writes `planes` under generic names (float) and returns the path.
std::string writeGeneric(const std::filesystem::path& dir, const std::string& name, const Planes& planes);

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b);

} // namespace obscura::test
