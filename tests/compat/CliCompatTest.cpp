// SPDX-License-Identifier: Apache-2.0
// The `.vdb` files the vdb tool writes, read by OpenVDB 10: each grid OpenVDB reads has the
// name, class, voxel size and every active value (bit for bit; through halves where asked)
// that this library reads from the same file.

#include <vdb/Grid.h>
#include <vdb/io/File.h>

#include "OpenVdbConvert.h"
#include <GridContents.h>
#include <Oracles.h>
#include <ToolRunner.h>
#include <gtest/gtest.h>
#include <openvdb/io/File.h>
#include <openvdb/openvdb.h>

#include <filesystem>
#include <string>
#include <vector>

#ifdef VDB_TOOL_PATH

namespace vdb {
namespace {

class CliCompat : public ::testing::Test {
protected:
    void SetUp() override {
        openvdb::initialize();
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = test::tempPath("vdb-cli-compat-", info->name());
        std::filesystem::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        std::filesystem::remove_all(mDir, ec);
    }
    std::string path(const std::string& name) const { return mDir + "/" + name; }
    void ok(const std::vector<std::string>& args) {
        const test::Result r = test::runTool(VDB_TOOL_PATH, args, mDir);
        ASSERT_EQ(r.status, 0) << r.err;
    }

    /// Reads `file` with both libraries and compares its float grids.
    void expectSameInOpenVdb(const std::string& file) {
        io::File ours(file);
        ours.open();
        const GridPtrVec grids = *ours.getGrids();
        openvdb::io::File theirs(file);
        theirs.open();
        const auto theirGrids = theirs.getGrids();
        ASSERT_EQ(theirGrids->size(), grids.size());
        for (const auto& base : grids) {
            auto grid = gridPtrCast<FloatGrid>(base);
            ASSERT_TRUE(grid);
            auto other = openvdb::gridPtrCast<openvdb::FloatGrid>(theirs.readGrid(grid->getName()));
            ASSERT_TRUE(other) << grid->getName();
            EXPECT_EQ(other->getGridClass() == openvdb::GRID_LEVEL_SET,
                      grid->getGridClass() == GRID_LEVEL_SET);
            EXPECT_DOUBLE_EQ(other->voxelSize()[0], grid->voxelSize()[0]);
            EXPECT_EQ(other->activeVoxelCount(), grid->activeVoxelCount());
            EXPECT_EQ(other->saveFloatAsHalf(), grid->saveFloatAsHalf());
            auto acc = other->getConstAccessor();
            for (auto it = grid->cbeginValueOn(); it; ++it) {
                const auto ijk = test::toOvdb(it.getCoord());
                ASSERT_TRUE(acc.isValueOn(ijk)) << it.getCoord();
                ASSERT_TRUE(test::sameBits(acc.getValue(ijk), *it)) << it.getCoord();
            }
        }
        theirs.close();
    }

    std::string mDir;
};

TEST_F(CliCompat, ToolOutputsReadTheSameInOpenVdb) {
    ok({"sphere", "-o", path("a.vdb"), "--radius", "1", "--voxel-size", "0.05"});
    expectSameInOpenVdb(path("a.vdb"));
    ok({"sphere", "-o", path("b.vdb"), "--radius", "1", "--center", "0.7,0.2,0", "--voxel-size",
        "0.05", "--name", "b"});
    ok({"csg", "union", path("a.vdb"), path("b.vdb"), "-o", path("u.vdb"), "--compression", "zip"});
    expectSameInOpenVdb(path("u.vdb"));
    ok({"morph", "dilate", "2", path("u.vdb"), "-o", path("d.vdb"), "--compression", "none"});
    expectSameInOpenVdb(path("d.vdb"));
    ok({"convert", path("d.vdb"), "-o", path("h.vdb"), "--half", "--compression", "blosc"});
    expectSameInOpenVdb(path("h.vdb"));
}

}  // namespace
}  // namespace vdb

#endif  // VDB_TOOL_PATH
