// The obscura command-line host: parses a recipe of flags, runs the operator, writes files.
#pragma once

namespace obscura::cli {
// Returns the process exit code; prints one error line to stderr on failure.
int run(int argc, char** argv);
} // namespace obscura::cli
