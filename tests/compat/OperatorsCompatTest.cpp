// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's tools/GridOperators.h. The same grids (level set spheres, and vector and
// scalar fields sampled under uniform and non-uniform scale) go through both libraries'
// gradient, divergence, curl, Laplacian, mean curvature, magnitude and normalize; the results
// must have the same active voxels and values within 1e-4 in voxel units (derivatives of order
// n scaled by the voxel size to the n), the same background and the same vector type.

#include <vdb/Grid.h>
#include <vdb/tools/GridOperators.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/GridOperators.h>

#include <cmath>

namespace vdb {
namespace {

using test::sameActiveValues;

TEST(OperatorsCompat, ScalarOperatorsOfALevelSetMatchOpenVdb) {
    const float dx = 0.05f;
    auto p = test::spheres(1.0f, Vec3f(0.1f, -0.2f, 0.05f), dx);
    {
        auto ours = tools::gradient(*p.ours);
        auto theirs = openvdb::tools::gradient(*p.theirs);
        EXPECT_TRUE(sameActiveValues(*ours, *theirs, 1e-4));
        EXPECT_EQ(int(ours->getVectorType()), int(theirs->getVectorType()));
        EXPECT_EQ(ours->background(), test::fromOvdb(theirs->background()));
    }
    {
        auto ours = tools::laplacian(*p.ours);
        auto theirs = openvdb::tools::laplacian(*p.theirs);
        EXPECT_TRUE(sameActiveValues(*ours, *theirs, 1e-4, dx));
        EXPECT_EQ(int(ours->getVectorType()), int(theirs->getVectorType()));
    }
    {
        auto ours = tools::meanCurvature(*p.ours);
        auto theirs = openvdb::tools::meanCurvature(*p.theirs);
        EXPECT_TRUE(sameActiveValues(*ours, *theirs, 1e-4, dx));
        EXPECT_EQ(ours->background(), theirs->background());
    }
}

TEST(OperatorsCompat, NonUniformScaleAndTranslation) {
    const Vec3d scale(0.1, 0.05, 0.2), t(1.0, -2.0, 0.5);
    const CoordBBox box(Coord(-12), Coord(11));
    auto s = test::sampledPair<test::FloatPair>(
        box, scale, t,
        [](const Vec3d& q) { return float(std::sin(q[0]) * std::cos(2 * q[1]) + q[2] * q[2]); },
        0.0f);
    EXPECT_TRUE(sameActiveValues(*tools::gradient(*s.ours), *openvdb::tools::gradient(*s.theirs),
                                 1e-4, 0.05));
    EXPECT_TRUE(sameActiveValues(*tools::laplacian(*s.ours), *openvdb::tools::laplacian(*s.theirs),
                                 1e-4, 0.05 * 0.05));
    EXPECT_TRUE(sameActiveValues(*tools::meanCurvature(*s.ours),
                                 *openvdb::tools::meanCurvature(*s.theirs), 1e-4, 0.05));
    auto v = test::sampledPair<test::Vec3SPair>(
        box, scale, t,
        [](const Vec3d& q) {
            return Vec3s(float(q[1] * q[2]), float(std::sin(q[0])), float(q[0] - q[1] * q[1]));
        },
        Vec3s(0.0f));
    EXPECT_TRUE(sameActiveValues(*tools::divergence(*v.ours),
                                 *openvdb::tools::divergence(*v.theirs), 1e-4, 0.05));
    EXPECT_TRUE(
        sameActiveValues(*tools::curl(*v.ours), *openvdb::tools::curl(*v.theirs), 1e-4, 0.05));
    EXPECT_TRUE(
        sameActiveValues(*tools::magnitude(*v.ours), *openvdb::tools::magnitude(*v.theirs), 1e-5));
    EXPECT_TRUE(
        sameActiveValues(*tools::normalize(*v.ours), *openvdb::tools::normalize(*v.theirs), 1e-5));
}

TEST(OperatorsCompat, StaggeredDivergenceMatchesOpenVdb) {
    const CoordBBox box(Coord(-8), Coord(8));
    auto v = test::sampledPair<test::Vec3SPair>(
        box, Vec3d(0.25), Vec3d(0.0),
        [](const Vec3d& q) { return Vec3s(float(q[0] * q[0]), float(q[1] * q[0]), float(q[2])); },
        Vec3s(0.0f));
    v.ours->setGridClass(GRID_STAGGERED);
    v.theirs->setGridClass(openvdb::GRID_STAGGERED);
    EXPECT_TRUE(sameActiveValues(*tools::divergence(*v.ours),
                                 *openvdb::tools::divergence(*v.theirs), 1e-4, 0.25));
}

TEST(OperatorsCompat, MasksAndTilesMatchOpenVdb) {
    auto p = test::spheres(1.0f, Vec3f(0.0f), 0.05f);
    // The mask: a box through the band, in both libraries.
    auto ourMask = MaskGrid::create();
    auto theirMask = openvdb::MaskGrid::create();
    const CoordBBox box(Coord(-30, -5, -40), Coord(3, 40, 40));
    ourMask->tree().fill(box, true, true);
    theirMask->tree().fill(test::toOvdb(box), true, true);
    EXPECT_TRUE(sameActiveValues(*tools::gradient(*p.ours, *ourMask),
                                 *openvdb::tools::gradient(*p.theirs, *theirMask), 1e-4));
    EXPECT_TRUE(sameActiveValues(*tools::meanCurvature(*p.ours, *ourMask),
                                 *openvdb::tools::meanCurvature(*p.theirs, *theirMask), 1e-4,
                                 0.05));
    // Active tiles next to voxels: expanded, differentiated, pruned.
    auto ours = FloatGrid::create(0.0f);
    auto theirs = openvdb::FloatGrid::create(0.0f);
    ours->tree().fill(CoordBBox::createCube(Coord(0), 128), 1.0f, true);
    theirs->tree().fill(openvdb::CoordBBox::createCube(openvdb::Coord(0), 128), 1.0f, true);
    for (int i = 0; i < 20; ++i) {
        ours->tree().setValue(Coord(128, i, 2 * i), float(i));
        theirs->tree().setValue(openvdb::Coord(128, i, 2 * i), float(i));
    }
    EXPECT_TRUE(
        sameActiveValues(*tools::gradient(*ours), *openvdb::tools::gradient(*theirs), 1e-6));
    EXPECT_TRUE(
        sameActiveValues(*tools::laplacian(*ours), *openvdb::tools::laplacian(*theirs), 1e-6));
}

}  // namespace
}  // namespace vdb
