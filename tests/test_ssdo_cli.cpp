// SSDO and frame sequences through the obscura command: what runs is only what was asked
// for, the layers land where they should, and sequences resume.
#include "support/cli_runner.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace fs = std::filesystem;
using obscura::test::CliResult;

namespace {

const fs::path kRoom = fs::path(OBSCURA_TEST_DATA_DIR) / "room.exr";

class SsdoCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::path(OBSCURA_TEST_TMP) / ("ssdo-cli-" + std::to_string(::getpid()) + "-" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override { fs::remove_all(dir); }

    CliResult run(std::vector<std::string> args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

    nlohmann::json report(const fs::path& p) {
        std::ifstream f(p);
        return nlohmann::json::parse(f);
    }

    fs::path dir;
};

std::vector<std::string> fast = {"--radius", "1", "--samples", "16", "--interleave", "2", "--quiet"};

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

bool has(const nlohmann::json& list, const std::string& prefix) {
    for (const auto& item : list)
        if (item.get<std::string>().rfind(prefix, 0) == 0) return true;
    return false;
}

} // namespace

// AO alone runs HBAO and writes one channel; an --env given to it is refused, not loaded.
TEST_F(SsdoCli, AoAloneRunsNothingElse) {
    const fs::path out = dir / "ao.exr", rep = dir / "ao.json";
    const CliResult r = run({kRoom.string(), "-o", out.string(), "--radius", "1", "--report", rep.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = report(rep);
    EXPECT_EQ(j["plan"], nlohmann::json::array({"hbao"}));
    EXPECT_EQ(j["written"], nlohmann::json::array({"obscura.AO.Y"}));
    // A map only ssdo lights with is refused, not ignored: the run would not do what it says.
    const fs::path out2 = dir / "ao2.exr";
    const CliResult e = run({kRoom.string(), "-o", out2.string(), "--env", "/nonexistent.hdr"});
    EXPECT_EQ(e.exitCode, 2) << e.err;
    EXPECT_NE(e.err.find("--env is read by --method ssdo only"), std::string::npos) << e.err;
    EXPECT_FALSE(fs::exists(out2));
}

// DO without GI: no bounce pass, no GI layer; with --bounce the GI layer appears and the
// plan says where the bounce came from.
TEST_F(SsdoCli, BounceRunsOnlyWhenAskedFor) {
    const fs::path out = dir / "do.exr", rep = dir / "do.json";
    CliResult r = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--report", rep.string()}, fast));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    auto j = report(rep);
    EXPECT_TRUE(has(j["plan"], "ssdo (no bounce)"));
    EXPECT_FALSE(has(j["written"], "obscura.GI"));
    EXPECT_TRUE(has(j["written"], "obscura.DO.R"));

    r = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--bounce", "--out-layer", "relit=Relit",
                 "--report", rep.string()},
                fast));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    j = report(rep);
    EXPECT_TRUE(has(j["plan"], "ssdo + bounce from direct-diffuse"));
    for (const char* c : {"obscura.GI.R", "obscura.GI.B", "Relit.G", "obscura.AO.Y"}) EXPECT_TRUE(has(j["written"], c)) << c;
}

// hbao's bounce (kernels/hbao_gi.glsl) writes GI and relit as ssdo's does, and no DO: it has none.
TEST_F(SsdoCli, HbaoBounceWritesGiAndRelit) {
    const fs::path out = dir / "hbao_gi.exr", rep = dir / "hbao_gi.json";
    CliResult r = run({kRoom.string(), "-o", out.string(), "--method", "hbao", "--bounce", "--radius", "1", "--quiet",
                       "--report", rep.string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const auto j = report(rep);
    EXPECT_TRUE(has(j["plan"], "hbao + bounce from direct-diffuse"));
    for (const char* c : {"obscura.AO.Y", "obscura.GI.R", "obscura.GI.B", "obscura.relit.G"})
        EXPECT_TRUE(has(j["written"], c)) << c;
    EXPECT_FALSE(has(j["written"], "obscura.DO"));
    const fs::path out2 = dir / "hbao_do.exr";
    r = run({kRoom.string(), "-o", out2.string(), "--method", "hbao", "--bounce", "--out-layer", "do=DO", "--quiet"});
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("written by --method ssdo only"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out2));
}

// An environment map is read (and listed in the plan) only for ssdo.
TEST_F(SsdoCli, EnvironmentLoadsOnlyForSsdo) {
    const fs::path env = dir / "env.exr", out = dir / "env_out.exr", rep = dir / "env.json";
    // A 16x8 lat-long map, via the tool itself: oiiotool is in the project's packages.
    ASSERT_EQ(std::system(("oiiotool --pattern constant:color=0.5,0.6,0.7 16x8 3 -d float -o " + env.string()).c_str()), 0);
    const CliResult r = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--env", env.string(),
                                 "--env-rotate", "90", "--report", rep.string()},
                                fast));
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_TRUE(has(report(rep)["plan"], "environment"));
    const CliResult bad = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--env", "/nope.exr"}, fast));
    EXPECT_EQ(bad.exitCode, 1);
    EXPECT_NE(bad.err.find("environment map"), std::string::npos) << bad.err;
    // An unknown space for the map names the map's flag, not the colour passes'.
    const CliResult space = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--env", env.string(),
                                     "--env-colorspace", "nosuch"},
                                    fast));
    EXPECT_EQ(space.exitCode, 1);
    EXPECT_NE(space.err.find("'nosuch' for --env-colorspace"), std::string::npos) << space.err;
}

