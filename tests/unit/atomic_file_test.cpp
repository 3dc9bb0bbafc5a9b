// Atomic file writing: complete content or nothing, and stale temporaries of dead writers cleared.
#include "io/atomic_file.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

class AtomicFile : public ::testing::Test {
protected:
    void SetUp() override {
        folder = fs::temp_directory_path() / ("atomic_file_test_" + std::to_string(::getpid()));
        fs::remove_all(folder);
        fs::create_directories(folder);
    }
    void TearDown() override { fs::remove_all(folder); }
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        for (const auto& e : fs::directory_iterator(folder)) out.push_back(e.path().filename().string());
        std::sort(out.begin(), out.end());
        return out;
    }
    fs::path folder;
};

TEST_F(AtomicFile, WritesTheConcatenatedPiecesAndNothingElse) {
    const std::string path = (folder / "out.bin").string();
    const std::string a = "header\n";
    const float values[2] = {1.5f, -2.0f};
    rad::writeFileAtomically(path, {{a.data(), a.size()}, {values, sizeof(values)}, {nullptr, 0}});
    const auto bytes = radtest::readBytes(path);
    ASSERT_EQ(bytes.size(), a.size() + sizeof(values));
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + a.size()), a);
    float back[2];
    std::memcpy(back, bytes.data() + a.size(), sizeof(back));
    EXPECT_EQ(back[0], 1.5f);
    EXPECT_EQ(back[1], -2.0f);
    EXPECT_EQ(names(), std::vector<std::string>{"out.bin"});
    // Replacing keeps one file with the new content.
    rad::writeFileAtomically(path, {{a.data(), 3}});
    EXPECT_EQ(radtest::readBytes(path).size(), 3u);
    EXPECT_EQ(names(), std::vector<std::string>{"out.bin"});
}

TEST_F(AtomicFile, FailureLeavesTheOldFileAndNoTemporary) {
    const std::string missingFolder = (folder / "missing" / "out.bin").string();
    try {
        rad::writeFileAtomically(missingFolder, {{"x", 1}});
        FAIL() << "no error";
    } catch (const rad::AtomicFileError& e) {
        EXPECT_NE(std::string(e.what()).find("check that the folder exists"), std::string::npos) << e.what();
    }
    // The destination is a folder: the rename fails, the folder stays, the temporary is removed.
    fs::create_directories(folder / "taken");
    EXPECT_THROW(rad::writeFileAtomically((folder / "taken").string(), {{"x", 1}}), rad::AtomicFileError);
    EXPECT_TRUE(fs::is_directory(folder / "taken"));
    EXPECT_EQ(names(), std::vector<std::string>{"taken"});
}

TEST_F(AtomicFile, TemporaryNamesAreUnique) {
    const std::string path = (folder / "x.rply").string();
    const std::string a = rad::uniqueTemporaryPath(path), b = rad::uniqueTemporaryPath(path);
    EXPECT_NE(a, b);
    EXPECT_EQ(a.rfind(path + ".part-" + std::to_string(::getpid()) + "-", 0), 0u) << a;
}

TEST_F(AtomicFile, StaleTemporariesOfDeadWritersAreRemovedOthersKept) {
    const std::string path = (folder / "x.rply").string();
    // A pid that does not exist: above the kernel's pid_max (4194304 at most on Linux).
    const std::string dead = "x.rply.part-4194305-0-12";
    const std::string live = "x.rply.part-" + std::to_string(::getpid()) + "-0-12";
    const std::string foreign[] = {"x.rply.part-abc-0-12", "x.rply.partial", "y.rply.part-4194305-0-12"};
    for (const std::string& name : {dead, live}) radtest::writeBytes((folder / name).string(), {'a'});
    for (const std::string& name : foreign) radtest::writeBytes((folder / name).string(), {'a'});
    rad::removeStaleTemporaries(path);
    const auto left = names();
    EXPECT_EQ(std::count(left.begin(), left.end(), dead), 0);
    EXPECT_EQ(std::count(left.begin(), left.end(), live), 1);
    for (const std::string& name : foreign) EXPECT_EQ(std::count(left.begin(), left.end(), name), 1) << name;
}

}  // namespace
