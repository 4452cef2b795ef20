// The numeric settings every host offers beside the methods' own parameters (core/methods.h):
// one name, range and spelling each for the CLI's flag, Python's keyword and the OpenFX
// parameter. Hosts parse the value, then ask numberProblem; none keeps a range of its own.
#pragma once
#include "core/methods.h"

#include <string>
#include <vector>

namespace obscura {

struct NumberSetting {
    const char* key;      // Python keyword ("radius")
    const char* flag;     // CLI flag ("--radius")
    const char* ofx;      // OpenFX parameter, nullptr where the node has none
    double min, max;      // the range, both ends included unless minExcluded
    bool minExcluded;
    bool integer;
    // OpenFX ranges are closed: the least value the node stores. Where min is excluded it is the
    // smallest meaningful value above it; below min it is a word's stand-in (blur -1: auto).
    double ofxMin;
    // Values the setting takes, each in the range: 2 for --depth-range NEAR,FAR (the CLI's
    // comma-separated pair, Python's tuple, the node's 2D parameter).
    int count = 1;
};

const std::vector<NumberSetting>& numberSettings();
// The entry named `name` (key, flag or OpenFX name); throws obscura::Error for none.
const NumberSetting& numberSetting(const std::string& name);
// "" when `value` is in the setting's range (and whole, for an integer setting), else the
// one-line refusal in the host's spelling: "--radius must be above 0, got 0".
std::string numberProblem(const NumberSetting& s, double value, Spelling spelling);
// "" when --depth-range A,B is usable: each end in the table's range, and A != B (A > B is the
// reversed form, white near); else the one-line refusal in the host's spelling.
std::string depthRangeProblem(double a, double b, Spelling spelling);

// Settings whose values are names, read alike by every method and offered by every host that
// has the thing they name: the CLI's flag, Python's keyword, the OpenFX parameter (nullptr where
// the host supplies it: the node gets its views from the host).
struct NameListSetting {
    const char* key;    // Python keyword ("view"): a name or a list of names
    const char* flag;   // CLI flag ("--view"): NAME[,NAME...]
    const char* ofx;
    const char* value;  // the CLI's placeholder
    const char* help;
};
const std::vector<NameListSetting>& nameListSettings();
// The entry named `name` (key, flag or OpenFX name); throws obscura::Error for none.
const NameListSetting& nameListSetting(const std::string& name);
// "a,b" -> {"a", "b"}.
std::vector<std::string> splitNameList(const std::string& commaSeparated);
// "" when every name is non-empty, has no comma and is given once; else the one-line refusal.
std::string nameListProblem(const NameListSetting& s, const std::vector<std::string>& names, Spelling spelling);

} // namespace obscura
