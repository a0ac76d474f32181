// SPDX-License-Identifier: Apache-2.0
// `vdb mesh` reports how it signed a mesh, in its report line and in --json: a closed cube by
// flood fill, a box without its lid by winding numbers (the lid's four edges), the mode asked
// for with --sign (robust being another name for winding). The box's inside is inside.

#include <vdb/Grid.h>
#include <vdb/io/File.h>

#include "GridContents.h"
#include "ToolRunner.h"
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;

class CliMesh : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::path(test::tempPath("vdb-cli-mesh-", info->name()));
        fs::create_directories(mDir);
        // A unit cube of six quads, counter-clockwise seen from outside, and the same without
        // its top.
        std::ofstream cube(path("cube.obj")), box(path("box.obj"));
        const std::string points =
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
        const std::string sides = "f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
        cube << points << sides << "f 5 6 7 8\n";
        box << points << sides;
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }

    std::string path(const std::string& name) const { return (mDir / name).string(); }

    /// Runs `vdb mesh IN -o OUT --resolution 20` with `extra`, which must succeed.
    test::Result mesh(const std::string& in, const std::vector<std::string>& extra = {}) {
        std::vector<std::string> args{"mesh",          path(in),       "-o",
                                      path("out.vdb"), "--resolution", "20"};
        args.insert(args.end(), extra.begin(), extra.end());
        test::Result r = test::runTool(VDB_TOOL_PATH, args, mDir.string());
        EXPECT_EQ(r.status, 0) << r.err;
        return r;
    }

    fs::path mDir;
};

TEST_F(CliMesh, ReportsFloodFillForAClosedMesh) {
    const test::Result text = mesh("cube.obj");
    EXPECT_NE(text.out.find("signs: mesh is closed and consistently oriented: flood fill"),
              std::string::npos)
        << text.out;
    const test::Result json = mesh("cube.obj", {"--json", "--quiet"});
    EXPECT_NE(json.out.find("\"sign\": \"flood\""), std::string::npos) << json.out;
    EXPECT_NE(json.out.find("\"holes\": 0"), std::string::npos) << json.out;
    EXPECT_NE(json.out.find("\"boundaryEdges\": 0"), std::string::npos) << json.out;
}

TEST_F(CliMesh, ReportsWindingNumbersForABoxWithoutItsLid) {
    const test::Result text = mesh("box.obj");
    EXPECT_NE(text.out.find("signs: 1 open loop (4 boundary edges): winding numbers near the "
                            "holes"),
              std::string::npos)
        << text.out;
    const test::Result json = mesh("box.obj", {"--json", "--quiet"});
    EXPECT_NE(json.out.find("\"sign\": \"winding\""), std::string::npos) << json.out;
    EXPECT_NE(json.out.find("\"boundaryEdges\": 4"), std::string::npos) << json.out;
    EXPECT_NE(json.out.find("\"holes\": 1"), std::string::npos) << json.out;
    io::File file(path("out.vdb"));
    file.open();
    const auto grid = gridPtrCast<FloatGrid>(file.getGrids()->front());
    ASSERT_TRUE(grid);
    // The middle of the box (0.5 world units: voxel 10) is inside, its lid's middle too (the
    // open face is closed across), a point above the lid outside.
    EXPECT_LT(grid->tree().getValue(Coord(10, 10, 10)), 0.0f);
    EXPECT_GT(grid->tree().getValue(Coord(10, 10, 26)), 0.0f);
}

TEST_F(CliMesh, ReportsTheModeAskedFor) {
    const test::Result robust = mesh("box.obj", {"--sign", "robust"});
    EXPECT_NE(robust.out.find("winding numbers near the holes (asked for)"), std::string::npos)
        << robust.out;
    const test::Result flood = mesh("box.obj", {"--sign", "flood", "--json", "--quiet"});
    EXPECT_NE(flood.out.find("\"sign\": \"flood\""), std::string::npos) << flood.out;
    EXPECT_NE(flood.out.find("flood fill by crossing parity (asked for)"), std::string::npos)
        << flood.out;
    const test::Result none = mesh("cube.obj", {"--sign", "unsigned"});
    EXPECT_NE(none.out.find("signs: unsigned distances (asked for)"), std::string::npos)
        << none.out;
}

}  // namespace
}  // namespace vdb
