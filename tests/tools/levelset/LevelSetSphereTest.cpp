// SPDX-License-Identifier: Apache-2.0
// Oracle: the analytic signed distance to the sphere (or to the union of spheres), computed in
// double precision in world units at every voxel of the band's bounding box, and at the corners
// and centre of every inactive tile.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tree/TreeConfigs.h>

#include "LevelSetTestUtil.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace vdb {
namespace {

/// A world-space signed distance: negative inside.
using WorldSdf = std::function<double(double, double, double)>;

struct SphereCase {
    float radius;
    Vec3f center;
    float voxelSize;
    float halfWidth;
};

WorldSdf sphereDistance(float radius, const Vec3f& c) {
    return [=](double x, double y, double z) {
        const double dx = x - c[0], dy = y - c[1], dz = z - c[2];
        return std::sqrt(dx * dx + dy * dy + dz * dz) - double(radius);
    };
}

/// Checks a narrow-band level set against `sdf` (world units) over `box` (index space), which
/// must hold the whole band:
/// - voxels with |d| below halfWidth voxels (less 1e-3) are active with value d within
///   `tolerance`; those beyond it (plus 1e-3) are inactive; in between either is accepted;
/// - every inactive voxel and tile holds -background where d < 0 and +background elsewhere;
/// - the background, grid class, transform and the number of active voxels.
template <typename GridT>
void checkLevelSet(const GridT& grid, const WorldSdf& sdf, const CoordBBox& box, double voxelSize,
                   double halfWidth, double tolerance) {
    using ValueT = typename GridT::ValueType;
    const auto& tree = grid.tree();
    const ValueT background = ValueT(voxelSize * halfWidth);
    ASSERT_EQ(tree.background(), background);
    EXPECT_EQ(grid.getGridClass(), GRID_LEVEL_SET);
    EXPECT_EQ(grid.voxelSize()[0], voxelSize);
    EXPECT_EQ(tree.activeTileCount(), 0u);

    auto distance = [&](const Coord& ijk) {
        return sdf(ijk[0] * voxelSize, ijk[1] * voxelSize, ijk[2] * voxelSize);
    };
    typename GridT::ConstAccessor acc(tree);
    Index64 active = 0;
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk(i, j, k);
                const double d = distance(ijk);
                const double band = std::abs(d) / voxelSize;
                ValueT value;
                const bool on = acc.probeValue(ijk, value);
                if (band < halfWidth - 1e-3) {
                    ASSERT_TRUE(on) << ijk << " at distance " << d << " is not in the band";
                } else if (band >= halfWidth + 1e-3) {
                    ASSERT_FALSE(on) << ijk << " at distance " << d << " is in the band";
                }
                if (on) {
                    ++active;
                    ASSERT_NEAR(double(value), d, tolerance) << ijk;
                } else {
                    ASSERT_EQ(value, d < 0.0 ? -background : background) << ijk << " at " << d;
                }
            }
    EXPECT_EQ(tree.activeVoxelCount(), active) << "active voxels outside " << box;

    for (auto it = tree.cbeginValueOff(); it; ++it) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        const Int32 e = bbox.dim()[0] - 1;
        const Coord& lo = bbox.min();
        for (const Coord& p : {lo, lo.offsetBy(e, e, e), lo.offsetBy(e / 2, e / 2, e / 2),
                               lo.offsetBy(e, 0, 0), lo.offsetBy(0, e, 0), lo.offsetBy(0, 0, e)}) {
            const double d = distance(p);
            ASSERT_EQ(it.getValue(), d < 0.0 ? -background : background)
                << (e == 0 ? "voxel " : "tile ") << bbox << " at " << p << ", distance " << d;
        }
    }
}

/// The index box that holds the band of a sphere, with two voxels of margin.
CoordBBox bandBox(const SphereCase& c) {
    const double reach = c.radius / c.voxelSize + c.halfWidth + 2.0;
    Coord lo, hi;
    for (int a = 0; a < 3; ++a) {
        const double centre = c.center[a] / c.voxelSize;
        lo[a] = Int32(std::floor(centre - reach));
        hi[a] = Int32(std::ceil(centre + reach));
    }
    return CoordBBox(lo, hi);
}

/// Float arithmetic in voxel units loses about 1e-7 of the largest magnitude involved.
double valueTolerance(const SphereCase& c) {
    double centre = 0.0;
    for (int a = 0; a < 3; ++a)
        centre = std::max(centre, std::abs(double(c.center[a]) / c.voxelSize));
    const double extent = centre + c.radius / c.voxelSize + c.halfWidth;
    return c.voxelSize * std::max(1e-5, 2e-7 * extent);
}

const std::vector<SphereCase>& sphereCases() {
    static const std::vector<SphereCase> cases = {
        {1.0f, Vec3f(0.0f, 0.0f, 0.0f), 0.05f, 3.0f},
        {2.5f, Vec3f(-1.3f, 0.7f, -2.2f), 0.1f, 3.0f},
        {7.0f, Vec3f(-20.5f, -33.25f, 12.0f), 0.25f, 4.0f},
        {0.6f, Vec3f(0.3f, -0.3f, 0.3f), 0.02f, 2.0f},
        {15.0f, Vec3f(100.5f, -3.0f, 7.0f), 1.0f, 1.5f},
    };
    return cases;
}

/// The cases a test runs: all, or two in a scaled-down (sanitizer) run.
std::vector<SphereCase> testCases() {
    const auto& all = sphereCases();
    const int n = std::min<int>(int(all.size()), std::max(2, test::scaledBatchCount(5)));
    return {all.begin(), all.begin() + n};
}

