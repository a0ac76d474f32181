// SPDX-License-Identifier: Apache-2.0
// Oracle: the analytic signed distance of the surface the input holds (a sphere, a torus, a
// Gaussian blob's level surface). levelSetRebuild must return a level set whose band voxels hold
// that distance (to the accuracy of the surface's mesh, a few hundredths of a voxel, plus the
// band's own rounding), active exactly within the band, with the flood-filled values beyond,
// whatever the input's band looked like.

#include <vdb/tools/LevelSetRebuild.h>
#include <vdb/vdb.h>

#include "AnalyticLevelSets.h"
#include "LevelSetTestUtil.h"
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace vdb::tools {
namespace {

/// Compares every voxel of `box` of `grid` (index space of `grid`) with the signed distance
/// `sdf` (in voxels of `grid`): band voxels within `tolerance` voxels, every voxel active
/// exactly when within the band (voxels within `tolerance` of its edge may go either way), and
/// the inactive values +-halfWidth voxels by the side of the surface.
::testing::AssertionResult matchesDistance(const FloatGrid& grid, const test::Sdf& sdf,
                                           const CoordBBox& box, double halfWidth,
                                           double tolerance) {
    const double dx = grid.voxelSize()[0];
    const auto acc = grid.getConstAccessor();
    size_t active = 0, failures = 0;
    std::ostringstream msg;
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk(i, j, k);
                const double d = test::sdfAt(sdf, ijk);
                float value = 0.0f;
                const bool on = acc.probeValue(ijk, value);
                const double v = double(value) / dx;
                std::string problem;
                if (std::abs(std::abs(d) - halfWidth) > tolerance &&
                    on != (std::abs(d) < halfWidth))
                    problem = on ? "active outside the band" : "inactive inside the band";
                else if (on && std::abs(v - d) > tolerance)
                    problem = "value off";
                else if (!on && std::abs(d) > tolerance && v != (d < 0 ? -halfWidth : halfWidth))
                    problem = "inactive value off";
                active += on;
                if (!problem.empty() && ++failures <= 5)
                    msg << "\n  " << ijk << ": " << problem << ", value " << v << " distance " << d;
            }
    if (active == 0)
        return ::testing::AssertionFailure() << "no active voxel";
    if (failures > 0)
        return ::testing::AssertionFailure() << failures << " voxels differ:" << msg.str();
    return ::testing::AssertionSuccess();
}

TEST(LevelSetRebuild, DistortedBandBecomesSignedDistances) {
    // Half the distance, in a band of one voxel: a level set no tool could march.
    auto grid = FloatGrid::create(0.5f);
    grid->setGridClass(GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    for (Int32 i = 0; i < 128; ++i)
        for (Int32 j = 0; j < 128; ++j)
            for (Int32 k = 0; k < 128; ++k) {
                const double d = test::kTorus(i, j, k);
                if (std::abs(d) < 1.0)
                    acc.setValue(Coord(i, j, k), float(0.5 * d));
            }
    signedFloodFill(grid->tree());
    const auto rebuilt = levelSetRebuild(*grid);
    EXPECT_EQ(rebuilt->getGridClass(), GRID_LEVEL_SET);
    EXPECT_FLOAT_EQ(rebuilt->background(), 3.0f);
    EXPECT_TRUE(matchesDistance(*rebuilt, test::kTorus, test::kBox128, 3.0, 0.05));
}

TEST(LevelSetRebuild, FogVolumeBecomesTheLevelSetOfItsSurface) {
    // A Gaussian blob exp(-r^2 / s^2): density 0.5 at r = s sqrt(ln 2).
    const double s = 24.0, radius = s * std::sqrt(std::log(2.0));
    auto fog = FloatGrid::create(0.0f);
    fog->setGridClass(GRID_FOG_VOLUME);
    fog->setTransform(math::Transform::createLinearTransform(0.5));
    auto acc = fog->getAccessor();
    for (Int32 i = -40; i <= 40; ++i)
        for (Int32 j = -40; j <= 40; ++j)
            for (Int32 k = -40; k <= 40; ++k) {
                const double r2 = double(i * i + j * j + k * k);
                if (r2 < 38.0 * 38.0)
                    acc.setValue(Coord(i, j, k), float(std::exp(-r2 / (s * s))));
            }
    const auto rebuilt = levelSetRebuild(*fog, 0.5f, 2.0f);
    EXPECT_EQ(rebuilt->getGridClass(), GRID_LEVEL_SET);
    EXPECT_DOUBLE_EQ(rebuilt->voxelSize()[0], 0.5);
    // Linear interpolation of an exponential moves the surface by a few hundredths of a voxel.
    EXPECT_TRUE(matchesDistance(*rebuilt, test::sphereSdf(0, 0, 0, radius),
                                CoordBBox(Coord(-30), Coord(30)), 2.0, 0.1));
    EXPECT_LT(rebuilt->tree().getValue(Coord(0)), 0.0f) << "the dense middle is inside";
}

TEST(LevelSetRebuild, NewTransformAndUnequalBands) {
    const auto grid = test::levelSetOf(test::kSphere, test::kBox128);
    // Voxels twice as large, moved by a quarter voxel of the result.
    auto xform = math::Transform::createLinearTransform(2.0);
    xform->postTranslate(Vec3d(0.5, 0.0, -0.5));
    const auto rebuilt = levelSetRebuild(*grid, 0.0f, 2.0f, 4.0f, xform.get());
    EXPECT_DOUBLE_EQ(rebuilt->voxelSize()[0], 2.0);
    EXPECT_FLOAT_EQ(rebuilt->background(), 4.0f);
    // The sphere in the new index space: centre (63.3 - 0.5, 64.1, 62.7 + 0.5) / 2, radius 20.
    const test::Sdf moved = test::sphereSdf(31.4, 32.05, 31.6, 20.0);
    size_t active = 0;
    for (auto it = rebuilt->cbeginValueOn(); it; ++it, ++active) {
        const double d = test::sdfAt(moved, it.getCoord());
        ASSERT_NEAR(*it / 2.0, d, 0.05) << it.getCoord();
        ASSERT_TRUE(d < 2.0 + 0.05 && d > -4.0 - 0.05) << it.getCoord();
    }
    EXPECT_GT(active, 10000u);
}

TEST(LevelSetRebuild, EmptyGridsAndBadArguments) {
    const auto empty = levelSetRebuild(*FloatGrid::create(1.0f));
    EXPECT_TRUE(empty->empty());
    const auto grid = test::levelSetOf(test::kSphere, test::kBox128);
    EXPECT_THROW(levelSetRebuild(*grid, 0.0f, 0.5f), ValueError);
    EXPECT_THROW(levelSetRebuild(*grid, std::numeric_limits<float>::quiet_NaN()), ValueError);
    const auto frustum =
        math::Transform::createFrustumTransform(BBoxd(Vec3d(0.0), Vec3d(127.0)), 0.5, 10.0, 1.0);
    EXPECT_THROW(levelSetRebuild(*grid, 0.0f, 3.0f, frustum.get()), ValueError);
    // Doubles too.
    const auto d = test::levelSetOf<DoubleGrid>(test::kSphere, test::kBox128);
    const auto rebuilt = levelSetRebuild(*d);
    EXPECT_GT(rebuilt->activeVoxelCount(), 10000u);
    for (auto it = rebuilt->cbeginValueOn(); it; ++it)
        ASSERT_NEAR(*it, test::sdfAt(test::kSphere, it.getCoord()), 0.05);
}

}  // namespace
}  // namespace vdb::tools
