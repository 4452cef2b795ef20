// Writes that leave either the old file or the whole new one: a temp file beside the target,
// then a rename; and the temp files a killed writer left, found and cleared. A path that is a
// symlink is written through (the file it leads to is replaced, the link kept), an earlier file's
// permission bits are kept, and a file the user may not write is refused, not replaced.
#pragma once
#include <functional>
#include <string>
#include <vector>

namespace obscura {

// Writes `path` through write(tmp), a temp file beside the file it replaces (writeTarget), then a
// rename (or a stage in the thread's WriteBatch), keeping an earlier file's permission bits. The
// temp file, "<target>.tmp-<pid>-<n>" + tempSuffix, is unique to the call, so threads and
// processes writing one path never share one; write's exception removes it and passes on.
// Refuses what requireWritableDestination refuses.
void writeAtomically(const std::string& path, const std::function<void(const std::string& tmp)>& write,
                     const std::string& tempSuffix = "");
// Writes text + newline to path so; throws obscura::Error.
void writeTextFileAtomically(const std::string& path, const std::string& text);

// The file a write to `path` replaces: path itself, or the file its symlinks lead to (which
// need not exist yet).
std::string writeTarget(const std::string& path);

// A run's files written as one: while a batch lives, the writes its thread commits stay temp
// files, and commit() renames them all, so a run that fails after writing its output (its report
// or preview could not be written) leaves nothing. Without commit() the temp files are removed.
class WriteBatch {
public:
    WriteBatch();
    ~WriteBatch();
    WriteBatch(const WriteBatch&) = delete;
    WriteBatch& operator=(const WriteBatch&) = delete;
    void commit();
    // The batch writeAtomically stages into on this thread, or null.
    static WriteBatch* current();
    void stage(const std::string& tmp, const std::string& target, const std::string& path);
    // The temp file a write to `path` staged here (what a program handed the file before the
    // commit reads), or "" when none did.
    std::string staged(const std::string& path) const;

private:
    struct Staged {
        std::string tmp, target, path;
    };
    std::vector<Staged> staged_;
    WriteBatch* outer_;
};

// The temp files "<path>.tmp-<pid>[-<n>]" of atomic writes to `path` (outputs, reports).
std::vector<std::string> atomicWriteTemps(const std::string& path);
// Removes those whose writer is no longer running on this host (a killed or crashed run), so a
// retried frame leaves no half-written file; a live writer's temp file is kept. Returns how many.
int removeStaleTemps(const std::string& path);
// Throws FileError when the directory `path` would be written into does not exist.
void requireOutputDirectory(const std::string& path);
// Throws FileError when `path` cannot be written: its directory does not exist, or a file
// already there (an earlier output) is one the user may not write (read-only: kept, as cp would).
void requireWritableDestination(const std::string& path);

} // namespace obscura
