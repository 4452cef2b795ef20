// The obscura command-line host: parses a recipe of flags, runs the operator, writes files.
#pragma once
#include "base/error.h"
#include "io/exr_file.h"

#include <optional>
#include <string>
#include <vector>

namespace obscura {
struct FrameJob;
}

namespace obscura::cli {
// Returns the process exit code; prints one error line to stderr on failure.
int run(int argc, char** argv);

// A bad command line (exit status 2), as opposed to a failure while running (1).
using obscura::UsageError;

// What a normal run's command line (without the program name) asks for: the parts a host
// planning runs elsewhere needs (obscura farm). A sequence's files are checked as its run checks
// them before the first frame (the frames' paths, and the directories written into): throws
// UsageError or FileError as `run` would.
struct RunPlan {
    std::string input, output, frames, report, aoChannel;  // report: a pattern, or "" for none
    std::vector<int> frameList;          // a sequence's frames (--frames, else every input found)
    std::vector<std::string> readFiles;  // what every frame reads beside its input: --camera, --env
    int threads = 0;
    bool resume = false;
};
// reportByDefault: with no --report, the report a farm task is given (the output pattern with
// .json), checked with the rest.
RunPlan planRun(const std::vector<std::string>& args, bool reportByDefault = false);

// A sequence's job (its paths frame patterns) for one frame.
FrameJob sequenceFrame(const FrameJob& sequence, int frame);

// A frame's output is complete: it reads back as an EXR holding the AO channel, with every chunk
// its tables name inside the file (a copy cut short is not complete). Its headers, for
// staleOutputReason, else nullopt.
std::optional<ExrInfo> completeOutput(const std::string& path, const std::string& aoChannel);
// Why a complete output (its headers `output`, as completeOutput read them) is stale, or "" when it is not: a file it was computed from (the input,
// a deep input, the camera sidecar, the environment map) is newer ("is older than FILE"), or the
// obscura/settings of the part this output's run wrote (the one naming this output: what a
// --report records, the settings and the recipe) differ from `job`'s ("was written with other
// settings"). The threads and the device change no result beyond GL's parity and do not count;
// an output that records no recipe (an older obscura's), or none naming it, is not stale.
std::string staleOutputReason(const FrameJob& job, const ExrInfo& output);

// `obscura farm ...` (farm.cpp): argv[1] is "farm".
int runFarm(int argc, char** argv);
} // namespace obscura::cli
