#include "io/atomic_files.h"

#include "base/error.h"

#include <signal.h>
#include <unistd.h>

#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace obscura {

namespace fs = std::filesystem;

namespace {
void requireDirectoryOf(const std::string& path, const std::string& target) {
    const fs::path dir = fs::path(target).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec))
        throw FileError(path, "cannot write: directory '" + dir.string() + "' does not exist");
}

void requireWritable(const std::string& path, const std::string& target) {
    requireDirectoryOf(path, target);
    // No write bit at all counts as read-only for root too, who may write anything (as rm asks).
    struct stat st {};
    if (::stat(target.c_str(), &st) == 0 &&
        (::access(target.c_str(), W_OK) != 0 || (st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0))
        throw FileError(path, "is read-only, so it is kept; make it writable to let obscura replace it");
}
} // namespace

void requireOutputDirectory(const std::string& path) { requireDirectoryOf(path, writeTarget(path)); }

void requireWritableDestination(const std::string& path) { requireWritable(path, writeTarget(path)); }

std::string writeTarget(const std::string& path) {
    fs::path p(path);
    std::error_code ec;
    // A chain of links, each relative to the directory holding it; 40 as the kernel's own limit.
    for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(p, ec)); ++hops) {
        const fs::path next = fs::read_symlink(p, ec);
        if (ec) break;
        p = next.is_absolute() ? next : p.parent_path() / next;
    }
    return p.string();
}

namespace {
thread_local WriteBatch* tCurrentBatch = nullptr;

void renameOver(const std::string& tmp, const std::string& target, const std::string& path) {
    struct stat before {};
    if (::stat(target.c_str(), &before) == 0) ::chmod(tmp.c_str(), before.st_mode & 07777);
    if (std::rename(tmp.c_str(), target.c_str()) != 0) {
        const int err = errno;
        std::remove(tmp.c_str());
        throw FileError(path, std::string("cannot write: rename failed: ") + std::strerror(err));
    }
}
} // namespace

WriteBatch::WriteBatch() : outer_(tCurrentBatch) { tCurrentBatch = this; }

WriteBatch::~WriteBatch() {
    tCurrentBatch = outer_;
    for (const Staged& s : staged_) std::remove(s.tmp.c_str());
}

WriteBatch* WriteBatch::current() { return tCurrentBatch; }

void WriteBatch::stage(const std::string& tmp, const std::string& target, const std::string& path) {
    staged_.push_back({tmp, target, path});
}

std::string WriteBatch::staged(const std::string& path) const {
    for (const Staged& s : staged_)
        if (s.path == path) return s.tmp;
    return "";
}

void WriteBatch::commit() {
    std::vector<Staged> staged;
    staged.swap(staged_);
    for (size_t i = 0; i < staged.size(); ++i) {
        try {
            renameOver(staged[i].tmp, staged[i].target, staged[i].path);
        } catch (const Error&) {
            for (size_t j = i + 1; j < staged.size(); ++j) std::remove(staged[j].tmp.c_str());
            throw;
        }
    }
}

void writeAtomically(const std::string& path, const std::function<void(const std::string& tmp)>& write,
                     const std::string& tempSuffix) {
    static std::atomic<unsigned long> calls{0};
    const std::string target = writeTarget(path);
    requireWritable(path, target);
    const std::string tmp = target + ".tmp-" + std::to_string((long)::getpid()) + "-" + std::to_string(++calls) + tempSuffix;
    try {
        write(tmp);  // the file is closed when this returns
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
    if (WriteBatch* batch = WriteBatch::current()) return batch->stage(tmp, target, path);
    renameOver(tmp, target, path);
}

void writeTextFileAtomically(const std::string& path, const std::string& text) {
    writeAtomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << text << "\n";
        f.close();
        if (!f.good()) throw FileError(path, std::string("cannot write: ") + std::strerror(errno));
    });
}

std::vector<std::string> atomicWriteTemps(const std::string& path) {
    const fs::path p(writeTarget(path));
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    const std::string prefix = p.filename().string() + ".tmp-";
    std::vector<std::string> found;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > prefix.size() && name.compare(0, prefix.size(), prefix) == 0 &&
            std::isdigit((unsigned char)name[prefix.size()]) &&
            name.find_first_not_of("0123456789-", prefix.size()) == std::string::npos)
            found.push_back((p.parent_path() / name).string());
    }
    std::sort(found.begin(), found.end());
    return found;
}

int removeStaleTemps(const std::string& path) {
    int removed = 0;
    for (const std::string& tmp : atomicWriteTemps(path)) {
        const long pid = std::atol(tmp.c_str() + tmp.rfind(".tmp-") + 5);  // atol stops at "-<n>"
        // kill(pid, 0) probes without signalling: ESRCH means no such process here. This
        // process's own temp files are another thread's writes in flight.
        if (pid == (long)::getpid()) continue;
        if (pid > 0 && ::kill((pid_t)pid, 0) == 0) continue;
        if (pid > 0 && errno != ESRCH) continue;
        if (std::remove(tmp.c_str()) == 0) ++removed;
    }
    return removed;
}

} // namespace obscura
