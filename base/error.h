// One exception type for every user-facing failure: its message is the one line a user sees.
#pragma once
#include <stdexcept>
#include <string>

namespace obscura {
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A request that cannot be carried out as asked (a flag or keyword the method ignores, two
// roles naming one file): the command line's exit status 2, Python's ValueError.
struct UsageError : Error {
    using Error::Error;
};

// A failure a file caused, in the one form users and scripts parse: 'FILE': what is wrong.
// Hosts name the input for an Error that names no file (see blameInput in io/frame_job.h).
struct FileError : Error {
    FileError(const std::string& path, const std::string& what) : Error("'" + path + "': " + what) {}
};

// A message's text without the "'path': " a FileError of `path` starts with, to be said again
// of that file with more context ("frame 12: ...", "view 'left': ...").
inline std::string withoutFilePrefix(const std::string& what, const std::string& path) {
    const std::string prefix = "'" + path + "': ";
    return what.rfind(prefix, 0) == 0 ? what.substr(prefix.size()) : what;
}

// The first line of a library's message (OpenImageIO, OpenColorIO), trailing spaces and dots
// dropped: users get one line.
inline std::string firstLineOf(std::string s, const char* ifEmpty = "unknown error") {
    const auto nl = s.find_first_of("\r\n");
    if (nl != std::string::npos) s.resize(nl);
    while (!s.empty() && (s.back() == ' ' || s.back() == '.')) s.pop_back();
    return s.empty() ? std::string(ifEmpty) : s;
}
} // namespace obscura
