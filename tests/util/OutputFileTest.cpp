// SPDX-License-Identifier: Apache-2.0
// Oracle: the file system itself, read back with stat, lstat, readlink and the files' bytes:
// an OutputFile must leave either the old file or the complete new one, keep links and modes,
// write devices in place, and leave no temporary file behind.

#include <vdb/Exceptions.h>
#include <vdb/util/OutputFile.h>

#include "GridContents.h"
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;

class OutputFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::path(test::tempPath("vdb-output-", info->name()));
        fs::remove_all(mDir);
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }
    std::string path(const std::string& name) const { return (mDir / name).string(); }
    std::vector<std::string> listing() const { return test::folderNames(mDir); }
    void put(const std::string& name, const std::string& text) const {
        std::ofstream(path(name), std::ios::binary) << text;
    }
    std::string get(const std::string& name) const {
        const auto bytes = test::fileBytes(path(name));
        return std::string(bytes.begin(), bytes.end());
    }
    fs::path mDir;
};

TEST_F(OutputFileTest, CommitReplacesAndAbandonLeavesTheOldFile) {
    put("a.txt", "old");
    {
        util::OutputFile out(path("a.txt"));
        EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});  // nothing created yet
        out.write("new contents", 12);
        EXPECT_EQ(get("a.txt"), "old");
    }
    EXPECT_EQ(get("a.txt"), "old");
    EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
    util::writeOutputFile(path("a.txt"), [](util::OutputFile& out) { out.write("new", 3); });
    EXPECT_EQ(get("a.txt"), "new");
    EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
    // A writer that throws changes nothing.
    EXPECT_THROW(util::writeOutputFile(path("a.txt"),
                                       [](util::OutputFile& out) {
                                           out.write("partial", 7);
                                           throw std::runtime_error("failed");
                                       }),
                 std::runtime_error);
    EXPECT_EQ(get("a.txt"), "new");
    EXPECT_EQ(listing(), std::vector<std::string>{"a.txt"});
    // An output with no bytes is an empty file.
    util::OutputFile empty(path("empty.txt"));
    empty.commit();
    EXPECT_EQ(get("empty.txt"), "");
}

TEST_F(OutputFileTest, LinksAreWrittenThroughAndModesKept) {
    put("target.txt", "old");
    fs::permissions(path("target.txt"), fs::perms(0604));
    fs::create_symlink("target.txt", path("link.txt"));
    util::OutputFile out(path("link.txt"));
    EXPECT_EQ(out.target(), path("target.txt"));
    EXPECT_FALSE(out.isDirect());
    out.write("new", 3);
    out.commit();
    EXPECT_TRUE(fs::is_symlink(path("link.txt")));
    EXPECT_EQ(get("target.txt"), "new");
    EXPECT_EQ(fs::status(path("target.txt")).permissions() & fs::perms::mask, fs::perms(0604));
}

TEST_F(OutputFileTest, DevicesAreWrittenInPlace) {
    util::OutputFile out("/dev/null");
    EXPECT_TRUE(out.isDirect());
    out.write("discarded", 9);
    out.commit();
    struct stat st {};
    ASSERT_EQ(::stat("/dev/null", &st), 0);
    EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST_F(OutputFileTest, BadTargetsAreRefusedBeforeAnythingIsCreated) {
    put("file.txt", "x");
    const auto message = [&](const std::string& target) {
        try {
            util::checkOutputFile(target);
        } catch (const IoError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message("").find("empty path"), std::string::npos);
    EXPECT_NE(message(mDir.string()).find("is a folder"), std::string::npos);
    EXPECT_NE(message(path("missing/out.txt")).find("does not exist"), std::string::npos);
    EXPECT_NE(message(path("file.txt/out.txt")).find("file.txt is a file, not a folder"),
              std::string::npos);
    fs::create_symlink("loop2", path("loop1"));
    fs::create_symlink("loop1", path("loop2"));
    EXPECT_NE(message(path("loop1")).find("symbolic links"), std::string::npos);
    EXPECT_EQ(listing(), (std::vector<std::string>{"file.txt", "loop1", "loop2"}));
}

TEST_F(OutputFileTest, StaleTemporariesOfDeadProcessesGoAndLiveOnesStay) {
    const pid_t child = ::fork();
    if (child == 0)
        ::_exit(0);
    ASSERT_GT(child, 0);
    ::waitpid(child, nullptr, 0);
    const std::string stale = ".vdb-" + std::to_string(child) + "-zzzzzz";
    const std::string notOurs = ".vdb-" + std::to_string(child) + "-toolong1";
    put(stale, "stale");
    put(notOurs, "a name of another pattern");
    util::writeOutputFile(path("out.txt"), [](util::OutputFile& out) { out.write("x", 1); });
    EXPECT_EQ(listing(), (std::vector<std::string>{notOurs, "out.txt"}));
}

}  // namespace
}  // namespace vdb
