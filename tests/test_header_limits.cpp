// Windows in a header are checked before anything is allocated: against --max-pixels and
// against the size of the file, for the input and for an environment map.
#include "io/exr_file.h"
#include "support/cli_runner.h"
#include "support/exr_fixtures.h"
#include "support/scratch.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace obscura::fixtures;
using obscura::test::CliResult;

namespace {

CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

// A 16 x 12 generic frame (Z, N.X/Y/Z) whose dataWindow attribute is then rewritten in place.
std::string frameWithDataWindow(const fs::path& dir, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
    const std::string path = (dir / "in.exr").string();
    writeSimple(path, {"Z", "N.X", "N.Y", "N.Z"});
    std::ifstream in(path, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string key("dataWindow\0box2i\0", 17);
    const auto at = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    if (at == bytes.end()) throw std::runtime_error("no dataWindow attribute in " + path);
    const int32_t box[4] = {x0, y0, x1, y1};
    std::memcpy(&*(at + key.size() + 4), box, sizeof box);  // after the 4-byte attribute size
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), (std::streamsize)bytes.size());
    return path;
}

void expectOneLine(const CliResult& r, const std::vector<std::string>& parts) {
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("obscura: '", 0), 0u) << r.err;
    for (const std::string& p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << "'" << p << "' not in " << r.err;
}

const std::vector<std::string> kCamera = {"--fov-deg", "60", "--camera-to-world", "1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1"};

std::vector<std::string> run(const std::string& in, const fs::path& dir, std::vector<std::string> extra) {
    std::vector<std::string> args = {in, "-o", (dir / "out.exr").string(), "--bad-pixels", "skip"};
    args.insert(args.end(), kCamera.begin(), kCamera.end());
    args.insert(args.end(), extra.begin(), extra.end());
    return args;
}

TEST(HeaderLimits, HugeDataWindowIsRefusedByTheDefaultLimit) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, 0, 0, 99999, 99999);
    expectOneLine(cli(run(in, dir, {})), {in, "data window [0,0 - 99999,99999]", "100000 x 100000", "--max-pixels"});
    expectOneLine(cli({in, "--inspect"}), {in, "data window [0,0 - 99999,99999]"});
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

TEST(HeaderLimits, OverflowingDataWindowIsRefused) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, -2147483647, 0, 2147483646, 11);
    expectOneLine(cli(run(in, dir, {})), {in, "data window"});  // OpenEXR's own header check words it
}

// Under the limit, but 12000 scanlines of ZIP need a 6 kB chunk table the small file lacks.
TEST(HeaderLimits, WindowLargerThanTheFileCanHoldIsRefused) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, 0, 0, 15999, 11999);
    ASSERT_LT(fileSize(in), 6000u);
    expectOneLine(cli(run(in, dir, {})), {in, "data window [0,0 - 15999,11999]", "chunk table", "the file has"});
}

// 16384 x 1024 (under the limit; 64 ZIP chunks, a 512-byte table the file has) of 4 float
// channels decode to 268 MB: more than a file of a few kB holds at deflate's best (1032:1).
TEST(HeaderLimits, WindowDecodingToMoreThanTheFileCanHoldIsRefused) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, 0, 0, 16383, 1023);
    ASSERT_LT(fileSize(in), 10000u);
    expectOneLine(cli(run(in, dir, {})),
                  {in + "': data window [0,0 - 16383,1023] decodes to 268435456 bytes", "can hold", "1032:1"});
    expectOneLine(cli({in, "--inspect"}), {in + "': data window", "decodes to"});
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

// The bound never refuses a real file: zero-filled channels, each codec's best case, read.
TEST(HeaderLimits, MostCompressibleFilesOfEveryCodecAreRead) {
    const fs::path dir = obscura::test::testDir("limits");
    const auto zero = [](int, int) { return 0.0f; };
    for (int c = 0; c < Imf::NUM_COMPRESSION_METHODS; ++c)
        for (Imf::PixelType type : {Imf::HALF, Imf::FLOAT}) {
            FixturePart part;
            part.displayWindow = part.dataWindow = Imath::Box2i(Imath::V2i(0, 0), Imath::V2i(1023, 1023));
            part.compression = (Imf::Compression)c;
            for (const char* name : {"R", "G", "B", "Z"}) part.channels.push_back({name, type, 1, 1, zero});
            const std::string path = (dir / ("zero_" + std::to_string(c) + ".exr")).string();
            writeFixture(path, {part});
            EXPECT_NO_THROW(obscura::readExrInfo(path)) << "codec " << c << (type == Imf::HALF ? " half" : " float")
                                                        << ", " << fileSize(path) << " bytes";
        }
}

TEST(HeaderLimits, MaxPixelsIsTheUsersLimit) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, 0, 0, 15, 11);  // unchanged: 192 pixels
    expectOneLine(cli(run(in, dir, {"--max-pixels", "191"})), {in, "16 x 12", "limit of 191"});
    const CliResult ok = cli(run(in, dir, {"--max-pixels", "192", "--quiet"}));
    EXPECT_EQ(ok.exitCode, 0) << ok.err;
    const CliResult bad = cli(run(in, dir, {"--max-pixels", "lots"}));
    EXPECT_EQ(bad.exitCode, 2) << bad.err;
    EXPECT_NE(bad.err.find("--max-pixels expects a whole number"), std::string::npos) << bad.err;
    const CliResult zero = cli(run(in, dir, {"--max-pixels", "0"}));
    EXPECT_EQ(zero.exitCode, 2) << zero.err;
    EXPECT_NE(zero.err.find("--max-pixels must be a whole number at least 1"), std::string::npos) << zero.err;
}

TEST(HeaderLimits, EnvironmentMapAboveTheLimitIsRefused) {
    const fs::path dir = obscura::test::testDir("limits");
    const std::string in = frameWithDataWindow(dir, 0, 0, 15, 11), env = (dir / "env.exr").string();
    writeSimple(env, {"R", "G", "B"}, 32, 16);
    expectOneLine(cli(run(in, dir, {"--method", "ssdo", "--env", env, "--max-pixels", "500"})),
                  {env, "image window [0,0 - 31,15]", "32 x 16", "limit of 500"});
    EXPECT_FALSE(fs::exists(dir / "out.exr"));
}

} // namespace
