#include "io/sequence.h"

#include "base/error.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace obscura {

namespace {

// The placeholder: [begin, end) in `path` and its zero-padding width.
struct Placeholder {
    size_t begin = std::string::npos, end = std::string::npos;
    int width = 1;
};

Placeholder findPlaceholder(const std::string& path) {
    Placeholder p;
    const size_t name = path.find_last_of('/') == std::string::npos ? 0 : path.find_last_of('/') + 1;
    const size_t hash = path.find('#', name);
    if (hash != std::string::npos) {
        p.begin = hash;
        p.end = path.find_first_not_of('#', hash);
        if (p.end == std::string::npos) p.end = path.size();
        p.width = (int)(p.end - p.begin);
        return p;
    }
    for (size_t i = path.find('%', name); i != std::string::npos; i = path.find('%', i + 1)) {
        size_t j = i + 1;
        while (j < path.size() && std::isdigit((unsigned char)path[j])) ++j;
        if (j < path.size() && path[j] == 'd') {
            p.begin = i;
            p.end = j + 1;
            p.width = j > i + 1 ? std::max(1, std::stoi(path.substr(i + 1, j - i - 1))) : 1;
            return p;
        }
    }
    return p;
}

int toInt(const std::string& s, const std::string& spec) {
    size_t used = 0;
    int v = 0;
    try {
        v = std::stoi(s, &used);
    } catch (...) {
        used = 0;
    }
    if (s.empty() || used != s.size()) throw Error("--frames: cannot read '" + spec + "' (e.g. 1-100, 1-100x2, 1,5,9-12)");
    return v;
}

} // namespace

bool isFramePattern(const std::string& path) { return findPlaceholder(path).begin != std::string::npos; }

std::string framePath(const std::string& pattern, int frame) {
    const Placeholder p = findPlaceholder(pattern);
    if (p.begin == std::string::npos) return pattern;
    char digits[32];
    std::snprintf(digits, sizeof digits, frame < 0 ? "-%0*d" : "%0*d", p.width, frame < 0 ? -frame : frame);
    return pattern.substr(0, p.begin) + digits + pattern.substr(p.end);
}

std::vector<int> parseFrames(const std::string& spec) {
    std::vector<int> frames;
    std::stringstream ss(spec);
    std::string item;
    while (std::getline(ss, item, ',')) {
        const size_t x = item.find('x');
        const int step = x == std::string::npos ? 1 : toInt(item.substr(x + 1), spec);
        const std::string range = item.substr(0, x);
        const size_t dash = range.find('-', 1);  // a leading '-' is a negative frame
        const int first = toInt(range.substr(0, dash), spec);
        const int last = dash == std::string::npos ? first : toInt(range.substr(dash + 1), spec);
        if (step < 1 || last < first) throw Error("--frames: '" + item + "' is an empty range");
        // A bound on the list, so that a typo (1-2000000000) is an error, not the whole memory.
        constexpr long long kMostFrames = 10000000;
        if ((long long)frames.size() + ((long long)last - first) / step + 1 > kMostFrames)
            throw Error("--frames: '" + spec + "' is more than 10,000,000 frames");
        for (long long f = first; f <= last; f += step) frames.push_back((int)f);
    }
    if (frames.empty()) throw Error("--frames: no frames in '" + spec + "'");
    return frames;
}

std::vector<int> existingFrames(const std::string& pattern) {
    namespace fs = std::filesystem;
    const Placeholder p = findPlaceholder(pattern);
    if (p.begin == std::string::npos) return {};
    const fs::path dir = fs::path(pattern).parent_path();
    const std::string prefix = fs::path(pattern.substr(0, p.begin)).filename().string();
    const std::string suffix = pattern.substr(p.end);
    std::vector<int> frames;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
            name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
            continue;
        const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
        if (digits.find_first_not_of("0123456789-") != std::string::npos) continue;
        try {
            const int f = std::stoi(digits);
            if (framePath(pattern, f) == (dir.empty() ? name : (dir / name).string())) frames.push_back(f);
        } catch (...) {
        }
    }
    std::sort(frames.begin(), frames.end());
    return frames;
}

std::vector<std::vector<int>> chunkFrames(const std::vector<int>& frames, int size) {
    if (size < 1) throw Error("chunk size must be at least 1, got " + std::to_string(size));
    std::vector<std::vector<int>> chunks;
    for (size_t i = 0; i < frames.size(); i += (size_t)size)
        chunks.emplace_back(frames.begin() + i, frames.begin() + std::min(frames.size(), i + (size_t)size));
    return chunks;
}

std::string frameSpec(const std::vector<int>& frames) {
    std::string spec;
    for (size_t i = 0; i < frames.size();) {
        // The longest run from i with one positive step; runs of two stay two items ("1,3").
        size_t j = i + 1;
        const long step = j < frames.size() ? (long)frames[j] - frames[i] : 0;
        while (step > 0 && j < frames.size() && (long)frames[j] - frames[j - 1] == step) ++j;
        if (!spec.empty()) spec += ',';
        if (j - i >= 3 || (j - i == 2 && step == 1)) {
            spec += std::to_string(frames[i]) + "-" + std::to_string(frames[j - 1]);
            if (step > 1) spec += "x" + std::to_string(step);
            i = j;
        } else {
            spec += std::to_string(frames[i]);
            ++i;
        }
    }
    return spec;
}

} // namespace obscura
