#include "core/settings_schema.h"

#include "base/error.h"

#include <cmath>
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
      << (s.minExcluded ? "above " : "at least ") << s.min << " and at most " << s.max << ", got " << v;
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

} // namespace obscura
