// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h) fed the same writes as the tree, with the
// rule applied voxel by voxel: activate() turns on every inactive voxel whose value is within
// the tolerance of the target (exactly equal for tolerance 0), deactivate() turns off every
// active one; values never change. Every voxel of a box around the contents is checked,
// including the voxels of tiles; interiorMask is checked the same way against the sign of a
// level set or the active states of a fog volume.

#include <vdb/Grid.h>
#include <vdb/tools/Activate.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Mask.h>
#include <vdb/tree/TreeConfigs.h>

#include "GridContents.h"
#include "VoxelChecks.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vdb {
namespace {

using test::expectVoxels;
using test::SparseVolumeModel;

/// Voxels and tiles in [-40, 40]^3 whose values come from a small set, so that many match.
void populate(FloatTree& tree, SparseVolumeModel<float>& model, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-40, 40);
    const float values[] = {0.0f, 1.0f, 1.0005f, 0.9991f, 2.0f, -1.0f};
    for (int n = 0; n < 2000; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        const float value = values[rng() % 6];
        test::setBoth(tree, model, ijk, value, rng() % 2 == 0);
    }
    const auto tile = [&](const Coord& origin, float value, bool active) {
        test::fillBoth(tree, model, CoordBBox::createCube(origin, 8), value, active);
    };
    tile(Coord(-24, 8, -16), 1.0f, false);
    tile(Coord(16, -32, 0), 1.0f, true);
    tile(Coord(0, 0, -40), 1.0004f, false);
    tile(Coord(-40, -40, 32), 2.0f, false);
}

const CoordBBox kRegion(Coord(-44), Coord(44));

class ActivateByValue : public ::testing::TestWithParam<std::tuple<bool, float>> {};

TEST_P(ActivateByValue, EveryVoxelMatchesTheModel) {
    const auto [on, tolerance] = GetParam();
    FloatTree tree(0.0f);
    SparseVolumeModel<float> model(0.0f);
    populate(tree, model, 3);
    FloatTree serial(tree);
    if (on) {
        tools::activate(tree, 1.0f, tolerance);
        tools::activate(serial, 1.0f, tolerance, false);
    } else {
        tools::deactivate(tree, 1.0f, tolerance);
        tools::deactivate(serial, 1.0f, tolerance, false);
    }
    expectVoxels(tree, kRegion, [&](const Coord& ijk) {
        const float value = model.getValue(ijk);
        const bool match = tolerance == 0.0f ? value == 1.0f : std::abs(value - 1.0f) <= tolerance;
        const bool active = model.isValueOn(ijk);
        return std::pair<float, bool>(value, match ? on : active);
    });
    EXPECT_TRUE(test::sameContents(tree, serial));
}

INSTANTIATE_TEST_SUITE_P(Activate, ActivateByValue,
                         ::testing::Combine(::testing::Bool(), ::testing::Values(0.0f, 1e-3f)));

TEST(Activate, BackgroundValueActivatesStoredBackgroundTilesAndVoxelsOnly) {
    FloatTree tree(0.0f);
    tree.setValueOff(Coord(1, 2, 3), 5.0f);  // a leaf of background voxels around one value
    tools::activate(tree, 0.0f);
    // Every background voxel of the leaf and every background tile of the nodes above it.
    EXPECT_FALSE(tree.isValueOn(Coord(1, 2, 3)));
    EXPECT_TRUE(tree.isValueOn(Coord(0, 0, 0)));
    EXPECT_TRUE(tree.isValueOn(Coord(100, 100, 100)));  // a tile of the upper internal node
    EXPECT_FALSE(tree.isValueOn(Coord(5000, 0, 0)));    // no root entry: nothing to activate
}

TEST(Activate, RootTilesAndMaskTreesFollowTheRule) {
    FloatTree tree(0.0f);
    tree.addTile(3, Coord(4096, 0, 0), 2.0f, false);
    tree.addTile(3, Coord(-4096, 0, 0), 2.0f, true);
    tools::activate(tree, 2.0f);
    EXPECT_TRUE(tree.isValueOn(Coord(4096, 0, 0)));
    tools::deactivate(tree, 2.0f);
    EXPECT_FALSE(tree.isValueOn(Coord(-4096, 0, 0)));
    EXPECT_EQ(tree.activeVoxelCount(), 0u);

    MaskTree mask(false);
    mask.setValueOn(Coord(3, 3, 3));
    mask.addTile(1, Coord(16, 0, 0), true, true);
    tools::deactivate(mask, true);
    EXPECT_EQ(mask.activeVoxelCount(), 0u);
    EXPECT_FALSE(mask.getValue(Coord(17, 1, 1)));  // a mask tile's value is its state
}

TEST(Activate, GridFormWorksOnTheTree) {
    auto grid = Int32Grid::create(0);
    grid->tree().setValueOff(Coord(-3, -4, -5), 9);
    grid->tree().setValueOff(Coord(-3, -4, -6), 10);
    tools::activate(*grid, Int32(9));
    EXPECT_TRUE(grid->tree().isValueOn(Coord(-3, -4, -5)));
    EXPECT_FALSE(grid->tree().isValueOn(Coord(-3, -4, -6)));
    tools::activate(*grid, Int32(10), Int32(1));
    EXPECT_TRUE(grid->tree().isValueOn(Coord(-3, -4, -6)));
}

TEST(InteriorMask, LevelSetGivesTheVoxelsBelowTheIsovalue) {
    auto sdf = tools::createLevelSetSphere<FloatGrid>(6.0f, Vec3f(0.5f, -0.25f, 1.0f), 1.0f, 3.0f);
    const auto mask = tools::interiorMask(*sdf, 0.5);
    EXPECT_TRUE(mask->transform() == sdf->transform());
    // Inside the band the sign decides; deep inside, the enclosed inside tiles count too.
    expectVoxels(mask->tree(), CoordBBox(Coord(-10), Coord(10)), [&](const Coord& ijk) {
        const bool inside = sdf->tree().getValue(ijk) < 0.5f;
        return std::pair<bool, bool>(inside, inside);
    });
    EXPECT_TRUE(mask->tree().isValueOn(Coord(0, 0, 1)));
    EXPECT_FALSE(mask->tree().isValueOn(Coord(8, 0, 1)));
}

TEST(InteriorMask, FogVolumeGivesItsActiveTopology) {
    auto fog = FloatGrid::create(0.0f);
    SparseVolumeModel<float> model(0.0f);
    populate(fog->tree(), model, 9);
    const auto mask = tools::interiorMask(*fog, 0.5);
    // OpenVDB's rule: the topology is copied, the values stay the background (false).
    expectVoxels(mask->tree(), kRegion, [&](const Coord& ijk) {
        return std::pair<bool, bool>(false, model.isValueOn(ijk));
    });
    auto boolGrid = BoolGrid::create(false);
    boolGrid->tree().setValueOff(Coord(1, 1, 1), true);
    EXPECT_TRUE(tools::interiorMask(*boolGrid)->tree().getValue(Coord(1, 1, 1)));
}

}  // namespace
}  // namespace vdb
