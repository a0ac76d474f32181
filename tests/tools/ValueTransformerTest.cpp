// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h) fed the same writes as the grid, with the
// transform applied voxel by voxel to the model; every voxel of a box around the contents is
// checked (tiles included), and threaded runs must equal serial ones item for item.

#include <vdb/Grid.h>
#include <vdb/tools/ValueTransformer.h>
#include <vdb/tree/TreeConfigs.h>

#include "GridContents.h"
#include "VoxelChecks.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>

namespace vdb {
namespace {

using test::expectVoxels;
using test::SparseVolumeModel;

/// Many leaves of random voxels in [-60, 60]^3 (so the threaded paths split them into several
/// runs) and two active tiles and an inactive one.
void populate(FloatGrid& grid, SparseVolumeModel<float>& model, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-60, 60);
    std::uniform_real_distribution<float> v(-4.0f, 4.0f);
    for (int n = 0; n < 20000; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        test::setBoth(grid.tree(), model, ijk, v(rng), n % 4 != 0);
    }
    const auto tile = [&](const Coord& origin, float value, bool active) {
        test::fillBoth(grid.tree(), model, CoordBBox::createCube(origin, 8), value, active);
    };
    tile(Coord(-24, 8, -16), 2.5f, true);
    tile(Coord(16, -32, 0), -1.5f, true);
    tile(Coord(0, 0, -40), -3.0f, false);
    ASSERT_GE(grid.tree().activeTileCount(), 2u);
}

const CoordBBox kRegion(Coord(-64), Coord(64));

TEST(ValueTransformer, ForeachChangesEveryActiveValueAndState) {
    for (bool threaded : {false, true}) {
        SCOPED_TRACE(threaded ? "threaded" : "serial");
        auto grid = FloatGrid::create(0.5f);
        SparseVolumeModel<float> model(0.5f);
        populate(*grid, model, 1);
        // Doubles each active value; turns off the negative ones.
        tools::foreach (
            grid->beginValueOn(),
            [](const FloatGrid::ValueOnIter& it) {
                it.setValue(*it * 2.0f);
                if (*it < 0.0f)
                    it.setActiveState(false);
            },
            threaded);
        expectVoxels(grid->tree(), kRegion, [&](const Coord& ijk) {
            const float value = model.getValue(ijk);
            if (!model.isValueOn(ijk))
                return std::pair<float, bool>(value, false);
            return std::pair<float, bool>(value * 2.0f, value * 2.0f >= 0.0f);
        });
    }
}

TEST(ValueTransformer, ForeachVisitsEveryItemOnceWithSharedOrCopiedOps) {
    auto grid = FloatGrid::create(0.0f);
    SparseVolumeModel<float> model(0.0f);
    populate(*grid, model, 2);
    Index64 items = 0;
    for (auto it = grid->cbeginValueOn(); it; ++it)
        ++items;
    for (bool share : {true, false}) {
        std::atomic<Index64> count{0};
        tools::foreach (
            grid->cbeginValueOn(), [&](const auto&) { ++count; }, true, share);
        EXPECT_EQ(count.load(), items);
    }
    for (bool threaded : {false, true}) {
        std::atomic<Index64> tiles{0};
        tools::foreach (
            grid->cbeginValueOn(), [&](const auto& it) { tiles += it.isTileValue(); }, threaded);
        EXPECT_EQ(tiles.load(), grid->tree().activeTileCount()) << threaded;
    }
    std::atomic<Index64> leaves{0};
    tools::foreach (grid->tree().cbeginLeaf(), [&](const auto&) { ++leaves; });
    EXPECT_EQ(leaves.load(), grid->tree().leafCount());
}

TEST(ValueTransformer, TransformValuesWritesAnotherGridTypeThreadedAsSerial) {
    auto grid = FloatGrid::create(0.0f);
    SparseVolumeModel<float> model(0.0f);
    populate(*grid, model, 3);
    const auto op = [](const FloatGrid::ValueOnCIter& it, Int32Grid::Accessor& acc) {
        const Int32 value = Int32(std::lround(*it * 100.0f));
        if (it.isVoxelValue()) {
            acc.setValue(it.getCoord(), value);
        } else {
            CoordBBox bbox;
            it.getBoundingBox(bbox);
            for (Int32 x = bbox.min()[0]; x <= bbox.max()[0]; ++x)
                for (Int32 y = bbox.min()[1]; y <= bbox.max()[1]; ++y)
                    for (Int32 z = bbox.min()[2]; z <= bbox.max()[2]; ++z)
                        acc.setValueOff(Coord(x, y, z), value);
        }
    };
    auto serial = Int32Grid::create(-7);
    auto threaded = Int32Grid::create(-7);
    tools::transformValues(grid->cbeginValueOn(), *serial, op, false);
    tools::transformValues(grid->cbeginValueOn(), *threaded, op, true);
    expectVoxels(threaded->tree(), kRegion, [&](const Coord& ijk) {
        if (!model.isValueOn(ijk))
            return std::pair<Int32, bool>(-7, false);
        const Int32 value = Int32(std::lround(model.getValue(ijk) * 100.0f));
        const bool inTile = CoordBBox::createCube(Coord(-24, 8, -16), 8).isInside(ijk) ||
                            CoordBBox::createCube(Coord(16, -32, 0), 8).isInside(ijk);
        return std::pair<Int32, bool>(value, !inTile);
    });
    expectVoxels(serial->tree(), kRegion, [&](const Coord& ijk) {
        return std::pair<Int32, bool>(threaded->tree().getValue(ijk),
                                      threaded->tree().isValueOn(ijk));
    });
}

TEST(ValueTransformer, TransformValuesIntoAPopulatedGridKeepsWhatOpDoesNotWrite) {
    auto grid = FloatGrid::create(0.0f);
    grid->tree().setValueOn(Coord(-1, -2, -3), 4.0f);
    auto out = FloatGrid::create(0.0f);
    out->tree().setValueOn(Coord(50, 50, 50), 9.0f);
    out->tree().setValueOn(Coord(-1, -2, -3), 1.0f);
    tools::transformValues(grid->cbeginValueOn(), *out,
                           [](const auto& it, auto& acc) { acc.setValue(it.getCoord(), *it + 1); });
    EXPECT_EQ(out->tree().getValue(Coord(-1, -2, -3)), 5.0f);
    EXPECT_EQ(out->tree().getValue(Coord(50, 50, 50)), 9.0f);
    EXPECT_EQ(out->activeVoxelCount(), 2u);
}

TEST(ValueTransformer, AccessorHelpersCombineAndActivate) {
    FloatTree tree(1.0f);
    FloatTree::Accessor acc(tree);
    const Coord a(-5, 0, 3), b(7, -8, 9), c(0, 0, -1), d(100, -100, 3);
    tools::setValueOnMin(acc, a, 0.25f);
    tools::setValueOnMin(acc, a, 0.5f);
    tools::setValueOnMax(acc, b, 3.0f);
    tools::setValueOnMax(acc, b, 2.0f);
    tools::setValueOnSum(acc, c, 2.0f);
    tools::setValueOnSum(acc, c, 2.0f);
    tools::setValueOnMult(acc, d, 3.0f);
    tools::setValueOnMult(acc, d, 3.0f);
    EXPECT_EQ(tree.getValue(a), 0.25f);
    EXPECT_EQ(tree.getValue(b), 3.0f);
    EXPECT_EQ(tree.getValue(c), 5.0f);
    EXPECT_EQ(tree.getValue(d), 9.0f);
    EXPECT_EQ(tree.activeVoxelCount(), 4u);
    tools::setValueOnMax(acc, Coord(1, 1, 1), 0.0f);  // below the background: still activated
    EXPECT_TRUE(tree.isValueOn(Coord(1, 1, 1)));
    EXPECT_EQ(tree.getValue(Coord(1, 1, 1)), 1.0f);
}

}  // namespace
}  // namespace vdb
