// SPDX-License-Identifier: Apache-2.0
// Oracles: brute force over boxes of voxels and analytic shapes. Every voxel of a box around
// the shapes is checked against the rule the tool implements (fog ramp, interior, isosurface
// crossing, enclosed region of a hollow shell); segmentations are checked against the shapes
// they were made from.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetUtil.h>

#include "ToolboxTestUtil.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace vdb {
namespace {

using test::forEachVoxel;

FloatGrid::Ptr sphere(double radius, const Vec3d& c, double dx = 0.1) {
    return tools::createLevelSetSphere<FloatGrid>(radius, c, dx);
}

TEST(LevelSetUtil, SdfToFogVolumeRampsTheInsideHalfOfTheBand) {
    auto grid = sphere(2.0, Vec3d(0.0));
    auto sdf = grid->deepCopy();
    const float bg = grid->background();
    tools::sdfToFogVolume(*grid);
    EXPECT_EQ(grid->getGridClass(), GRID_FOG_VOLUME);
    EXPECT_EQ(grid->background(), 0.0f);
    auto acc = sdf->getConstAccessor();
    forEachVoxel(CoordBBox(Coord(-25), Coord(25)), [&](const Coord& ijk) {
        const float d = acc.getValue(ijk);
        const float want = d > 0.0f ? 0.0f : std::min(d / -bg, 1.0f);
        ASSERT_NEAR(grid->tree().getValue(ijk), want, 1e-6f) << ijk;
        ASSERT_EQ(grid->tree().isValueOn(ijk), want > 0.0f) << ijk;
    });
    // A shorter cutoff: density 1 from that depth inwards.
    auto short_ = sdf->deepCopy();
    tools::sdfToFogVolume(*short_, 0.1f);
    forEachVoxel(CoordBBox(Coord(-25), Coord(25)), [&](const Coord& ijk) {
        const float d = acc.getValue(ijk);
        const float want = d > 0.0f ? 0.0f : std::min(d / -0.1f, 1.0f);
        ASSERT_NEAR(short_->tree().getValue(ijk), want, 1e-6f) << ijk;
    });
}

TEST(LevelSetUtil, InteriorMaskHoldsTheVoxelsBelowTheIsovalue) {
    auto grid = sphere(2.0, Vec3d(0.3, 0.0, -0.2));
    for (const float iso : {0.0f, -0.15f, 0.1f}) {
        auto mask = tools::sdfInteriorMask(*grid, iso);
        EXPECT_TRUE(mask->transform() == grid->transform());
        auto acc = grid->getConstAccessor();
        forEachVoxel(CoordBBox(Coord(-30), Coord(30)), [&](const Coord& ijk) {
            const bool inside = acc.getValue(ijk) < iso;
            ASSERT_EQ(mask->tree().isValueOn(ijk), inside) << ijk;
            ASSERT_EQ(mask->tree().getValue(ijk), inside) << ijk;
        });
    }
}

TEST(LevelSetUtil, IsosurfaceMaskHoldsTheCrossingVoxels) {
    auto grid = sphere(1.5, Vec3d(0.0));
    auto mask = tools::extractIsosurfaceMask(*grid, 0.0f);
    auto acc = grid->getConstAccessor();
    forEachVoxel(CoordBBox(Coord(-20), Coord(20)), [&](const Coord& ijk) {
        bool crossing = false;
        const bool under = acc.getValue(ijk) < 0.0f;
        for (int a = 0; a < 3; ++a)
            for (int s = -1; s <= 1; s += 2) {
                Coord nb = ijk;
                nb[size_t(a)] += s;
                crossing = crossing || (acc.getValue(nb) < 0.0f) != under;
            }
        ASSERT_EQ(mask->tree().isValueOn(ijk), crossing && acc.isValueOn(ijk)) << ijk;
    });
}

TEST(LevelSetUtil, EnclosedRegionFillsTheCavityOfAHollowShell) {
    // A shell between radii 5 and 10 voxels: its cavity is enclosed.
    const auto inner = test::sphereSdf(0, 0, 0, 5), outer = test::sphereSdf(0, 0, 0, 10);
    const test::Sdf shell = [&](double x, double y, double z) {
        return std::max(outer(x, y, z), -inner(x, y, z));
    };
    auto grid = test::levelSetFromSdf(shell, CoordBBox(Coord(-16), Coord(16)), 1.0);
    auto region = tools::extractEnclosedRegion(*grid);
    auto interior = tools::sdfInteriorMask(*grid);
    forEachVoxel(CoordBBox(Coord(-16), Coord(16)), [&](const Coord& ijk) {
        ASSERT_EQ(region->tree().isValueOn(ijk), test::sdfAt(outer, ijk) < 0.0) << ijk;
        ASSERT_EQ(interior->tree().isValueOn(ijk), test::sdfAt(shell, ijk) < 0.0) << ijk;
    });
    // With a fill mask that misses the cavity's centre, the cavity is not enclosed.
    BoolTree fill(false);
    fill.fill(CoordBBox(Coord(-16), Coord(16)), true, true);
    fill.setValueOff(Coord(0));
    auto partial = tools::extractEnclosedRegion(*grid, 0.0f, &fill);
    forEachVoxel(CoordBBox(Coord(-16), Coord(16)), [&](const Coord& ijk) {
        ASSERT_EQ(partial->tree().isValueOn(ijk), test::sdfAt(shell, ijk) < 0.0) << ijk;
    });
    // A plain sphere encloses nothing more than its inside.
    auto ball = sphere(1.2, Vec3d(0.0));
    auto a = tools::extractEnclosedRegion(*ball), b = tools::sdfInteriorMask(*ball);
    EXPECT_EQ(a->activeVoxelCount(), b->activeVoxelCount());
}

TEST(LevelSetUtil, SegmentActiveVoxelsSplitsDisjointPartsLargestFirst) {
    auto grid = FloatGrid::create(-1.0f);
    grid->setName("parts");
    grid->tree().fill(CoordBBox(Coord(0), Coord(9)), 1.0f, true);                // 1000 voxels
    grid->tree().fill(CoordBBox(Coord(20, 0, 0), Coord(24, 4, 4)), 2.0f, true);  // 125
    grid->tree().fill(CoordBBox::createCube(Coord(128, 0, 0), 8), 3.0f, true);   // a leaf tile
    grid->tree().setValue(Coord(136, 0, 0), 4.0f);      // touches the tile: same part (513)
    grid->tree().setValueOff(Coord(30, 30, 30), 5.0f);  // inactive: no part
    std::vector<FloatGrid::Ptr> parts;
    tools::segmentActiveVoxels(*grid, parts);
    ASSERT_EQ(parts.size(), 3u);
    EXPECT_EQ(parts[0]->activeVoxelCount(), 1000u);
    EXPECT_EQ(parts[1]->activeVoxelCount(), 513u);
    EXPECT_EQ(parts[2]->activeVoxelCount(), 125u);
    EXPECT_EQ(parts[1]->tree().getValue(Coord(130, 1, 1)), 3.0f);
    EXPECT_EQ(parts[1]->tree().getValue(Coord(136, 0, 0)), 4.0f);
    EXPECT_EQ(parts[2]->tree().getValue(Coord(22, 2, 2)), 2.0f);
    EXPECT_EQ(parts[0]->getName(), "parts");
    EXPECT_EQ(parts[0]->background(), -1.0f);
    std::vector<BoolGrid::Ptr> masks;
    tools::extractActiveVoxelSegmentMasks(*grid, masks);
    ASSERT_EQ(masks.size(), 3u);
    EXPECT_EQ(masks[2]->activeVoxelCount(), 125u);
    // One part: a copy; none: one empty grid.
    std::vector<FloatGrid::Ptr> one, none;
    tools::segmentActiveVoxels(*sphere(1.0, Vec3d(0.0)), one);
    EXPECT_EQ(one.size(), 1u);
    tools::segmentActiveVoxels(*FloatGrid::create(2.0f), none);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_TRUE(none[0]->empty());
}

TEST(LevelSetUtil, SegmentSdfSeparatesTwoSpheres) {
    auto a = sphere(1.0, Vec3d(-1.5, 0.0, 0.0)), b = sphere(0.8, Vec3d(1.5, 0.0, 0.0));
    auto both = a->deepCopy();
    auto bCopy = b->deepCopy();
    tools::csgUnion(both->tree(), bCopy->tree());
    std::vector<FloatGrid::Ptr> parts;
    tools::segmentSDF(*both, parts);
    ASSERT_EQ(parts.size(), 2u);
    // Largest first: the sphere of radius 1, then 0.8; each only its own surface.
    const auto check = [](const FloatGrid& part, const FloatGrid& alone, const Vec3d& c,
                          const Vec3d& other) {
        EXPECT_EQ(part.activeVoxelCount(), alone.activeVoxelCount());
        EXPECT_LT(part.tree().getValue(part.transform().worldToIndexCellCentered(c)), 0.0f);
        EXPECT_GT(part.tree().getValue(part.transform().worldToIndexCellCentered(other)), 0.0f);
    };
    check(*parts[0], *a, Vec3d(-1.5, 0, 0), Vec3d(1.5, 0, 0));
    check(*parts[1], *b, Vec3d(1.5, 0, 0), Vec3d(-1.5, 0, 0));
}

}  // namespace
}  // namespace vdb
