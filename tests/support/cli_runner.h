// Runs a program as a subprocess (no shell) and captures its exit code, stdout and stderr.
#pragma once
#include <string>
#include <vector>

namespace obscura::test {

struct CliResult {
    int exitCode = -1;      // the exit status; 128 + N if killed by signal N; -1 if it could not start
    std::string out, err;   // everything written to stdout / stderr
};

// argv[0] is `program`; `args` follow verbatim (no shell, no splitting, no globbing). The child
// gets this process's environment with `env`'s "NAME=value" entries set on top.
CliResult runProgram(const std::string& program, const std::vector<std::string>& args,
                     const std::vector<std::string>& env = {});

#ifdef OBSCURA_CLI_PATH
// The built obscura command (each test executable is given its path) with `args`.
inline CliResult runObscura(const std::vector<std::string>& args) { return runProgram(OBSCURA_CLI_PATH, args); }
#endif

// "exit N" and everything the program printed, for a failed expectation's message.
std::string outcome(const CliResult& r);

} // namespace obscura::test
