// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's tools/FastSweeping.h. The same grids (sphere level sets from both
// libraries' createLevelSetSphere, which agree, turned into fog volumes or distorted bands the
// same way in both) go through both libraries' fogToSdf, sdfToSdf, dilateSdf, maskSdf and
// sdfToExt; the results must have the same active voxels and values within 1e-3 voxel, and
// the same background.
//
// Known differences, avoided here: OpenVDB 10 evaluates the extension functor at index
// positions (its extension grid has an identity transform), so the extension is compared at
// voxel size 1; it stops at distances of 1000 world units; and its fogToSdf keeps the grid
// class of the fog volume where ours returns a level set.

#include <vdb/Grid.h>
#include <vdb/tools/FastSweeping.h>
#include <vdb/tools/LevelSetUtil.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/FastSweeping.h>
#include <openvdb/tools/LevelSetUtil.h>

#include <cmath>

namespace vdb {
namespace {

using test::sameActiveValues;

constexpr float DX = 0.05f;
constexpr double TOLERANCE = 1e-3;  // voxels

test::FloatPair sphere(float halfWidth = 3.0f) {
    return test::spheres(1.0f, Vec3f(0.013f, -0.021f, 0.032f), DX, halfWidth);
}

TEST(FastSweepingCompat, FogToSdfMatchesOpenVdb) {
    auto p = sphere();
    tools::sdfToFogVolume(*p.ours);
    openvdb::tools::sdfToFogVolume(*p.theirs);
    for (const float iso : {0.5f, 0.25f}) {
        const auto ours = tools::fogToSdf(*p.ours, iso);
        const auto theirs = openvdb::tools::fogToSdf(*p.theirs, iso);
        EXPECT_TRUE(sameActiveValues(*ours, *theirs, TOLERANCE, 1.0 / DX)) << iso;
        EXPECT_NEAR(ours->background(), theirs->background(), 1e-3 * DX);
        EXPECT_EQ(ours->tree().activeTileCount(), theirs->tree().activeTileCount());
    }
}

TEST(FastSweepingCompat, SdfToSdfOfADistortedBandMatchesOpenVdb) {
    auto p = sphere(6.0f);
    for (auto it = p.ours->tree().beginValueAll(); it; ++it)
        it.setValue(*it * (1.0f + 0.4f * std::sin(0.2f * float(it.getCoord()[0]))));
    for (auto it = p.theirs->beginValueAll(); it; ++it)
        it.setValue(*it * (1.0f + 0.4f * std::sin(0.2f * float(it.getCoord()[0]))));
    for (const int nIter : {1, 2}) {
        EXPECT_TRUE(sameActiveValues(*tools::sdfToSdf(*p.ours, 0.0f, nIter),
                                     *openvdb::tools::sdfToSdf(*p.theirs, 0.0f, nIter), TOLERANCE,
                                     1.0 / DX))
            << nIter;
    }
    EXPECT_TRUE(sameActiveValues(*tools::sdfToSdf(*p.ours, 0.5f * DX),
                                 *openvdb::tools::sdfToSdf(*p.theirs, 0.5f * DX), TOLERANCE,
                                 1.0 / DX));
}

TEST(FastSweepingCompat, DilateSdfMatchesOpenVdb) {
    auto p = sphere();
    const struct {
        tools::NearestNeighbors ours;
        openvdb::tools::NearestNeighbors theirs;
    } stencils[] = {{tools::NN_FACE, openvdb::tools::NN_FACE},
                    {tools::NN_FACE_EDGE_VERTEX, openvdb::tools::NN_FACE_EDGE_VERTEX}};
    for (const auto& nn : stencils) {
        const auto ours = tools::dilateSdf(*p.ours, 10, nn.ours);
        const auto theirs = openvdb::tools::dilateSdf(*p.theirs, 10, nn.theirs);
        EXPECT_TRUE(sameActiveValues(*ours, *theirs, TOLERANCE, 1.0 / DX)) << int(nn.ours);
        EXPECT_NEAR(ours->background(), theirs->background(), 1e-3 * DX);
    }
    const auto outside = tools::dilateSdf(*p.ours, 6, tools::NN_FACE, 1,
                                          tools::FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE);
    const auto theirsOutside =
        openvdb::tools::dilateSdf(*p.theirs, 6, openvdb::tools::NN_FACE, 1,
                                  openvdb::tools::FastSweepingDomain::SWEEP_GREATER_THAN_ISOVALUE);
    EXPECT_TRUE(sameActiveValues(*outside, *theirsOutside, TOLERANCE, 1.0 / DX));
    const auto inside = tools::dilateSdf(*p.ours, 6, tools::NN_FACE, 1,
                                         tools::FastSweepingDomain::SWEEP_LESS_THAN_ISOVALUE);
    const auto theirsInside =
        openvdb::tools::dilateSdf(*p.theirs, 6, openvdb::tools::NN_FACE, 1,
                                  openvdb::tools::FastSweepingDomain::SWEEP_LESS_THAN_ISOVALUE);
    EXPECT_TRUE(sameActiveValues(*inside, *theirsInside, TOLERANCE, 1.0 / DX));
}

TEST(FastSweepingCompat, MaskSdfMatchesOpenVdb) {
    auto p = sphere();
    auto mask = MaskGrid::create();
    mask->setTransform(p.ours->transform().copy());
    auto theirMask = openvdb::MaskGrid::create();
    theirMask->setTransform(p.theirs->transform().copy());
    const CoordBBox box(Coord(-30, -5, -5), Coord(5, 30, 12));
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i) {
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j) {
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                mask->tree().setValueOn(Coord(i, j, k));
                theirMask->tree().setValueOn(openvdb::Coord(i, j, k));
            }
        }
    }
    EXPECT_TRUE(sameActiveValues(*tools::maskSdf(*p.ours, *mask),
                                 *openvdb::tools::maskSdf(*p.theirs, *theirMask), TOLERANCE,
                                 1.0 / DX));
}

TEST(FastSweepingCompat, ExtensionMatchesOpenVdb) {
    // Voxel size 1, where OpenVDB's index-space functor calls agree with world positions.
    auto p = test::spheres(20.0f, Vec3f(0.3f, -0.2f, 0.1f), 1.0f, 5.0f);
    const auto field = [](const auto& xyz) {
        return float(std::sin(0.2 * xyz[0]) + 0.5 * std::cos(0.15 * xyz[2]));
    };
    const auto [sdf, ext] = tools::sdfToSdfAndExt(
        *p.ours, [&](const Vec3d& xyz) { return field(xyz); }, 0.0f, 0.0f, 1);
    const auto theirs = openvdb::tools::sdfToSdfAndExt(
        *p.theirs, [&](const openvdb::Vec3R& xyz) { return field(xyz); }, 0.0f, 0.0f, 1);
    EXPECT_TRUE(sameActiveValues(*sdf, *theirs.first, TOLERANCE));
    EXPECT_TRUE(sameActiveValues(*ext, *theirs.second, 1e-4));
    const auto vec = tools::sdfToExt(
        *p.ours, [](const Vec3d& xyz) { return Vec3s(float(xyz[0]), float(xyz[1]), 1.0f); },
        Vec3s(0.0f), 0.0f);
    const auto theirVec = openvdb::tools::sdfToExt(
        *p.theirs,
        [](const openvdb::Vec3R& xyz) {
            return openvdb::Vec3s(float(xyz[0]), float(xyz[1]), 1.0f);
        },
        openvdb::Vec3s(0.0f), 0.0f);
    EXPECT_TRUE(sameActiveValues(*vec, *theirVec, 1e-3));
}

}  // namespace
}  // namespace vdb
