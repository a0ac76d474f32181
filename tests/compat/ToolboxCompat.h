// SPDX-License-Identifier: Apache-2.0
// Shared by the toolbox compatibility tests (operators, filters, measures, utilities): the same
// grids built in both libraries, and comparisons of results voxel by voxel.

#pragma once

#include <vdb/Grid.h>
#include <vdb/math/Transform.h>
#include <vdb/tools/LevelSetSphere.h>

#include "OpenVdbConvert.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <type_traits>

namespace vdb::test {

inline openvdb::Vec3d toOvdb(const Vec3d& v) {
    return openvdb::Vec3d(v[0], v[1], v[2]);
}
inline Vec3d fromOvdb(const openvdb::Vec3d& v) {
    return Vec3d(v[0], v[1], v[2]);
}

/// The same grid in both libraries.
template <typename OursT, typename TheirsT>
struct GridPair {
    typename OursT::Ptr ours;
    typename TheirsT::Ptr theirs;
};
using FloatPair = GridPair<FloatGrid, openvdb::FloatGrid>;
using Vec3SPair = GridPair<Vec3SGrid, openvdb::Vec3SGrid>;

/// OpenVDB's transform of the same map: a uniform or non-uniform scale and a translation.
inline openvdb::math::Transform::Ptr ovdbTransform(const Vec3d& scale, const Vec3d& translation) {
    auto x = openvdb::math::Transform::createLinearTransform(1.0);
    x->preScale(toOvdb(scale));
    x->postTranslate(toOvdb(translation));
    return x;
}
inline math::Transform::Ptr ourTransform(const Vec3d& scale, const Vec3d& translation) {
    auto x = math::Transform::createLinearTransform(1.0);
    x->preScale(scale);
    x->postTranslate(translation);
    return x;
}

/// The same level set sphere in both libraries (both createLevelSetSphere, which agree).
inline FloatPair spheres(float radius, const Vec3f& c, float dx, float halfWidth = 3.0f) {
    openvdb::initialize();
    FloatPair p;
    p.ours = tools::createLevelSetSphere<FloatGrid>(radius, c, dx, halfWidth);
    p.theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        radius, openvdb::Vec3f(c[0], c[1], c[2]), dx, halfWidth);
    return p;
}

/// A field sampled at the voxels of `box` into both libraries (active), with the same
/// transform (scale and translation) and background.
template <typename PairT, typename FieldT, typename ValueT>
PairT sampledPair(const CoordBBox& box, const Vec3d& scale, const Vec3d& translation,
                  const FieldT& field, const ValueT& background) {
    openvdb::initialize();
    PairT p;
    using OursT = std::decay_t<decltype(*p.ours)>;
    using TheirsT = std::decay_t<decltype(*p.theirs)>;
    p.ours = OursT::create(background);
    p.theirs = TheirsT::create(toOvdb(background));
    p.ours->setTransform(ourTransform(scale, translation));
    p.theirs->setTransform(ovdbTransform(scale, translation));
    auto a = p.ours->getAccessor();
    auto b = p.theirs->getAccessor();
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk(i, j, k);
                const ValueT v = field(p.ours->indexToWorld(Vec3d(ijk)));
                a.setValue(ijk, v);
                b.setValue(toOvdb(ijk), toOvdb(v));
            }
    return p;
}

/// The largest difference between two values (of any component for vectors).
template <typename A, typename B>
double valueDifference(const A& a, const B& b) {
    if constexpr (std::is_arithmetic_v<A>) {
        return std::abs(double(a) - double(b));
    } else {
        double d = 0;
        for (int i = 0; i < 3; ++i)
            d = std::max(d, std::abs(double(a[size_t(i)]) - double(b[i])));
        return d;
    }
}

/// Success when both grids have the same active voxels (and active voxel count) and their
/// values there differ by at most `tolerance` after scaling by `scale` (e.g. the voxel size,
/// to compare in voxel units).
template <typename OursT, typename TheirsT>
::testing::AssertionResult sameActiveValues(const OursT& ours, const TheirsT& theirs,
                                            double tolerance, double scale = 1.0) {
    if (ours.activeVoxelCount() != theirs.activeVoxelCount())
        return ::testing::AssertionFailure() << "active voxels: " << ours.activeVoxelCount()
                                             << " vs OpenVDB's " << theirs.activeVoxelCount();
    auto acc = ours.getConstAccessor();
    double worst = 0;
    Coord where;
    for (auto it = theirs.cbeginValueOn(); it; ++it) {
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        for (auto c = box.begin(); c; ++c) {
            const Coord ijk = fromOvdb(*c);
            if (!acc.isValueOn(ijk))
                return ::testing::AssertionFailure() << ijk << " is active only in OpenVDB's";
            const double d = valueDifference(acc.getValue(ijk), *it) * scale;
            if (d > worst) {
                worst = d;
                where = ijk;
            }
        }
    }
    if (worst > tolerance)
        return ::testing::AssertionFailure() << "values differ by " << worst << " at " << where
                                             << " (tolerance " << tolerance << ")";
    return ::testing::AssertionSuccess() << "largest difference " << worst;
}

}  // namespace vdb::test
