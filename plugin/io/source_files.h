// The files a frame is computed from, and their stamps: what --resume compares with what an
// output records, so that a file rendered again, or rolled back to an older version (a link
// pointed at an earlier render, a copy that kept its older time), computes the frame again.
#pragma once
#include <string>
#include <vector>

namespace obscura {

struct FrameJob;

// One file as a run read it: its absolute path, its size and modification time. A file is the
// same version while its size and time are (a project moved or copied with its times keeps
// them; another render, even an older one, has its own); where its links lead is not compared,
// as hosts mounting one project under other names resolve them differently.
struct FileStamp {
    std::string path;
    long long size = 0, mtimeNs = 0;
};

// The files a frame is computed from that exist: the input (unless it is replaced in place),
// deep inputs, the camera sidecar, the environment map; each once.
std::vector<std::string> filesReadBy(const FrameJob& job);
// A path as the records name it (the output_absolute and sources of a report, and what --resume
// looks them up by): absolute, lexically normal.
std::string recordedPath(const std::string& path);
std::vector<FileStamp> stampsOf(const std::vector<std::string>& files);

} // namespace obscura
