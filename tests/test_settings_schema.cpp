// One settings schema for every host (issue 29): each shared numeric setting of
// core/settings_schema.h is refused by the CLI just outside its range and taken at its ends,
// and the OpenFX node declares the same range (tests/python/test_settings_schema.py holds
// Python to it). Generated from the table, so a new setting is checked without a new test.
#include "core/settings_schema.h"
#include "ofx_host/ofx_host.h"
#include "support/cli_runner.h"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

using namespace obscura;
using obscura::test::CliResult;
using namespace obscura::ofxhost;

namespace {

const std::string kRoom = std::string(OBSCURA_TEST_DATA_DIR) + "/room.exr";

std::string text(const NumberSetting& n, double v) {
    if (n.integer) return std::to_string((long long)v);
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

// --inspect with the flag (and what it needs to be read: its method, a preview to expose, the
// depth encoding it is for, the other half of the film back). A setting of two values gets
// `value` first and the other end of the range second (a range's two ends must differ).
CliResult inspectWith(const NumberSetting& n, double value) {
    const double other = value == n.max ? n.min + (n.minExcluded ? 1 : 0) : n.max;
    const std::string values = n.count == 2 ? text(n, value) + "," + text(n, other) : text(n, value);
    std::vector<std::string> args = {kRoom, "--inspect", n.flag, values};
    if (std::string(n.flag) == "--depth-range") args.insert(args.end(), {"--depth", "normalized"});
    // The film back's two halves go together.
    if (std::string(n.flag) == "--focal-mm") args.insert(args.end(), {"--aperture-mm", "36"});
    if (std::string(n.flag) == "--aperture-mm") args.insert(args.end(), {"--focal-mm", "50"});
    const std::vector<std::string> readers = methodsReading(n.flag);
    if (!readers.empty()) args.insert(args.end(), {"--method", readers.front()});
    if (std::string(n.flag) == "--preview-exposure") args.insert(args.end(), {"--preview", "unused.png"});
    return obscura::test::runProgram(OBSCURA_CLI_PATH, args);
}

} // namespace

TEST(SettingsSchema, TheCliTakesTheRangeAndRefusesOutsideIt) {
    for (const NumberSetting& n : numberSettings()) {
        SCOPED_TRACE(n.flag);
        const double inside = n.minExcluded ? (n.integer ? n.min + 1 : n.min + 1e-3) : n.min;
        // Taken: no usage error (a 1-pixel --max-pixels then refuses the file itself, exit 1).
        const CliResult low = inspectWith(n, inside);
        EXPECT_NE(low.exitCode, 2) << low.err;
        const CliResult high = inspectWith(n, n.max);
        EXPECT_EQ(high.exitCode, 0) << high.err;
        const double below = n.minExcluded ? n.min : n.min - 1;
        const CliResult under = inspectWith(n, below);
        EXPECT_EQ(under.exitCode, 2) << under.err;
        EXPECT_NE(under.err.find(numberProblem(n, below, Spelling::Flag)), std::string::npos) << under.err;
        const CliResult over = inspectWith(n, n.integer ? n.max + 1 : n.max * 2 + 1);
        EXPECT_EQ(over.exitCode, 2) << over.err;
    }
}

TEST(SettingsSchema, TheNodeDeclaresTheSameRanges) {
    Host host(OBSCURA_OFX_BUNDLE);
    ASSERT_EQ(host.load(), kOfxStatOK);
    ASSERT_EQ(host.describe(), kOfxStatOK);
    int checked = 0;
    for (const NumberSetting& n : numberSettings()) {
        if (!n.ofx) continue;
        const Param* p = host.descriptor().params.find(n.ofx);
        ASSERT_TRUE(p) << n.ofx;
        const bool integer = p->type == kOfxParamTypeInteger;
        EXPECT_EQ(integer, n.integer) << n.ofx;
        const double lo = integer ? p->props.integer(kOfxParamPropMin) : p->props.doubles(kOfxParamPropMin).at(0);
        const double hi = integer ? p->props.integer(kOfxParamPropMax) : p->props.doubles(kOfxParamPropMax).at(0);
        EXPECT_EQ(lo, n.ofxMin) << n.ofx;
        EXPECT_EQ(hi, n.max) << n.ofx;
        ++checked;
    }
    EXPECT_GE(checked, 8);
}
