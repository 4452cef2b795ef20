#include "core/settings_schema.h"

#include "base/error.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace obscura {

const std::vector<NumberSetting>& numberSettings() {
    static const std::vector<NumberSetting> table = {
        // key, flag, ofx, min, max, minExcluded, integer, ofxMin
        {"radius", "--radius", "radius", 0, 1e9, true, false, 1e-6},
        {"blur", "--blur", "blur", 0, 64, false, true, -1},
        {"threads", "--threads", "threads", 0, 1024, false, true, 0},
        {"fov_deg", "--fov-deg", "fovDeg", 0, 179.999, true, false, 1e-3},
        {"ortho_width", "--ortho-width", "orthoWidth", 0, 1e12, true, false, 1e-9},
        {"focal_mm", "--focal-mm", "focalMm", 0, 1e6, true, false, 1e-3},
        {"aperture_mm", "--aperture-mm", "apertureMm", 0, 1e6, true, false, 1e-3},
        {"sky_depth", "--sky-depth", "skyDepth", 0, 1e38, true, false, 1e-6},
        {"env_rotate", "--env-rotate", "envRotation", -36000, 36000, false, false, -36000},
        {"env_intensity", "--env-intensity", "envIntensity", 0, 1e9, false, false, 0},
        {"preview_exposure", "--preview-exposure", nullptr, -24, 24, false, false, -24},
        {"max_pixels", "--max-pixels", nullptr, 1, 1e15, false, true, 1},
        {"depth_range", "--depth-range", nullptr, 0, 1e38, false, false, 0, 2},
    };
    return table;
}

const NumberSetting& numberSetting(const std::string& name) {
    for (const NumberSetting& s : numberSettings())
        if (name == s.key || name == s.flag || (s.ofx && name == s.ofx)) return s;
    throw Error("no numeric setting '" + name + "'");
}

std::string numberProblem(const NumberSetting& s, double v, Spelling spelling) {
    const bool whole = !s.integer || v == std::floor(v);
    if (whole && (s.minExcluded ? v > s.min : v >= s.min) && v <= s.max) return "";
    std::ostringstream m;
    m << (spelling == Spelling::Flag ? s.flag : s.key) << " must be " << (s.integer ? "a whole number " : "")
      << (s.minExcluded ? "above " : "at least ") << s.min << " and at most " << s.max << ", got "
      << std::setprecision(10) << v;  // 179.9999 is not 180
    return m.str();
}

std::string depthRangeProblem(double a, double b, Spelling spelling) {
    const NumberSetting& s = numberSetting("depth_range");
    for (double v : {a, b}) {
        const std::string problem = numberProblem(s, v, spelling);
        if (!problem.empty()) return problem;
    }
    if (a != b) return "";
    std::ostringstream m;
    m << (spelling == Spelling::Flag ? s.flag : s.key) << " needs two different ends (NEAR,FAR, or FAR,NEAR for white near), got "
      << a << " twice";
    return m.str();
}

const std::vector<NameListSetting>& nameListSettings() {
    static const std::vector<NameListSetting> table = {
        {"view", "--view", nullptr, "NAME[,NAME]",
         "multi-view (stereo) input: process only these views (default: every view with a depth)"},
    };
    return table;
}

const NameListSetting& nameListSetting(const std::string& name) {
    for (const NameListSetting& s : nameListSettings())
        if (name == s.key || name == s.flag || (s.ofx && name == s.ofx)) return s;
    throw Error("no name setting '" + name + "'");
}

std::vector<std::string> splitNameList(const std::string& text) {
    std::vector<std::string> out;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) out.push_back(item);
    if (text.empty() || text.back() == ',') out.push_back("");
    return out;
}

std::string nameListProblem(const NameListSetting& s, const std::vector<std::string>& names, Spelling spelling) {
    const std::string what = spelling == Spelling::Flag ? s.flag : s.key;
    if (names.empty()) return what + " needs at least one name";
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i].empty() || names[i].find(',') != std::string::npos)
            return what + " expects " + s.value + ": names without commas, got '" + names[i] + "'";
        if (std::find(names.begin(), names.begin() + i, names[i]) != names.begin() + i)
            return what + " names '" + names[i] + "' twice";
    }
    return "";
}

} // namespace obscura
