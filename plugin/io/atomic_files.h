// Writes that leave either the old file or the whole new one: a temp file beside the target,
// then a rename; and the temp files a killed writer left, found and cleared.
#pragma once
#include <string>
#include <vector>

namespace obscura {

// Writes text + newline to path through a temp file and a rename; throws obscura::Error.
void writeTextFileAtomically(const std::string& path, const std::string& text);
// The temp files "<path>.tmp-<pid>" of atomic writes to `path` (outputs, reports).
std::vector<std::string> atomicWriteTemps(const std::string& path);
// Removes those whose writer is no longer running on this host (a killed or crashed run), so a
// retried frame leaves no half-written file; a live writer's temp file is kept. Returns how many.
int removeStaleTemps(const std::string& path);
// Throws obscura::Error when the directory `path` would be written into does not exist.
void requireOutputDirectory(const std::string& path);

} // namespace obscura
