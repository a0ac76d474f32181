// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels fed the same writes
// as the grid, and the clip rules written voxel by voxel: a voxel keeps its value and state
// when it is a candidate (active, or an inactive negative value of a level set) and its
// membership of the region (index box from the floors of the mapped box corners; the mask
// voxel holding its center; the frustum's index box holding its center) equals keepInterior;
// otherwise it reads as the inactive background. Every voxel of a box around the contents is
// checked, tiles included.

#include <vdb/Grid.h>
#include <vdb/math/Transform.h>
#include <vdb/tools/Clip.h>
#include <vdb/tree/TreeConfigs.h>

#include "GridContents.h"
#include "VoxelChecks.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

namespace vdb {
namespace {

using test::expectVoxels;
using test::SparseVolumeModel;

/// Random active and inactive voxels in [-44, 44]^3, and leaf-sized tiles (active and
/// inactive, positive and negative), written to both `grid` and `model`.
template <typename GridT>
void populate(GridT& grid, SparseVolumeModel<float>& model, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-44, 44);
    std::uniform_real_distribution<float> v(-5.0f, 5.0f);
    auto& tree = grid.tree();
    for (int n = 0; n < 600; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        test::setBoth(tree, model, ijk, v(rng), n % 3 != 0);
    }
    const auto tile = [&](const Coord& origin, float value, bool active) {
        test::fillBoth(tree, model, CoordBBox::createCube(origin, 8), value, active);
    };
    tile(Coord(-24, 8, -16), 2.5f, true);
    tile(Coord(16, -32, 0), -1.5f, false);
    tile(Coord(0, 0, -40), -3.0f, true);
    tile(Coord(-40, -40, 32), 4.0f, false);
    ASSERT_GT(tree.activeTileCount(), 0u);
}

const CoordBBox kRegion(Coord(-50), Coord(50));

/// The oracle of the box and mask clips: candidates inside (or outside) the region keep
/// their value and state.
std::pair<float, bool> expectedClip(const SparseVolumeModel<float>& model, bool levelSet,
                                    bool inRegion, bool keepInterior, const Coord& ijk) {
    const float value = model.getValue(ijk);
    const bool active = model.isValueOn(ijk);
    const bool candidate = active || (levelSet && value < 0.0f);
    if (candidate && inRegion == keepInterior)
        return {value, active};
    return {model.background(), false};
}

class ClipBox : public ::testing::TestWithParam<std::tuple<bool, bool>> {};

TEST_P(ClipBox, EveryVoxelMatchesTheRuleOfTheIndexBox) {
    const auto [levelSet, keepInterior] = GetParam();
    auto grid = FloatGrid::create(3.0f);
    grid->setTransform(math::Transform::createLinearTransform(0.5));
    grid->transform().postTranslate(Vec3d(0.1, -0.2, 0.3));
    if (levelSet)
        grid->setGridClass(GRID_LEVEL_SET);
    SparseVolumeModel<float> model(3.0f);
    populate(*grid, model, 7);

    const BBoxd box(Vec3d(-7.3, -11.0, -2.45), Vec3d(5.2, 3.9, 13.0));
    const auto result = tools::clip(*grid, box, keepInterior);
    EXPECT_EQ(result->background(), 3.0f);
    EXPECT_EQ(result->getGridClass(), levelSet ? GRID_LEVEL_SET : GRID_UNKNOWN);
    // Index box: floor((world - translation) / voxel size) of the two corners.
    const auto lo = [&](int a) {
        return std::floor((box.min()[a] - (a == 0 ? 0.1 : a == 1 ? -0.2 : 0.3)) / 0.5);
    };
    const auto hi = [&](int a) {
        return std::floor((box.max()[a] - (a == 0 ? 0.1 : a == 1 ? -0.2 : 0.3)) / 0.5);
    };
    expectVoxels(result->tree(), kRegion, [&](const Coord& ijk) {
        bool in = true;
        for (int a = 0; a < 3; ++a)
            in = in && ijk[a] >= lo(a) && ijk[a] <= hi(a);
        return expectedClip(model, levelSet, in, keepInterior, ijk);
    });
    EXPECT_TRUE(
        test::sameContents(result->tree(), tools::clip(*grid, box, keepInterior, false)->tree()));
}

INSTANTIATE_TEST_SUITE_P(Clip, ClipBox, ::testing::Combine(::testing::Bool(), ::testing::Bool()));

TEST(Clip, BoxCutsAPieceOutOfARootTile) {
    auto grid = FloatGrid::create(0.0f);
    grid->tree().addTile(3, Coord(0), 7.0f, true);
    const BBoxd box(Vec3d(10.2), Vec3d(20.7));
    const auto inside = tools::clip(*grid, box);
    EXPECT_EQ(inside->activeVoxelCount(), 11u * 11u * 11u);
    EXPECT_EQ(inside->tree().getValue(Coord(10, 15, 20)), 7.0f);
    EXPECT_FALSE(inside->tree().isValueOn(Coord(9, 15, 20)));
    const auto outside = tools::clip(*grid, box, false);
    EXPECT_EQ(outside->activeVoxelCount(), Index64(4096) * 4096 * 4096 - 11 * 11 * 11);
    EXPECT_FALSE(outside->tree().isValueOn(Coord(20, 20, 20)));
    EXPECT_TRUE(outside->tree().isValueOn(Coord(21, 20, 20)));
}

TEST(Clip, EmptyBoxKeepsNothingOrEverything) {
    auto grid = FloatGrid::create(1.0f);
    SparseVolumeModel<float> model(1.0f);
    populate(*grid, model, 11);
    const BBoxd empty(Vec3d(1.0), Vec3d(-1.0));
    EXPECT_EQ(tools::clip(*grid, empty)->activeVoxelCount(), 0u);
    EXPECT_EQ(tools::clip(*grid, empty, false)->activeVoxelCount(), grid->activeVoxelCount());
    EXPECT_THROW(tools::clip(*grid, BBoxd(Vec3d(0.0), Vec3d(INFINITY))), ValueError);
}

TEST(Clip, HugeBoxKeepsEveryCandidate) {
    auto grid = FloatGrid::create(1.0f);
    SparseVolumeModel<float> model(1.0f);
    populate(*grid, model, 12);
    const auto result = tools::clip(*grid, BBoxd(Vec3d(-1e300), Vec3d(1e300)));
    expectVoxels(result->tree(), kRegion,
                 [&](const Coord& ijk) { return expectedClip(model, false, true, true, ijk); });
}

class ClipMask : public ::testing::TestWithParam<std::tuple<bool, bool>> {};

TEST_P(ClipMask, EveryVoxelMatchesTheMaskVoxelHoldingItsCenter) {
    const auto [sameTransform, keepInterior] = GetParam();
    auto grid = FloatGrid::create(-2.0f);
    grid->setTransform(math::Transform::createLinearTransform(0.5));
    SparseVolumeModel<float> model(-2.0f);
    populate(*grid, model, 21);

    // A bool mask: scattered voxels, a blob and a tile, on a coarser shifted transform.
    auto mask = BoolGrid::create(false);
    if (!sameTransform) {
        mask->setTransform(math::Transform::createLinearTransform(0.73));
        mask->transform().postTranslate(Vec3d(0.111, -0.237, 0.05));
    } else {
        mask->setTransform(grid->transform().copy());
    }
    std::mt19937 rng(5);
    std::uniform_int_distribution<Int32> c(-30, 30);
    for (int n = 0; n < 400; ++n)
        mask->tree().setValueOn(Coord(c(rng), c(rng), c(rng)), true);
    mask->tree().fill(CoordBBox(Coord(-5, -6, -7), Coord(9, 4, 3)), true, true);
    mask->tree().fill(CoordBBox::createCube(Coord(-16, 0, 8), 8), false, true);

    const auto result = tools::clip(*grid, *mask, keepInterior);
    expectVoxels(result->tree(), kRegion, [&](const Coord& ijk) {
        const Vec3d p = mask->transform().worldToIndex(grid->transform().indexToWorld(Vec3d(ijk)));
        const Coord m(Int32(std::floor(p[0])), Int32(std::floor(p[1])), Int32(std::floor(p[2])));
        return expectedClip(model, false, mask->tree().isValueOn(m), keepInterior, ijk);
    });
    EXPECT_TRUE(
        test::sameContents(result->tree(), tools::clip(*grid, *mask, keepInterior, false)->tree()));
}

INSTANTIATE_TEST_SUITE_P(Clip, ClipMask, ::testing::Combine(::testing::Bool(), ::testing::Bool()));

TEST(Clip, FloatMaskUsesItsActiveVoxelsWhateverTheirValues) {
    auto grid = FloatGrid::create(0.0f);
    grid->tree().fill(CoordBBox(Coord(-10), Coord(10)), 1.0f, true);
    auto mask = FloatGrid::create(0.0f);
    mask->tree().setValueOn(Coord(-3, 2, 1), 0.0f);
    mask->tree().setValueOn(Coord(4, 4, 4), -9.0f);
    mask->tree().setValueOff(Coord(5, 5, 5), 9.0f);
    const auto result = tools::clip(*grid, *mask);
    EXPECT_EQ(result->activeVoxelCount(), 2u);
    EXPECT_TRUE(result->tree().isValueOn(Coord(-3, 2, 1)));
    EXPECT_TRUE(result->tree().isValueOn(Coord(4, 4, 4)));
}

class ClipFrustum : public ::testing::TestWithParam<bool> {};

TEST_P(ClipFrustum, EveryVoxelMatchesTheFrustumHoldingItsCenter) {
    const bool keepInterior = GetParam();
    auto grid = FloatGrid::create(3.0f);
    grid->setGridClass(GRID_LEVEL_SET);
    SparseVolumeModel<float> model(3.0f);
    populate(*grid, model, 31);
    auto frustum = math::Transform::createFrustumTransform(
        BBoxd(Vec3d(0.0), Vec3d(20.0, 16.0, 12.0)), 0.6, 1.5, 40.0);
    frustum->postRotate(0.3, math::Axis::Y);
    frustum->postTranslate(Vec3d(3.3, -2.1, -20.7));
    const BBoxd fbox = frustum->mapParams().frustumBBox;

    const auto result = tools::clip(*grid, *frustum, keepInterior);
    EXPECT_EQ(result->getGridClass(), GRID_UNKNOWN);
    int inside = 0;
    expectVoxels(result->tree(), kRegion, [&](const Coord& ijk) {
        const Vec3d p = frustum->worldToIndex(grid->transform().indexToWorld(Vec3d(ijk)));
        bool in = true;
        for (int a = 0; a < 3; ++a)
            in = in && p[a] > fbox.min()[a] - 1e-15 && p[a] < fbox.max()[a] + 1e-15;
        inside += in;
        if (in == keepInterior)
            return std::pair<float, bool>(model.getValue(ijk), model.isValueOn(ijk));
        return std::pair<float, bool>(3.0f, false);
    });
    // The frustum cuts the contents: some voxels are inside, most are not.
    EXPECT_GT(inside, 1000);
    EXPECT_LT(inside, int(kRegion.volume() / 2));
    EXPECT_TRUE(test::sameContents(result->tree(),
                                   tools::clip(*grid, *frustum, keepInterior, false)->tree()));
}

INSTANTIATE_TEST_SUITE_P(Clip, ClipFrustum, ::testing::Bool());

TEST(Clip, FrustumClipRefusesALinearTransform) {
    auto grid = FloatGrid::create(0.0f);
    EXPECT_THROW(tools::clip(*grid, *math::Transform::createLinearTransform(1.0)), ValueError);
}

TEST(Clip, LevelTwoTilesOfASmallTreeAreClippedVoxelExactly) {
    using TreeT = tree::MapTree432<float>;
    Grid<TreeT>::Ptr grid = Grid<TreeT>::create(0.5f);
    SparseVolumeModel<float> model(0.5f);
    const auto fill = [&](const CoordBBox& box, float value, bool active) {
        grid->tree().fill(box, value, active);
        model.fill(box, value, active);
    };
    fill(CoordBBox::createCube(Coord(-32, 0, -32), 32), 6.0f, true);  // a level-2 tile
    fill(CoordBBox::createCube(Coord(0, -4, 0), 4), -2.0f, true);     // a level-1 tile
    fill(CoordBBox(Coord(5, 5, 5), Coord(9, 7, 6)), 1.0f, true);      // voxels
    ASSERT_GT(grid->tree().activeTileCount(), 1u);
    const BBoxd box(Vec3d(-20.5, 3.0, -40.0), Vec3d(6.0, 40.0, 5.5));
    for (bool keepInterior : {true, false}) {
        const auto result = tools::clip(*grid, box, keepInterior);
        expectVoxels(result->tree(), CoordBBox(Coord(-40), Coord(40)), [&](const Coord& ijk) {
            bool in = true;
            for (int a = 0; a < 3; ++a)
                in = in && ijk[a] >= std::floor(box.min()[a]) && ijk[a] <= std::floor(box.max()[a]);
            return expectedClip(model, false, in, keepInterior, ijk);
        });
    }
}

}  // namespace
}  // namespace vdb
