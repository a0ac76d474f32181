// SPDX-License-Identifier: Apache-2.0
// Oracles: the analytic signed distance of a sphere (renormalisation must bring distorted
// values back to it, with |grad phi| ~ 1 measured by central differences, an operator the
// tracker does not use), and brute-force walks of the tree for the rebuild (every kept voxel
// lies in the band, every voxel of the band is kept, no node without active values).

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Stencils.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetTracker.h>
#include <vdb/tools/Morphology.h>

#include "AdvectTestUtil.h"
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <set>
#include <tuple>

namespace vdb {
namespace {

constexpr float kRadius = 0.3f;
constexpr float kVoxel = 0.02f;
const Vec3f kCenter(0.1f, -0.05f, 0.2f);

FloatGrid::Ptr makeSphere(float halfWidth = 3.0f) {
    return tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, halfWidth);
}

double exactDistance(const FloatGrid& grid, const Coord& ijk) {
    return test::sphereDistance(grid.indexToWorld(Vec3d(ijk)), Vec3d(kCenter), double(kRadius));
}

/// Multiplies every active value by `factor(world position)`.
void distort(FloatGrid& grid, const std::function<double(const Vec3d&)>& factor) {
    for (auto it = grid.beginValueOn(); it; ++it)
        it.setValue(float(*it * factor(grid.indexToWorld(Vec3d(it.getCoord())))));
}

/// Checks |grad phi| ~ 1 (central differences) and phi ~ the exact distance at the active
/// voxels within `reach` voxels of the interface.
void expectDistanceNearInterface(const FloatGrid& grid, double reach, double gradTol,
                                 double valueTol) {
    math::SevenPointStencil<FloatGrid> s(grid);
    int checked = 0;
    double worstGrad = 0.0, worstValue = 0.0;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const double d = exactDistance(grid, it.getCoord());
        if (std::abs(d) > reach * kVoxel)
            continue;
        s.moveTo(it);
        worstGrad = std::max(worstGrad, std::abs(double(s.gradient().length()) - 1.0));
        worstValue = std::max(worstValue, std::abs(double(*it) - d) / kVoxel);
        ++checked;
    }
    EXPECT_GT(checked, 1000);
    EXPECT_LT(worstGrad, gradTol);
    EXPECT_LT(worstValue, valueTol);
}

TEST(LevelSetTracker, NormalizeRestoresADistanceScaledByTwo) {
    auto grid = makeSphere();
    distort(*grid, [](const Vec3d&) { return 2.0; });
    tools::LevelSetTracker<FloatGrid> tracker(*grid);
    tracker.setNormCount(12);
    tracker.normalize();
    expectDistanceNearInterface(*grid, 1.5, 0.1, 0.05);
}

TEST(LevelSetTracker, NormalizeRemovesASmoothBumpWithEveryScheme) {
    for (auto spatial : {math::FIRST_BIAS, math::HJWENO5_BIAS}) {
        for (auto temporal : {math::TVD_RK1, math::TVD_RK2, math::TVD_RK3}) {
            SCOPED_TRACE(std::string(math::biasedGradientSchemeToString(spatial)) + ", " +
                         std::string(math::temporalIntegrationSchemeToString(temporal)));
            auto grid = makeSphere();
            distort(*grid, [](const Vec3d& p) {
                return 1.0 + 0.6 * std::sin(8.0 * p[0]) * std::cos(6.0 * p[1]);
            });
            tools::LevelSetTracker<FloatGrid> tracker(*grid);
            tracker.setSpatialScheme(spatial);
            tracker.setTemporalScheme(temporal);
            tracker.setNormCount(12);
            tracker.normalize();
            // First order smears the interface a little more.
            const double tol = spatial == math::FIRST_BIAS ? 0.15 : 0.06;
            expectDistanceNearInterface(*grid, 1.5, 2 * tol, tol);
        }
    }
}

