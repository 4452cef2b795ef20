#include "write_guard.h"

#include "io/camera_sources.h"
#include "io/colour.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <unordered_map>

namespace obscura {

namespace fs = std::filesystem;

namespace {

struct NamedPath {
    std::string role, path;
    bool written;
};

// What a role is called on the host's side of the call.
std::string roleName(const char* flag, const char* key, Spelling spelling) {
    return spelling == Spelling::Flag ? flag : key;
}

// A file's identity: its device and inode when it exists (stat follows every link, so a
// symlink and a hard link meet their target), else its absolute path with the links of the
// directories above it resolved (two spellings of one file that does not exist yet).
std::string identity(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0)
        return "inode " + std::to_string((unsigned long long)st.st_dev) + ":" + std::to_string((unsigned long long)st.st_ino);
    // A symlink to a file not written yet: the file it will reach.
    std::error_code ec;
    fs::path p = fs::absolute(path, ec);
    for (int hops = 0; hops < 40 && fs::is_symlink(p, ec); ++hops) {
        const fs::path target = fs::read_symlink(p, ec);
        p = target.is_absolute() ? target : p.parent_path() / target;
    }
    const fs::path canonical = fs::weakly_canonical(p, ec);
    return "path " + (ec ? p.lexically_normal().string() : canonical.lexically_normal().string());
}

std::string lower(std::string s) {
    for (char& c : s) c = (char)std::tolower((unsigned char)c);
    return s;
}

void requireExtension(const std::string& role, const std::string& path, const char* extension, const char* what) {
    if (lower(fs::path(path).extension().string()) != extension)
        throw UsageError(role + " '" + path + "': " + what + "; name it " + extension);
}

// The files one frame reads and writes, each under the role that names it to the user.
void listFrame(const FrameFiles& f, Spelling s, std::vector<NamedPath>& out) {
    const FrameJob& job = *f.job;
    const bool deep = !job.deepInput.empty();
    auto read = [&](std::string role, const std::string& path) {
        if (!path.empty()) out.push_back({std::move(role), path, false});
    };
    auto write = [&](std::string role, const std::string& path) {
        if (!path.empty()) out.push_back({std::move(role), path, true});
    };
    read(deep ? roleName("--flat", "flat", s) : "the input", job.input);
    if (deep) read("the input", job.deepInput);
    for (size_t i = 1; i < job.deepElements.size(); ++i) read("the deep element", job.deepElements[i]);
    if (!job.camera.sidecarPath.empty()) read(roleName("--camera", "camera", s), job.camera.sidecarPath);
    else read("the camera sidecar", findSidecar(job.input));
    read(roleName("--env", "env", s), job.envPath);
    write(roleName("-o", "out", s), job.output);
    write(roleName("--report", "report", s), f.report);
    write(roleName("--preview", "preview", s), job.previewPath);
}

std::string described(const NamedPath& p) { return p.role + (p.role == "the input" ? "" : " '" + p.path + "'"); }

} // namespace

void checkFrameFiles(const std::vector<FrameFiles>& frames, Spelling spelling) {
    std::vector<NamedPath> paths;
    bool inPlace = false;
    for (const FrameFiles& f : frames) {
        listFrame(f, spelling, paths);
        inPlace = inPlace || f.job->inPlace;
    }
    try {  // the config is read by every run that tags its output; a missing one fails later, not here
        paths.push_back({"the OpenColorIO config", colourConfigPath(), false});
    } catch (const Error&) {
    }
    // The first holder of each identity; reads come first, so a collision names the read role.
    std::stable_partition(paths.begin(), paths.end(), [](const NamedPath& p) { return !p.written; });
    std::unordered_map<std::string, const NamedPath*> seen;
    const std::string output = roleName("-o", "out", spelling);
    for (const NamedPath& p : paths) {
        const auto [at, fresh] = seen.emplace(identity(p.path), &p);
        if (fresh) continue;
        const NamedPath& first = *at->second;
        if (!p.written) continue;  // one file read in two roles (a sidecar given twice) is fine
        if (inPlace && p.role == output && first.role == "the input") continue;
        const bool sameRole = first.role == p.role;
        const bool replacesInput = p.role == output && first.role == "the input";
        throw UsageError(described(p) + (sameRole ? " is written for two frames" : " is the same file as " + described(first)) +
                         (replacesInput ? " (only --in-place replaces the input)" : "") + "; nothing written");
    }
    // After the collisions, so `-o in.json` names the sidecar it would have replaced.
    const std::string preview = roleName("--preview", "preview", spelling);
    for (const NamedPath& p : paths) {
        if (!p.written) continue;
        if (p.role == output) requireExtension(p.role, p.path, ".exr", "the output is an OpenEXR file");
        else if (p.role == preview) requireExtension(p.role, p.path, ".png", "the preview is a PNG");
        else requireExtension(p.role, p.path, ".json", "the report is JSON");
    }
}

std::string besideOutput(const std::string& spec, const std::string& output, const char* extension) {
    if (spec.empty()) return spec;
    std::error_code ec;
    const bool directory = spec.back() == '/' || fs::is_directory(spec, ec);
    if (!directory) return spec;
    return (fs::path(spec) / fs::path(output).filename().replace_extension(extension)).string();
}

} // namespace obscura