template <typename GridT>
void checkSphereCases() {
    for (const SphereCase& c : testCases()) {
        SCOPED_TRACE(::testing::Message()
                     << "radius " << c.radius << " center " << c.center << " voxel " << c.voxelSize
                     << " half width " << c.halfWidth);
        auto grid =
            tools::createLevelSetSphere<GridT>(c.radius, c.center, c.voxelSize, c.halfWidth);
        ASSERT_GT(grid->activeVoxelCount(), 0u);
        checkLevelSet(*grid, sphereDistance(c.radius, c.center), bandBox(c), double(c.voxelSize),
                      double(c.halfWidth), valueTolerance(c));
    }
}

TEST(LevelSetSphere, MatchesTheAnalyticDistance) {
    checkSphereCases<FloatGrid>();
}

TEST(LevelSetSphere, DoubleGridsMatchTheAnalyticDistance) {
    checkSphereCases<DoubleGrid>();
}

TEST(LevelSetSphere, BoundedAndNonDefaultTreesMatchTheAnalyticDistance) {
    checkSphereCases<Grid<tree::FixedTree6543<float>>>();
    checkSphereCases<Grid<tree::HashTree432<float>>>();
    checkSphereCases<Grid<tree::FixedTree6545<float>>>();
}

TEST(LevelSetSphere, ThreadedMatchesSingleThreadedBitForBit) {
    for (const SphereCase& c : testCases()) {
        auto a = tools::createLevelSetSphere<FloatGrid>(c.radius, c.center, c.voxelSize,
                                                        c.halfWidth, true);
        auto b = tools::createLevelSetSphere<FloatGrid>(c.radius, c.center, c.voxelSize,
                                                        c.halfWidth, false);
        EXPECT_TRUE(test::identicalTrees(a->tree(), b->tree()));
    }
}

TEST(LevelSetSphere, SpheresBelowOneAndAHalfVoxelsGiveAnEmptyLevelSet) {
    auto grid = tools::createLevelSetSphere<FloatGrid>(1.4f, Vec3f(0.0f), 1.0f, 3.0f);
    EXPECT_TRUE(grid->empty());
    EXPECT_EQ(grid->background(), 3.0f);
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    EXPECT_EQ(grid->voxelSize()[0], 1.0);
}

TEST(LevelSetSphere, InvalidArgumentsThrow) {
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(0.0f, Vec3f(0.0f), 0.1f), ValueError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(-1.0f, Vec3f(0.0f), 0.1f), ValueError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.0f), ValueError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f, 1.0f), ValueError);
    EXPECT_THROW(tools::createEnrightSphere<FloatGrid>(0), ValueError);
    EXPECT_THROW(tools::createEnrightEightSpheres<FloatGrid>(-4), ValueError);
    // A [6,4,3] tree holds [-4096, 4096): a sphere around x = 5000 does not fit.
    using SmallGrid = Grid<tree::FixedTree643<float>>;
    EXPECT_THROW(tools::createLevelSetSphere<SmallGrid>(20.0f, Vec3f(5000.0f, 0.0f, 0.0f), 1.0f),
                 IndexError);
    EXPECT_NO_THROW(
        tools::createLevelSetSphere<SmallGrid>(20.0f, Vec3f(-4000.0f, 0.0f, 0.0f), 1.0f));
}

TEST(LevelSetSphere, EnrightSphereHasTheShellVolume) {
    const int resolution = 128;
    auto grid = tools::createEnrightSphere<FloatGrid>(resolution);
    const SphereCase c{0.15f, Vec3f(0.35f, 0.35f, 0.35f), 1.0f / float(resolution), 5.0f};
    checkLevelSet(*grid, sphereDistance(c.radius, c.center), bandBox(c), double(c.voxelSize), 5.0,
                  valueTolerance(c));
    // The band |d| < 5 voxels around a radius of 19.2 voxels: the volume between two spheres.
    const double r = 0.15 * resolution, w = 5.0;
    const double shell = 4.0 / 3.0 * std::numbers::pi * (std::pow(r + w, 3) - std::pow(r - w, 3));
    EXPECT_NEAR(double(grid->activeVoxelCount()), shell, 0.02 * shell);
}

TEST(LevelSetSphere, EnrightEightSpheresIsTheLevelSetOfTheUnion) {
    const int resolution = 96;
    auto grid = tools::createEnrightEightSpheres<FloatGrid>(resolution);
    const std::vector<Vec3f> centers = {Vec3f(0.35f, 0.35f, 0.35f), Vec3f(0.15f, 0.15f, 0.85f),
                                        Vec3f(0.15f, 0.85f, 0.15f), Vec3f(0.35f, 0.65f, 0.65f),
                                        Vec3f(0.85f, 0.15f, 0.15f), Vec3f(0.65f, 0.35f, 0.65f),
                                        Vec3f(0.65f, 0.65f, 0.35f), Vec3f(0.85f, 0.85f, 0.85f)};
    const WorldSdf sdf = [&](double x, double y, double z) {
        double d = 1e30;
        for (const Vec3f& c : centers)
            d = std::min(d, sphereDistance(0.125f, c)(x, y, z));
        return d;
    };
    // The transform keeps the voxel size 1/96 in double, not rounded through float.
    const double dx = 1.0 / resolution;
    checkLevelSet(*grid, sdf, CoordBBox(Coord(-5), Coord(resolution + 5)), dx, 5.0, dx * 2e-5);
    const auto single = tools::createLevelSetSphere<FloatGrid>(0.125f, centers[0], float(dx), 5.0f);
    EXPECT_GT(grid->activeVoxelCount(), 4 * single->activeVoxelCount());
    auto serial = tools::createEnrightEightSpheres<FloatGrid>(resolution, 5.0f, false);
    EXPECT_TRUE(test::identicalTrees(grid->tree(), serial->tree()));
}

}  // namespace
}  // namespace vdb
