// The obscura command-line host: parses a recipe of flags, runs the operator, writes files.
#pragma once
#include "base/error.h"

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
// planning runs elsewhere needs (obscura farm). Throws UsageError as `run` would.
struct RunPlan {
    std::string input, output, frames, report, aoChannel;
    int threads = 0;
    bool resume = false;
};
RunPlan planRun(const std::vector<std::string>& args);

// A frame's output is complete: it reads back as an EXR holding the AO channel.
bool outputComplete(const std::string& path, const std::string& aoChannel);
// A complete output says (its part's obscura/settings, what a --report records) that it was
// written with other settings than `job`'s. The threads and the device change no result beyond
// GL's parity and do not count; an output that does not say counts as written alike.
bool writtenWithOtherSettings(const FrameJob& job);

// `obscura farm ...` (farm.cpp): argv[1] is "farm".
int runFarm(int argc, char** argv);
} // namespace obscura::cli
