// --inspect: what obscura finds in a frame before computing anything (layers, roles,
// conventions, camera, how it would write, device). One structure, two forms: the JSON of
// `--inspect --json` and Python's obscura.inspect(), and the text of `--inspect`, which is
// printed from that JSON so the two cannot say different things.
#pragma once
#include "io/frame_job.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace obscura {

// Reads the headers and the passes the camera needs; writes nothing. Only a file that cannot be
// read at all throws: a missing pass, camera or device is reported in the structure (each role's
// "fills", "problems", "camera": null and "camera_error"), with a command line that would run.
nlohmann::json inspectFrameJson(const FrameJob& job);
// The readable form of inspectFrameJson's structure.
std::string inspectText(const nlohmann::json& inspected);
// A command line that would run on the job's file: its own flags, plus what a run needs that
// they lack (an assumed lens when nothing gives one; normals from depth when world-space
// normals have no camera pose), each addition explained in `notes`. No args and the reason in
// `problem` when no flag can make it run (no depth, nor a position pass). Without -o the command
// writes NAME_ao.exr beside the input, or the first NAME_ao_K.exr that does not exist (noted).
// `loaded`: the passes loadPassesForInspection gave for `job`, where the caller has them.
struct SuggestedCommand {
    std::vector<std::string> args;   // "obscura", INPUT, "-o", OUTPUT, ...
    std::vector<std::string> notes;
    std::string problem;
};
SuggestedCommand suggestCommand(const FrameJob& job, const FramePasses* loaded = nullptr);
// The args as one line a POSIX shell reads back as them.
std::string commandLine(const std::vector<std::string>& args);
std::string shellQuoted(const std::string& arg);

inline std::string inspectFrame(const FrameJob& job) { return inspectText(inspectFrameJson(job)); }

} // namespace obscura
