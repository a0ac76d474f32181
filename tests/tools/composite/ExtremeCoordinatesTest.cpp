// SPDX-License-Identifier: Apache-2.0
// Level sets at the ends of the 32-bit index space (within a few hundred voxels of -2^31 and
// 2^31 - 1): building, CSG, flood fill, pruning and files must give what they give at the
// origin. Oracles: the analytic signed distance of each sphere (values in voxel units, voxel
// size 1, so world = index) and of their union, intersection and difference away from the
// circle where the spheres meet; and a voxel-by-voxel snapshot taken before pruning and before
// a file round trip.

#include <vdb/Grid.h>
#include <vdb/io/File.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Prune.h>

#include "GridContents.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

namespace vdb {
namespace {

struct Ball {
    Vec3d center;
    double radius;
    double distance(const Coord& ijk) const { return (Vec3d(ijk) - center).length() - radius; }
};

FloatGrid::Ptr makeBall(const Ball& b) {
    return tools::createLevelSetSphere<FloatGrid>(b.radius, b.center, 1.0, 3.0);
}

/// Checks every voxel of `bbox`: active values equal `sdf` to `tol`, and the sign of every
/// value matches it where the analytic distance is at least half a voxel from zero.
template <typename SdfT>
void expectLevelSet(const FloatGrid& grid, const CoordBBox& bbox, const SdfT& sdf, double tol,
                    const std::string& what) {
    const auto acc = grid.getConstAccessor();
    size_t active = 0;
    for (Int64 i = bbox.min()[0]; i <= bbox.max()[0]; ++i)
        for (Int64 j = bbox.min()[1]; j <= bbox.max()[1]; ++j)
            for (Int64 k = bbox.min()[2]; k <= bbox.max()[2]; ++k) {
                const Coord ijk{Int32(i), Int32(j), Int32(k)};
                const double d = sdf(ijk);
                const float v = acc.getValue(ijk);
                if (acc.isValueOn(ijk)) {
                    ++active;
                    ASSERT_NEAR(double(v), d, tol) << what << " at " << ijk;
                }
                if (std::abs(d) >= 0.5) {
                    ASSERT_EQ(v < 0.0f, d < 0.0)
                        << what << " at " << ijk << ": " << v << " vs " << d;
                }
            }
    EXPECT_GT(active, 0u) << what;
}

class ExtremeCoordinates : public ::testing::TestWithParam<double> {};

TEST_P(ExtremeCoordinates, SpheresAndTheirCsgAreRightAtTheEndsOfTheIndexSpace) {
    const double c = GetParam();
    const Ball a{Vec3d(c, c, c), 20.0};
    const Ball b{Vec3d(c + 15.0, c, c - 0.5), 14.0};
    const CoordBBox box(Coord(Int32(c - 26.0)), Coord(Int32(c + 36.0)));

    const auto ga = makeBall(a), gb = makeBall(b);
    expectLevelSet(
        *ga, box, [&](const Coord& p) { return a.distance(p); }, 1e-3, "sphere a");
    expectLevelSet(
        *gb, box, [&](const Coord& p) { return b.distance(p); }, 1e-3, "sphere b");

    // CSG: min, max and max(a, -b) of the two distances; these are the exact distances of
    // the results except near the circle where the spheres meet, so the values are checked
    // against the combination of the inputs' own analytic distances.
    const auto uni = tools::csgUnionCopy(*ga, *gb);
    expectLevelSet(
        *uni, box, [&](const Coord& p) { return std::min(a.distance(p), b.distance(p)); }, 1e-3,
        "union");
    const auto inter = tools::csgIntersectionCopy(*ga, *gb);
    expectLevelSet(
        *inter, box, [&](const Coord& p) { return std::max(a.distance(p), b.distance(p)); }, 1e-3,
        "intersection");
    const auto diff = tools::csgDifferenceCopy(*ga, *gb);
    expectLevelSet(
        *diff, box, [&](const Coord& p) { return std::max(a.distance(p), -b.distance(p)); }, 1e-3,
        "difference");

    // Pruning keeps every value and state; a file round trip keeps every voxel and tile.
    const auto sample = [&](const FloatGrid& grid) {
        std::vector<std::pair<float, bool>> values;
        const auto acc = grid.getConstAccessor();
        for (Int64 i = box.min()[0] - 8; i <= box.max()[0] + 8; ++i)
            for (Int64 j = box.min()[1] - 8; j <= box.max()[1] + 8; ++j)
                for (Int64 k = box.min()[2] - 8; k <= box.max()[2] + 8; ++k) {
                    const Coord ijk{Int32(i), Int32(j), Int32(k)};
                    values.emplace_back(acc.getValue(ijk), acc.isValueOn(ijk));
                }
        return values;
    };
    const auto values = sample(*diff);
    const Index64 leaves = diff->tree().leafCount();
    tools::pruneLevelSet(diff->tree());
    tools::prune(diff->tree());
    EXPECT_EQ(sample(*diff), values);
    EXPECT_LE(diff->tree().leafCount(), leaves);
    const auto before = test::treeContents(diff->tree());
    const std::string file = test::tempPath("vdb-extreme-", std::to_string(c < 0 ? 0 : 1) + ".vdb");
    io::File(file).write(GridPtrVec{diff});
    io::File in(file);
    in.open(false);
    const auto back = gridPtrCast<FloatGrid>(in.getGrids()->front());
    std::filesystem::remove(file);
    ASSERT_TRUE(back);
    EXPECT_EQ(test::treeContents(back->tree()), before);
    CoordBBox bbox;
    ASSERT_TRUE(back->tree().evalActiveVoxelBoundingBox(bbox));
    EXPECT_TRUE(box.isInside(bbox)) << bbox;
}

INSTANTIATE_TEST_SUITE_P(Corners, ExtremeCoordinates,
                         ::testing::Values(2147483647.0 - 60.0, -2147483648.0 + 60.0, 1.0e9,
                                           -1.5e9));

TEST(ExtremeCoordinatesLimits, SphereBandBeyondTheIndexSpaceIsAnIndexError) {
    EXPECT_THROW(
        tools::createLevelSetSphere<FloatGrid>(10.0, Vec3d(2147483647.0 - 5.0, 0, 0), 1.0, 3.0),
        IndexError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(10.0, Vec3d(0, -2147483648.0, 0), 1.0, 3.0),
                 IndexError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(
                     1.0, Vec3d(std::numeric_limits<double>::quiet_NaN(), 0, 0), 0.1, 3.0),
                 ValueError);
    EXPECT_THROW(tools::createLevelSetSphere<FloatGrid>(std::numeric_limits<double>::infinity(),
                                                        Vec3d(0.0), 0.1, 3.0),
                 ValueError);
}

TEST(ExtremeCoordinatesLimits, FloatFormAtTheOriginIsUnchangedByTheSplitCenter) {
    // Near the origin the float form computes exactly as OpenVDB does: the double form with the
    // same float inputs gives the same values bit for bit.
    const auto f = tools::createLevelSetSphere<FloatGrid>(0.3f, Vec3f(0.1f, -0.2f, 0.05f), 0.01f);
    const auto d = tools::createLevelSetSphere<FloatGrid>(
        double(0.3f), Vec3d(Vec3f(0.1f, -0.2f, 0.05f)), double(0.01f), 3.0);
    EXPECT_EQ(test::treeContents(f->tree()), test::treeContents(d->tree()));
}

}  // namespace
}  // namespace vdb
