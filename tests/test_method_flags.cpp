// Every flag does what it says or is refused (issue 31), generated from the method table
// (core/methods.h): for each method, every parameter and option that only other methods read
// is a usage error naming a method that reads it, every one the method reads is accepted, and
// an output it cannot write is refused. Python and the OpenFX node are held to the same table
// in tests/python/test_method_keywords.py and test_ofx.cpp.
#include "core/methods.h"
#include "support/cli_runner.h"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>

using namespace obscura;
using obscura::test::CliResult;
using obscura::test::outcome;

namespace {

const std::string kRoom = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";
// Where a run that was wrongly taken would write: never the working directory.
const std::string kNever = std::string(OBSCURA_TEST_TMP) + "/never.exr";

CliResult cli(const std::vector<std::string>& args) { return obscura::test::runProgram(OBSCURA_CLI_PATH, args); }

// A value each option's flag accepts; an option added to the table without one fails below.
const std::map<std::string, std::string> kOptionValues = {
    {"--weighting", "cosine"}, {"--falloff", "none"}, {"--bounce", ""}, {"--bounce-source", "beauty"},
    {"--env", kRoom}, {"--env-rotate", "10"}, {"--env-intensity", "2"}, {"--env-colorspace", "ACEScg"},
    {"--sky", "1,1,1"}, {"--light", "0,1,0,1,1,1"}, {"--up", "z"}, {"--colorspace", "ACEScg"},
    {"--times-albedo", ""}, {"--relit-direct", ""},
};

// The flag with a value it accepts, as arguments.
std::vector<std::string> flagWithValue(const std::string& flag, const std::string& value) {
    if (value.empty()) return {flag};
    return {flag, value};
}

struct Setting {
    std::string flag, value;
    std::vector<std::string> readers;
};

std::vector<Setting> everySetting() {
    std::vector<Setting> all;
    for (const MethodParam* p : allMethodParams()) {
        std::string value = !p->value ? "" : p->named.empty() ? std::to_string((int)p->min) : p->named.back().word;
        all.push_back({p->flag, value, methodsReading(p->flag)});
    }
    for (const MethodOption& o : methodOptions()) {
        const auto v = kOptionValues.find(o.flag);
        EXPECT_NE(v, kOptionValues.end()) << o.flag << " has no sample value in this test";
        if (v != kOptionValues.end()) all.push_back({o.flag, v->second, methodsReading(o.flag)});
    }
    return all;
}

bool reads(const Setting& s, const std::string& method) {
    return std::find(s.readers.begin(), s.readers.end(), method) != s.readers.end();
}

} // namespace

TEST(MethodFlags, EveryFlagOfAnotherMethodIsRefused) {
    int refused = 0;
    for (const MethodInfo& m : methods())
        for (const Setting& s : everySetting()) {
            if (reads(s, m.name)) continue;
            std::vector<std::string> args = {kRoom, "-o", kNever, "--method", m.name};
            for (const std::string& a : flagWithValue(s.flag, s.value)) args.push_back(a);
            const CliResult r = cli(args);
            SCOPED_TRACE(std::string(m.name) + " " + s.flag);
            EXPECT_EQ(r.exitCode, 2) << outcome(r);
            EXPECT_NE(r.err.find(s.flag + " is read by --method " + s.readers.front()), std::string::npos) << outcome(r);
            EXPECT_NE(r.err.find("not by --method " + std::string(m.name)), std::string::npos) << outcome(r);
            ++refused;
        }
    EXPECT_GT(refused, 30);  // the table has settings of several methods
}

// The same flags where the method reads them are taken (--inspect parses, plans and writes nothing).
TEST(MethodFlags, EveryFlagOfTheMethodIsAccepted) {
    for (const MethodInfo& m : methods())
        for (const Setting& s : everySetting()) {
            if (!reads(s, m.name)) continue;
            std::vector<std::string> args = {kRoom, "--inspect", "--method", m.name};
            for (const std::string& a : flagWithValue(s.flag, s.value)) args.push_back(a);
            const CliResult r = cli(args);
            EXPECT_EQ(r.exitCode, 0) << m.name << " " << s.flag << "\n" << outcome(r);
        }
}

TEST(MethodFlags, OutputsTheMethodCannotWriteAreRefused) {
    for (const MethodInfo& m : methods())
        for (const char* output : {"do", "gi", "relit"}) {
            // --inspect: a run that takes the request plans it and writes nothing.
            const std::vector<std::string> args = {kRoom, "--inspect", "--method", m.name, "--out-layer",
                                                   std::string(output) + "=X"};
            const CliResult r = cli(args);
            const bool writes = methodOutputs(m.name, output);
            if (writes) {
                EXPECT_EQ(r.exitCode, 0) << m.name << " " << output << "\n" << outcome(r);
                continue;
            }
            EXPECT_EQ(r.exitCode, 2) << m.name << " " << output << "\n" << outcome(r);
            // The refusal names every method that writes it (ssdo; gi and relit hbao's bounce too).
            EXPECT_NE(r.err.find("the " + std::string(output) + " output is written by --method "), std::string::npos)
                << outcome(r);
            EXPECT_NE(r.err.find("only, not by --method " + std::string(m.name)), std::string::npos) << outcome(r);
            for (const MethodInfo& writer : methods()) {
                if (methodOutputs(writer.name, output)) {
                    EXPECT_NE(r.err.find("--method " + std::string(writer.name)), std::string::npos) << outcome(r);
                }
            }
        }
}

TEST(MethodFlags, NumbersAreRangeChecked) {
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"--threads", "-1"}, {"--blur", "-1"}, {"--blur", "65"}, {"--radius", "0"},
          {"--radius", "-2"}, {"--fov-deg", "0"}, {"--fov-deg", "180"}, {"--ortho-width", "0"}, {"--sky-depth", "-1"},
          {"--method", "ssdo", "--env-intensity", "-1"}, {"--method", "ssdo", "--sky", "1,-1,1"},
          {"--method", "ssdo", "--light", "0,0,0,1,1,1"}, {"--method", "ssdo", "--light", "0,1,0,-1,1,1"}}) {
        std::vector<std::string> args = {kRoom, "-o", kNever};
        args.insert(args.end(), bad.begin(), bad.end());
        const CliResult r = cli(args);
        EXPECT_EQ(r.exitCode, 2) << bad.back() << "\n" << outcome(r);
    }
}
