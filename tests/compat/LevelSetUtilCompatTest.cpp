// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's tools/LevelSetUtil.h. The same level sets (spheres, a union of
// spheres, a hollow shell) go through both libraries' fog conversion, interior and isosurface
// masks, enclosed regions and segmentations; the results must have the same active voxels and
// values (within 1e-6), and the segments the same sizes in the same order.

#include <vdb/Grid.h>
#include <vdb/tools/LevelSetUtil.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Composite.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>
#include <vector>

namespace vdb {
namespace {

using test::sameActiveValues;

/// Two spheres of different sizes, apart, as one level set in both libraries (OpenVDB's union
/// copied into ours voxel by voxel, so both hold the same values).
test::FloatPair twoSpheres() {
    auto a = test::spheres(0.6f, Vec3f(-0.8f, 0.0f, 0.0f), 0.05f);
    auto b = test::spheres(0.4f, Vec3f(0.7f, 0.1f, 0.0f), 0.05f);
    openvdb::tools::csgUnion(*a.theirs, *b.theirs);
    test::FloatPair p;
    p.theirs = a.theirs;
    p.ours = FloatGrid::create(p.theirs->background());
    p.ours->setTransform(math::Transform::createLinearTransform(0.05));
    p.ours->setGridClass(GRID_LEVEL_SET);
    for (auto it = p.theirs->cbeginValueAll(); it; ++it) {
        openvdb::CoordBBox box;
        it.getBoundingBox(box);
        p.ours->tree().fill(CoordBBox(test::fromOvdb(box.min()), test::fromOvdb(box.max())), *it,
                            it.isValueOn());
    }
    return p;
}

TEST(LevelSetUtilCompat, FogVolumeMatchesOpenVdb) {
    auto p = test::spheres(1.0f, Vec3f(0.1f, 0.0f, -0.1f), 0.04f);
    tools::sdfToFogVolume(*p.ours);
    openvdb::tools::sdfToFogVolume(*p.theirs);
    EXPECT_TRUE(sameActiveValues(*p.ours, *p.theirs, 1e-6));
    EXPECT_EQ(int(p.ours->getGridClass()), int(p.theirs->getGridClass()));
    EXPECT_EQ(p.ours->background(), p.theirs->background());
}

TEST(LevelSetUtilCompat, MasksMatchOpenVdb) {
    auto p = test::spheres(1.0f, Vec3f(0.1f, 0.0f, -0.1f), 0.04f);
    for (const float iso : {0.0f, -0.05f, 0.05f}) {
        EXPECT_TRUE(sameActiveValues(*tools::sdfInteriorMask(*p.ours, iso),
                                     *openvdb::tools::sdfInteriorMask(*p.theirs, iso), 0.0))
            << iso;
        EXPECT_TRUE(sameActiveValues(*tools::extractIsosurfaceMask(*p.ours, iso),
                                     *openvdb::tools::extractIsosurfaceMask(*p.theirs, iso), 0.0))
            << iso;
    }
    EXPECT_TRUE(sameActiveValues(*tools::extractEnclosedRegion(*p.ours),
                                 *openvdb::tools::extractEnclosedRegion(*p.theirs), 0.0));
}

TEST(LevelSetUtilCompat, SegmentsMatchOpenVdb) {
    auto p = twoSpheres();
    std::vector<FloatGrid::Ptr> ours;
    std::vector<openvdb::FloatGrid::Ptr> theirs;
    tools::segmentSDF(*p.ours, ours);
    openvdb::tools::segmentSDF(*p.theirs, theirs);
    ASSERT_EQ(ours.size(), theirs.size());
    for (size_t i = 0; i < ours.size(); ++i)
        EXPECT_TRUE(sameActiveValues(*ours[i], *theirs[i], 0.0)) << "segment " << i;
    std::vector<FloatGrid::Ptr> ourParts;
    std::vector<openvdb::FloatGrid::Ptr> theirParts;
    tools::segmentActiveVoxels(*p.ours, ourParts);
    openvdb::tools::segmentActiveVoxels(*p.theirs, theirParts);
    ASSERT_EQ(ourParts.size(), theirParts.size());
    for (size_t i = 0; i < ourParts.size(); ++i)
        EXPECT_TRUE(sameActiveValues(*ourParts[i], *theirParts[i], 0.0)) << "part " << i;
}

}  // namespace
}  // namespace vdb
