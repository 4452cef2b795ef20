// Nothing a user has is overwritten: before a run writes anything, every path it would write
// is compared with every path it reads and with each other, by file identity (the inode a
// path reaches through its links), not by spelling. Shared by the CLI and Python.
#pragma once
#include "core/methods.h"
#include "io/frame_job.h"

#include <string>
#include <vector>

namespace obscura {

// One frame's files: the job (input, output, preview, sidecar, deep input, map) and its report.
struct FrameFiles {
    const FrameJob* job;
    std::string report;  // "" when no report is written
};

// Throws UsageError, naming both roles, when a written path is a file the run reads or
// another written path (a sequence passes every frame, so frames cannot collide either).
// The output may be the input only with job.inPlace. Also refuses an output not named .exr,
// a preview not named .png and a report not named .json: each would be a misnamed file.
void checkFrameFiles(const std::vector<FrameFiles>& frames, Spelling spelling);

// The path a --report or --preview spec gives for `output`: the spec itself, or, when it names
// a directory (an existing one, or a path ending in '/'), DIR/<output's stem><extension>. A
// sequence's output pattern keeps its frame placeholder in the stem.
std::string besideOutput(const std::string& spec, const std::string& output, const char* extension);

} // namespace obscura
