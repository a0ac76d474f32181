// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `vdb clip`: the output read back with the library must hold exactly the
// input's active voxels inside the box or mask (or outside, with --outside), counted by brute
// force over the input; bad requests fail with one error line, status 2, and leave the output
// file that was there unchanged.

#include <vdb/io/File.h>

#include "CliFixture.h"
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace vdb {
namespace {

class ClipCli : public test::ToolTest {
protected:
    void SetUp() override {
        ToolTest::SetUp();
        // A float grid of voxel size 0.5 with active voxels on both sides of the origin.
        auto grid = FloatGrid::create(0.0f);
        grid->setName("density");
        grid->setTransform(math::Transform::createLinearTransform(0.5));
        for (Int32 x = -20; x <= 20; ++x)
            for (Int32 y = -20; y <= 20; y += 3)
                for (Int32 z = -20; z <= 20; z += 5)
                    grid->tree().setValueOn(Coord(x, y, z), float(x + y + z));
        mInput = grid;
        io::File(path("in.vdb")).write(GridPtrVec{grid});
    }

    FloatGrid::Ptr readFloat(const std::string& name) {
        io::File file(path(name));
        file.open();
        auto grids = file.getGrids();
        return gridPtrCast<FloatGrid>(grids->front());
    }

    /// The input's active voxels whose index lies in [lo, hi] (or outside it).
    Index64 countIn(const Coord& lo, const Coord& hi, bool inside) const {
        Index64 n = 0;
        for (auto it = mInput->tree().cbeginValueOn(); it; ++it)
            n += CoordBBox(lo, hi).isInside(it.getCoord()) == inside;
        return n;
    }

    FloatGrid::Ptr mInput;
};

TEST_F(ClipCli, BoxKeepsTheVoxelsFromTheFloorOfEachCorner) {
    ok({"clip", path("in.vdb"), "-o", path("out.vdb"), "--bbox", "-2.2,-1,0.3,4.9,3.0,6"});
    const auto out = readFloat("out.vdb");
    ASSERT_TRUE(out);
    EXPECT_EQ(out->getName(), "density");
    // World / 0.5, floored: x in [-5, 9], y in [-2, 6], z in [0, 12].
    const Coord lo(-5, -2, 0), hi(9, 6, 12);
    EXPECT_EQ(out->activeVoxelCount(), countIn(lo, hi, true));
    for (auto it = out->tree().cbeginValueOn(); it; ++it) {
        ASSERT_TRUE(CoordBBox(lo, hi).isInside(it.getCoord())) << it.getCoord();
        ASSERT_EQ(*it, mInput->tree().getValue(it.getCoord()));
    }
    ok({"clip", path("in.vdb"), "-o", path("outside.vdb"), "--bbox", "-2.2,-1,0.3,4.9,3.0,6",
        "--outside"});
    EXPECT_EQ(readFloat("outside.vdb")->activeVoxelCount(), countIn(lo, hi, false));
}

TEST_F(ClipCli, MaskOfAnotherTypeAndTransformKeepsItsActiveVoxels) {
    auto mask = BoolGrid::create(false);
    mask->setTransform(math::Transform::createLinearTransform(1.0));
    // World [0, 3) on every axis: index 0..5 of the input (voxel size 0.5).
    mask->tree().fill(CoordBBox(Coord(0), Coord(2)), true, true);
    io::File(path("mask.vdb")).write(GridPtrVec{mask});
    ok({"clip", path("in.vdb"), "-o", path("out.vdb"), "--mask", path("mask.vdb")});
    EXPECT_EQ(readFloat("out.vdb")->activeVoxelCount(), countIn(Coord(0), Coord(5), true));
    ok({"clip", path("in.vdb"), "-o", path("out2.vdb"), "--mask", path("mask.vdb"), "--outside"});
    EXPECT_EQ(readFloat("out2.vdb")->activeVoxelCount(), countIn(Coord(0), Coord(5), false));
}

TEST_F(ClipCli, BadArgumentsFailAndLeaveTheOutputAlone) {
    io::File(path("keep.vdb")).write(GridPtrVec{mInput});
    const auto before = test::fileBytes(path("keep.vdb"));
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb")}, 2, "exactly one of --bbox and --mask");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--bbox", "0,0,0,1,1,1", "--mask",
           path("in.vdb")},
          2, "exactly one of --bbox and --mask");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--bbox", "0,0,0,1,1"}, 2, "bbox");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--bbox", "0,0,0,1,nan,1"}, 2, "bbox");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--bbox", "0,0,0,1,-1,1"}, 2,
          "must not exceed the maximum");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--mask", path("missing.vdb")}, 1,
          "missing.vdb");
    fails({"clip", path("missing.vdb"), "-o", path("keep.vdb"), "--bbox", "0,0,0,1,1,1"}, 1,
          "missing.vdb");
    fails({"clip", path("in.vdb"), "-o", path("keep.vdb"), "--mask", path("in.vdb"), "--mask-grid",
           "nope"},
          2, "nope");
    EXPECT_EQ(test::fileBytes(path("keep.vdb")), before);
}

}  // namespace
}  // namespace vdb
