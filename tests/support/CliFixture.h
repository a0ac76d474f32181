// SPDX-License-Identifier: Apache-2.0
/// @file
/// The fixture of the tests that run the `vdb` tool (tests/cli): a temporary folder per test,
/// running the tool there, expecting success or one error line with no file left behind; and
/// PNG pictures decoded with libpng. VDB_TOOL_PATH names the tool.

#pragma once

#include "GridContents.h"
#include "ToolRunner.h"
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace vdb::test {

namespace fs = std::filesystem;

/// A test that runs the tool in a folder of its own, removed afterwards.
class ToolTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::path(tempPath("vdb-cli-", info->name()));
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }

    std::string path(const std::string& name) const { return (mDir / name).string(); }

    pid_t spawn(const std::vector<std::string>& args) {
        return spawnTool(VDB_TOOL_PATH, args, mDir.string());
    }
    Result wait(pid_t pid) { return waitTool(pid, mDir.string()); }
    Result run(const std::vector<std::string>& args) { return wait(spawn(args)); }

    /// Runs a command that must succeed.
    Result ok(const std::vector<std::string>& args) {
        Result r = run(args);
        EXPECT_EQ(r.status, 0) << "stderr: " << r.err;
        return r;
    }

    /// Runs a command that must fail with `status`, one error line naming `needle`, and no
    /// new file in the test folder.
    void fails(const std::vector<std::string>& args, int status, const std::string& needle) {
        const std::vector<std::string> before = folderNames(mDir);
        const Result r = run(args);
        EXPECT_EQ(r.status, status) << "stderr: " << r.err;
        EXPECT_NE(r.err.find("error:"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos)
            << "expected '" << needle << "' in: " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1)
            << "one line expected: " << r.err;
        EXPECT_EQ(before, folderNames(mDir)) << "the failed command left files behind";
    }

    fs::path mDir;
};

/// A PNG file decoded with libpng into 8-bit RGBA.
struct Picture {
    size_t width = 0, height = 0;
    std::vector<uint8_t> rgba;
    bool lit(size_t x, size_t y) const {
        const uint8_t* p = &rgba[4 * (y * width + x)];
        return p[0] || p[1] || p[2];
    }
    uint8_t alpha(size_t x, size_t y) const { return rgba[4 * (y * width + x) + 3]; }
    /// Pixels that are not fully transparent.
    size_t coveredCount() const {
        size_t n = 0;
        for (size_t i = 3; i < rgba.size(); i += 4)
            n += rgba[i] != 0;
        return n;
    }
    /// Pixels whose colour is not black (the background).
    size_t litCount() const {
        size_t n = 0;
        for (size_t y = 0; y < height; ++y)
            for (size_t x = 0; x < width; ++x)
                n += lit(x, y);
        return n;
    }
};

/// Decodes `file`; fails the test (and returns an empty picture) when libpng cannot.
inline Picture readPng(const std::string& file) {
    png_image png;
    std::memset(&png, 0, sizeof(png));
    png.version = PNG_IMAGE_VERSION;
    Picture pic;
    if (!png_image_begin_read_from_file(&png, file.c_str())) {
        ADD_FAILURE() << file << ": " << png.message;
        return pic;
    }
    png.format = PNG_FORMAT_RGBA;
    std::vector<uint8_t> pixels(PNG_IMAGE_SIZE(png));
    if (!png_image_finish_read(&png, nullptr, pixels.data(), 0, nullptr)) {
        ADD_FAILURE() << file << ": " << png.message;
        png_image_free(&png);
        return pic;
    }
    pic.width = png.width;
    pic.height = png.height;
    pic.rgba = std::move(pixels);
    return pic;
}

}  // namespace vdb::test
