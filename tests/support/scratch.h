// Scratch directories for tests: OBSCURA_TEST_TMP/<prefix>-<pid>/<Suite.Test>, removed at
// exit when every test passed and kept for inspection otherwise. Header-only, so
// OBSCURA_TEST_TMP is the including test's own definition.
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <unistd.h>

namespace obscura::test {

inline std::filesystem::path scratchRoot(const std::string& prefix) {
    static const std::filesystem::path root =
        std::filesystem::path(OBSCURA_TEST_TMP) / (prefix + "-" + std::to_string(::getpid()));
    struct Cleanup : ::testing::Environment {
        void TearDown() override {
            if (::testing::UnitTest::GetInstance()->Passed()) std::filesystem::remove_all(root);
        }
    };
    static const auto* const registered = ::testing::AddGlobalTestEnvironment(new Cleanup);
    (void)registered;
    return root;
}

// A fresh, empty directory named after the running test.
inline std::filesystem::path testDir(const std::string& prefix) {
    const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string(info->test_suite_name()) + "." + info->name();
    for (char& c : name)
        if (c == '/') c = '_';
    const std::filesystem::path dir = scratchRoot(prefix) / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

} // namespace obscura::test
