// One exception type for every user-facing failure: its message is the one line a user sees.
#pragma once
#include <stdexcept>
#include <string>

namespace obscura {
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};
} // namespace obscura