TEST(LevelSetTracker, NormalizeLeavesATrueDistanceAlmostUnchanged) {
    auto grid = makeSphere();
    auto before = grid->deepCopy();
    tools::LevelSetTracker<FloatGrid> tracker(*grid);
    tracker.normalize();
    auto acc = before->getConstAccessor();
    double worst = 0.0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        if (std::abs(exactDistance(*grid, it.getCoord())) < 2.0 * kVoxel)
            worst = std::max(worst, double(std::abs(*it - acc.getValue(it.getCoord()))));
    }
    EXPECT_LT(worst, 0.01 * kVoxel);
    EXPECT_EQ(grid->activeVoxelCount(), before->activeVoxelCount());
}

TEST(LevelSetTracker, TrackKeepsExactlyTheVoxelsOfTheBandAndNoEmptyNodes) {
    for (float halfWidth : {3.0f, 5.0f}) {
        SCOPED_TRACE(halfWidth);
        // Values stretched by 1.4: after the rebuild's renormalisation some lie beyond the
        // half width and must go.
        auto grid = makeSphere(halfWidth);
        distort(*grid, [](const Vec3d&) { return 1.4; });
        const float gamma = grid->background();

        // Expected: dilate and normalize a copy the same way, keep |value| < background.
        auto expected = grid->deepCopy();
        {
            tools::LevelSetTracker<FloatGrid> t(*expected);
            t.dilate(1);
            t.normalize();
        }
        tools::LevelSetTracker<FloatGrid> tracker(*grid);
        EXPECT_EQ(tracker.getHalfWidth(), halfWidth);
        tracker.track();

        auto acc = grid->getConstAccessor();
        Index64 expectedCount = 0;
        for (auto it = expected->cbeginValueOn(); it; ++it) {
            const bool inBand = std::abs(*it) < gamma;
            expectedCount += inBand;
            ASSERT_EQ(acc.isValueOn(it.getCoord()), inBand) << it.getCoord() << " " << *it;
            if (inBand) {
                ASSERT_TRUE(test::sameBits(acc.getValue(it.getCoord()), *it)) << it.getCoord();
            }
        }
        EXPECT_EQ(grid->activeVoxelCount(), expectedCount);
        // Every leaf holds an active voxel; inactive values are exactly -+background with the
        // sign of the exact distance (the sphere is far from any ambiguity there).
        for (const auto& leaf : grid->tree().leaves()) {
            ASSERT_FALSE(leaf.isEmpty()) << "empty leaf at " << leaf.origin();
            for (auto it = leaf.cbeginValueOff(); it; ++it) {
                const double d = exactDistance(*grid, it.getCoord());
                ASSERT_EQ(*it, d < 0 ? -gamma : gamma) << it.getCoord();
            }
        }
        // No internal node is left without a leaf below it (level sets have no active tiles).
        EXPECT_EQ(grid->tree().activeTileCount(), 0u);
        std::set<std::tuple<Index, Int32, Int32, Int32>> occupied;
        for (const auto& leaf : grid->tree().leaves()) {
            for (Index level = 1, log2 = 7; level <= 2; ++level, log2 += 5) {
                const Coord o = leaf.origin().alignedDown(log2);
                occupied.insert({level, o[0], o[1], o[2]});
            }
        }
        for (auto it = grid->tree().cbeginNode(); it; ++it) {
            const Index level = it.getLevel();
            if (level == 0 || level == grid->tree().DEPTH - 1)
                continue;
            const Coord o = it.getCoord();
            ASSERT_TRUE(occupied.count({level, o[0], o[1], o[2]}))
                << "internal node without leaves at " << o;
        }
        // The band stays 2 x half width: nothing active at or beyond the half width.
        for (auto it = grid->cbeginValueOn(); it; ++it)
            ASSERT_LT(std::abs(*it), gamma);
    }
}

TEST(LevelSetTracker, RejectsUnsupportedSchemesAndGrids) {
    auto grid = makeSphere();
    tools::LevelSetTracker<FloatGrid> tracker(*grid);
    EXPECT_THROW(tracker.setSpatialScheme(math::WENO5_BIAS), ValueError);
    EXPECT_THROW(tracker.setTemporalScheme(math::UNKNOWN_TIS), ValueError);
    EXPECT_THROW(tracker.setCFL(0.0f), ValueError);
    auto empty = FloatGrid::create(-1.0f);
    EXPECT_THROW(tools::LevelSetTracker<FloatGrid>{*empty}, ValueError);
}

}  // namespace
}  // namespace vdb
