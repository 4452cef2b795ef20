#include "io/atomic_files.h"

#include "base/error.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace obscura {

namespace fs = std::filesystem;

void requireOutputDirectory(const std::string& path) {
    const fs::path dir = fs::path(path).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw FileError(path, "cannot write: directory '" + dir.string() + "' does not exist");
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    auto fail = [&] {
        const int err = errno;
        std::remove(tmp.c_str());
        return FileError(path, std::string("cannot write: ") + std::strerror(err));
    };
    {
        std::ofstream f(tmp, std::ios::binary);
        f << text << "\n";
        if (!f.good()) throw fail();
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) throw fail();
}

std::vector<std::string> atomicWriteTemps(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path);
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string prefix = p.filename().string() + ".tmp-";
    std::vector<std::string> found;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
            name.find_first_not_of("0123456789", prefix.size()) == std::string::npos)
            found.push_back((p.parent_path() / name).string());
    }
    std::sort(found.begin(), found.end());
    return found;
}

int removeStaleTemps(const std::string& path) {
    int removed = 0;
    for (const std::string& tmp : atomicWriteTemps(path)) {
        const long pid = std::atol(tmp.c_str() + tmp.rfind('-') + 1);
        // kill(pid, 0) probes without signalling: ESRCH means no such process here.
        if (pid > 0 && pid != (long)::getpid() && ::kill((pid_t)pid, 0) == 0) continue;
        if (pid > 0 && pid != (long)::getpid() && errno != ESRCH) continue;
        if (std::remove(tmp.c_str()) == 0) ++removed;
    }
    return removed;
}

} // namespace obscura
