#include "io/source_files.h"

#include "io/frame_job.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>

namespace obscura {

std::vector<std::string> filesReadBy(const FrameJob& job) {
    std::vector<std::string> files = {job.input, job.deepInput, job.camera.sidecarPath, job.envPath};
    files.insert(files.end(), job.deepElements.begin(), job.deepElements.end());
    if (job.camera.sidecarPath.empty()) files.push_back(findSidecar(job.input));
    std::error_code ec;
    // In place, the input (a deep element's too) is what the run writes: not a source of the output.
    files.erase(std::remove_if(files.begin(), files.end(),
                               [&](const std::string& f) {
                                   return f.empty() || (job.inPlace && f == job.input) || !std::filesystem::exists(f, ec);
                               }),
                files.end());
    std::sort(files.begin(), files.end());  // deep elements: the input is the first of them too
    files.erase(std::unique(files.begin(), files.end()), files.end());
    return files;
}

std::string recordedPath(const std::string& path) {
    return std::filesystem::absolute(path).lexically_normal().string();
}

std::vector<FileStamp> stampsOf(const std::vector<std::string>& files) {
    std::vector<FileStamp> stamps;
    for (const std::string& f : files) {
        struct stat st {};
        if (::stat(f.c_str(), &st) != 0) continue;
        stamps.push_back({recordedPath(f), (long long)st.st_size,
                          (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec});
    }
    return stamps;
}

} // namespace obscura
