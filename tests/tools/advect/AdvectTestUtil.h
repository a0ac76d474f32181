// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the level set advection tests: analytic spheres, measurements of a level
// set taken by brute force over a dense box (not through the library's tools), and bitwise
// tree comparison.

#pragma once

#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Vec3.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vdb::test {

/// Signed distance (world units) to the sphere of `radius` around `center`.
inline double sphereDistance(const Vec3d& xyz, const Vec3d& center, double radius) {
    return (xyz - center).length() - radius;
}

/// Volume and centroid of the inside of a level set, from a smeared Heaviside of width 1.5
/// voxels, summed voxel by voxel over the index box `box` through an accessor.
struct InsideMoments {
    double volume = 0.0;
    Vec3d centroid;
};

template <typename GridT>
InsideMoments insideMoments(const GridT& grid, const CoordBBox& box) {
    const double dx = grid.voxelSize()[0], e = 1.5 * dx;
    auto acc = grid.getConstAccessor();
    double sum = 0.0;
    Vec3d first(0.0);
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i) {
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j) {
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const double v = double(acc.getValue(Coord(i, j, k)));
                double h = v <= -e ? 1.0
                           : v >= e
                               ? 0.0
                               : 0.5 - v / (2 * e) -
                                     std::sin(std::numbers::pi * v / e) / (2 * std::numbers::pi);
                sum += h;
                first += grid.indexToWorld(Vec3d(Coord(i, j, k))) * h;
            }
        }
    }
    InsideMoments m;
    m.volume = sum * dx * dx * dx;
    m.centroid = sum > 0 ? first / sum : Vec3d(0.0);
    return m;
}

/// Success when both trees have the same leaves, masks and bit-identical values, the same
/// active voxel count and the same background.
template <typename TreeT>
::testing::AssertionResult bitIdenticalTrees(const TreeT& a, const TreeT& b) {
    if (!sameBits(a.background(), b.background()))
        return ::testing::AssertionFailure() << "backgrounds differ";
    if (a.leafCount() != b.leafCount() || a.activeVoxelCount() != b.activeVoxelCount())
        return ::testing::AssertionFailure() << "leaf or active voxel counts differ";
    for (const auto& leaf : a.leaves()) {
        const auto* other = b.probeConstLeaf(leaf.origin());
        if (!other)
            return ::testing::AssertionFailure() << "no leaf at " << leaf.origin();
        if (!(leaf.getValueMask() == other->getValueMask()))
            return ::testing::AssertionFailure() << "masks differ at " << leaf.origin();
        for (Index n = 0; n < leaf.NUM_VALUES; ++n) {
            if (!sameBits(leaf.getValue(n), other->getValue(n)))
                return ::testing::AssertionFailure()
                       << "values differ at " << leaf.offsetToGlobalCoord(n);
        }
    }
    return ::testing::AssertionSuccess();
}

}  // namespace vdb::test