TEST_F(SsdoCli, BadSsdoFlagsAreUsageErrors) {
    const fs::path out = dir / "x.exr";
    EXPECT_EQ(run({kRoom.string(), "-o", out.string(), "--light", "1,2,3,4,5"}).exitCode, 2);
    EXPECT_EQ(run({kRoom.string(), "-o", out.string(), "--sky", "a,b,c"}).exitCode, 2);
    EXPECT_EQ(run({kRoom.string(), "-o", out.string(), "--up", "x"}).exitCode, 2);
    EXPECT_EQ(run({kRoom.string(), "-o", out.string(), "--out-layer", "bent=Z"}).exitCode, 2);
    const CliResult r = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--bounce",
                                 "--bounce-source", "NoSuchLayer"},
                                fast));
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("NoSuchLayer"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // An unknown colour space for the colour passes: one line naming it, nothing written.
    const CliResult c = run(cat({kRoom.string(), "-o", out.string(), "--method", "ssdo", "--bounce", "--colorspace",
                                 "nosuch"},
                                fast));
    EXPECT_EQ(c.exitCode, 1);
    EXPECT_NE(c.err.find("'nosuch'"), std::string::npos) << c.err;
    EXPECT_EQ(std::count(c.err.begin(), c.err.end(), '\n'), 1) << c.err;
    EXPECT_FALSE(fs::exists(out));
}

// A sequence: every frame found is processed; --resume leaves finished frames alone;
// --frames picks a subset; a missing frame stops the run with its number.
TEST_F(SsdoCli, SequencesResumeAndSelectFrames) {
    for (int f = 1; f <= 3; ++f) {
        char name[32];
        std::snprintf(name, sizeof name, "shot.%04d", f);
        fs::copy_file(kRoom, dir / (std::string(name) + ".exr"));
        fs::copy_file(fs::path(OBSCURA_TEST_DATA_DIR) / "room.json", dir / (std::string(name) + ".json"));
    }
    const std::string in = (dir / "shot.####.exr").string(), out = (dir / "ao.%04d.exr").string();
    CliResult r = run({in, "-o", out, "--radius", "1", "--directions", "2", "--steps", "2"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("3/3 frames"), std::string::npos) << r.err;
    for (int f = 1; f <= 3; ++f) EXPECT_TRUE(fs::exists(dir / ("ao.000" + std::to_string(f) + ".exr")));
    const auto stamp = fs::last_write_time(dir / "ao.0002.exr");

    r = run({in, "-o", out, "--radius", "1", "--directions", "2", "--steps", "2", "--resume"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("(3 skipped)"), std::string::npos) << r.err;
    EXPECT_EQ(fs::last_write_time(dir / "ao.0002.exr"), stamp);

    fs::remove(dir / "ao.0003.exr");
    r = run({in, "-o", out, "--radius", "1", "--directions", "2", "--steps", "2", "--frames", "2-3", "--resume"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("2/2 frames (1 skipped)"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "ao.0003.exr"));

    r = run({in, "-o", out, "--radius", "1", "--frames", "3-4", "--quiet"});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("frame 4:"), std::string::npos) << r.err;
    EXPECT_EQ(run({in, "-o", (dir / "single.exr").string()}).exitCode, 2) << "a sequence needs an output pattern";
}
