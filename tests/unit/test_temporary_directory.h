// Each test's own folder for the files it writes (not a core unit: no test file of its own).
//
// ctest runs every test of core_tests as its own process, several at once. Tests that named their
// files only by what the file holds (for instance after the phrase a refusal must contain) could
// then write and read one another's files: one test read a file that a concurrent test had just
// replaced. A folder per test (suite and name) under the build's test folder rules that out.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <string>

namespace radtest {

inline const char* testTemporaryDirectory() {
    static std::string folder;
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = test ? std::string(test->test_suite_name()) + "." + test->name() : std::string("outside_tests");
    for (char& c : name)  // parameterised tests carry '/' in their names
        if (c != '.' && c != '_' && !std::isalnum(static_cast<unsigned char>(c))) c = '_';
    const std::string wanted = std::string(RADIANCE_TEST_TMPDIR_ROOT) + "/" + name;
    if (wanted != folder) {
        std::filesystem::create_directories(wanted);
        folder = wanted;
    }
    return folder.c_str();
}

}  // namespace radtest

// What the tests use: the current test's folder.
#define RADIANCE_TEST_TMPDIR (::radtest::testTemporaryDirectory())
