// Atomic file writing: complete content or nothing, and stale temporaries of dead writers cleared.
#include "io/atomic_file.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>
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

std::string contents(const fs::path& path) {
    const std::vector<char> bytes = radtest::readBytes(path.string());
    return std::string(bytes.begin(), bytes.end());
}
void writeText(const std::string& path, const std::string& text) {
    radtest::writeBytes(path, std::vector<char>(text.begin(), text.end()));
}

TEST_F(AtomicFile, FileSetPutsEveryFileInPlaceAtOnce) {
    writeText((folder / "a.png").string(), "old a");
    rad::AtomicFileSet files;
    const std::string a = files.add((folder / "a.png").string()), b = files.add((folder / "b.txt").string());
    EXPECT_NE(a, b);
    writeText(a, "new a");
    writeText(b, "new b");
    EXPECT_EQ(contents(folder / "a.png"), "old a");  // nothing visible before the commit
    EXPECT_FALSE(fs::exists(folder / "b.txt"));
    files.commit();
    EXPECT_EQ(contents(folder / "a.png"), "new a");
    EXPECT_EQ(contents(folder / "b.txt"), "new b");
    EXPECT_EQ(names(), (std::vector<std::string>{"a.png", "b.txt"}));  // no temporary, no backup left
}

// The glTF bake renamed its files one by one: a later rename failing left the new maps beside no
// .glb. A set is all or nothing: the files already replaced get their old contents back.
TEST_F(AtomicFile, FileSetRestoresEveryFileWhenALaterOneCannotBePutInPlace) {
    writeText((folder / "m_normal.png").string(), "old map");
    fs::create_directory(folder / "m.glb");  // a folder where the last file goes
    {
        rad::AtomicFileSet files;
        writeText(files.add((folder / "m_normal.png").string()), "new map");
        writeText(files.add((folder / "m_diffuse.png").string()), "new diffuse");
        writeText(files.add((folder / "m.glb").string()), "new glb");
        try {
            files.commit();
            FAIL() << "a folder in the way was replaced";
        } catch (const rad::AtomicFileError& e) {
            EXPECT_NE(std::string(e.what()).find("m.glb"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(contents(folder / "m_normal.png"), "old map");
    EXPECT_FALSE(fs::exists(folder / "m_diffuse.png"));
    EXPECT_EQ(names(), (std::vector<std::string>{"m.glb", "m_normal.png"}));
}

TEST_F(AtomicFile, FileSetNotCommittedLeavesNothing) {
    {
        rad::AtomicFileSet files;
        writeText(files.add((folder / "x.png").string()), "data");
    }
    EXPECT_TRUE(names().empty());
}

TEST_F(AtomicFile, OutputPathProblemsNameTheCauseAndTheFix) {
    EXPECT_EQ(rad::outputPathProblem((folder / "fine.png").string()), "");
    const std::string isFolder = rad::outputPathProblem(folder.string());
    EXPECT_NE(isFolder.find("is a folder, not a file name"), std::string::npos) << isFolder;
    const std::string missing = rad::outputPathProblem((folder / "no" / "x.png").string());
    EXPECT_NE(missing.find("does not exist: create it"), std::string::npos) << missing;
    writeText((folder / "plain").string(), "x");
    const std::string underFile = rad::outputPathProblem((folder / "plain" / "x.png").string());
    EXPECT_NE(underFile.find("is a file, not a folder"), std::string::npos) << underFile;
}

}  // namespace
