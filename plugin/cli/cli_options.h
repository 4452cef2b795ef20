// The obscura command's options: the flag table (each flag's value, help line and what it
// sets), --help's text, and the command line parsed into a FrameJob. Flags come from the
// method table and the settings schema where those own them (core/methods.h,
// core/settings_schema.h), so a method's parameter or a range is written in one place.
#pragma once
#include "io/frame_job.h"

#include <string>
#include <vector>

namespace obscura::cli {

struct Options {
    FrameJob job;
    bool inspect = false, quiet = false, help = false, version = false, resume = false;
    bool keepGoing = false;  // --keep-going: a sequence runs every frame past a failing one
    bool inspectJson = false;  // --inspect --json
    std::string reportPath, frames;
    std::string flat;  // --flat: the input is deep, this file gives the passes
    std::string quality;  // --quality: applied after the flags, which win over it
    std::vector<std::string> given;    // every flag given, to refuse those the method does not read
    std::vector<std::string> outputs;  // outputs asked for by name (--out-layer ROLE=, --bounce)
};

std::string helpText();
// Throws UsageError for a bad command line, a flag the method does not read, or a device
// the method does not run on.
Options parseArgs(int argc, char** argv);

} // namespace obscura::cli
