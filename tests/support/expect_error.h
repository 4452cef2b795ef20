// Expects a call to fail with obscura::Error on one line that names every given part.
#pragma once
#include "base/error.h"

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace obscura::test {

template <class F>
void expectError(F&& f, std::initializer_list<std::string> parts) {
    try {
        f();
        ADD_FAILURE() << "no Error thrown";
    } catch (const Error& e) {
        std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
        for (const std::string& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' not in: " << msg;
    }
}

} // namespace obscura::test
