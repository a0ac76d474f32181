// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's volumeToMesh on the same grids (every voxel and tile copied over). Both
// place a vertex at the mean of its cell's edge crossings, so at adaptivity 0 the meshes must
// have the same numbers of points and quads (within 1%: the libraries may resolve ambiguous
// cells differently) and lie within a quarter voxel of each other (symmetric Hausdorff
// distance, sampled at vertices, triangle centroids and edge midpoints), wound the same way.
// At adaptivity 0.5 this library must use fewer polygons than at 0, and stay as close to its
// adaptivity-0 mesh and to the analytic surface as OpenVDB's adaptive mesh does to its own,
// plus a tenth of a voxel.

#include <vdb/Grid.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/VolumeToMesh.h>

#include "AnalyticLevelSets.h"
#include "MeshMetrics.h"
#include "OpenVdbConvert.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/VolumeToMesh.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace vdb {
namespace {

using test::TestMesh;
using test::toOvdb;

constexpr double kSpacing = 0.5;        // voxels between the samples of a mesh's surface
constexpr double kCoarseSpacing = 1.0;  // the same for the adaptive meshes' comparisons

/// The same grid in OpenVDB: every voxel of every leaf, every tile, the background and class.
openvdb::FloatGrid::Ptr toOpenVdb(const FloatGrid& grid) {
    auto out = openvdb::FloatGrid::create(grid.background());
    out->setGridClass(grid.getGridClass() == GRID_LEVEL_SET ? openvdb::GRID_LEVEL_SET
                                                            : openvdb::GRID_FOG_VOLUME);
    auto acc = out->getAccessor();
    for (auto it = grid.cbeginValueAll(); it; ++it) {
        if (it.isTileValue()) {
            CoordBBox box;
            it.getBoundingBox(box);
            out->tree().fill(toOvdb(box), *it, it.isValueOn());
        } else if (it.isValueOn()) {
            acc.setValueOn(toOvdb(it.getCoord()), *it);
        } else {
            acc.setValueOff(toOvdb(it.getCoord()), *it);
        }
    }
    return out;
}

TestMesh openVdbMesh(const openvdb::FloatGrid& grid, double adaptivity) {
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(grid, points, triangles, quads, 0.0, adaptivity);
    TestMesh mesh;
    for (const auto& p : points)
        mesh.points.emplace_back(p[0], p[1], p[2]);
    for (const auto& t : triangles)
        mesh.triangles.emplace_back(t[0], t[1], t[2]);
    for (const auto& q : quads)
        mesh.quads.emplace_back(q[0], q[1], q[2], q[3]);
    return mesh;
}

/// The largest |sdf| over the samples of a mesh (vertices, centroids, edge midpoints).
double surfaceDeviation(const TestMesh& mesh, const test::Sdf& sdf) {
    double worst = 0.0;
    for (const Vec3d& p : test::surfaceSamples(mesh, kSpacing))
        worst = std::max(worst, std::abs(test::sdfAt(sdf, p)));
    return worst;
}

struct Case {
    std::string name;
    FloatGrid::Ptr grid;
    test::Sdf sdf;  // the analytic surface, when there is one
};

std::vector<Case> cases() {
    std::vector<Case> out;
    const std::pair<const char*, test::Sdf> shapes[] = {
        {"sphere", test::kSphere},
        {"torus", test::kTorus},
        {"cube", test::kCube},
        {"touching spheres", test::kTouchingSpheres}};
    for (const auto& [name, sdf] : shapes)
        out.push_back({name, test::levelSetOf(sdf, test::kBox128), sdf});
    // The sphere of the Enright test at 256^3, as createLevelSetSphere makes it.
    out.push_back({"enright sphere",
                   tools::createLevelSetSphere<FloatGrid>(0.15f, Vec3f(0.35f), 1.0f / 256.0f),
                   nullptr});
    // A level set scan-converted from a torus mesh: tiles inside, a band around.
    const TestMesh torus = test::makeTorusMesh(Vec3d(0.3, 0.1, -0.2), 1.0, 0.35, 96, 48);
    const auto xform = math::Transform::createLinearTransform(0.02);
    out.push_back(
        {"torus mesh",
         tools::meshToLevelSet<FloatGrid>(*xform, torus.points, torus.triangles, torus.quads),
         nullptr});
    return out;
}

TEST(VolumeToMeshCompat, AdaptivityZeroMatchesOpenVdb) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const auto theirsGrid = toOpenVdb(*c.grid);
        theirsGrid->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
        auto ours = c.grid->copy();  // meshed in index space, as OpenVDB's copy is
        ours->setTransform(math::Transform::createLinearTransform(1.0));
        const TestMesh mine = test::meshOf(*ours), theirs = openVdbMesh(*theirsGrid, 0.0);
        ASSERT_FALSE(theirs.quads.empty());
        const auto within1Percent = [](size_t a, size_t b) {
            return std::abs(double(a) - double(b)) <= 0.01 * double(b);
        };
        EXPECT_TRUE(within1Percent(mine.points.size(), theirs.points.size()))
            << mine.points.size() << " vs " << theirs.points.size();
        EXPECT_TRUE(within1Percent(mine.quads.size(), theirs.quads.size()))
            << mine.quads.size() << " vs " << theirs.quads.size();
        EXPECT_TRUE(mine.triangles.empty());
        const double distance = test::hausdorff(mine, theirs, 1.0, kSpacing);
        EXPECT_LT(distance, 0.25);
        const double volume = test::signedVolume(mine), reference = test::signedVolume(theirs);
        EXPECT_LT(volume, 0.0);
        EXPECT_LT(reference, 0.0);
        EXPECT_NEAR(volume / reference, 1.0, 1e-3);
        std::printf("  %-16s points %zu (OpenVDB %zu), quads %zu (%zu), Hausdorff %.4f voxels\n",
                    c.name.c_str(), mine.points.size(), theirs.points.size(), mine.quads.size(),
                    theirs.quads.size(), distance);
    }
}

TEST(VolumeToMeshCompat, AdaptiveMeshesStayAsCloseAsOpenVdbs) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        const auto theirsGrid = toOpenVdb(*c.grid);
        theirsGrid->setTransform(openvdb::math::Transform::createLinearTransform(1.0));
        auto ours = c.grid->copy();
        ours->setTransform(math::Transform::createLinearTransform(1.0));
        const TestMesh mine0 = test::meshOf(*ours), theirs0 = openVdbMesh(*theirsGrid, 0.0);
        const TestMesh mine = test::meshOf(*ours, 0.0, 0.5);
        const TestMesh theirs = openVdbMesh(*theirsGrid, 0.5);
        EXPECT_LT(mine.primitiveCount(), mine0.primitiveCount());
        EXPECT_TRUE(test::topologyOf(mine).closedManifold());
        EXPECT_LT(test::signedVolume(mine), 0.0);
        const double radius = 6.0;
        const double myGap = test::hausdorff(mine, mine0, radius, kCoarseSpacing);
        const double theirGap = test::hausdorff(theirs, theirs0, radius, kCoarseSpacing);
        EXPECT_LE(myGap, theirGap + 0.1);
        std::printf(
            "  %-16s adaptivity 0.5: %zu polygons (OpenVDB %zu); to the adaptivity-0 "
            "mesh %.3f (OpenVDB %.3f) voxels",
            c.name.c_str(), mine.primitiveCount(), theirs.primitiveCount(), myGap, theirGap);
        if (c.sdf) {
            const double mySurface = surfaceDeviation(mine, c.sdf);
            const double theirSurface = surfaceDeviation(theirs, c.sdf);
            EXPECT_LE(mySurface, theirSurface + 0.1);
            std::printf(", to the surface %.3f (OpenVDB %.3f)", mySurface, theirSurface);
        }
        std::printf("\n");
    }
}

TEST(VolumeToMeshCompat, FogVolumesAndTilesMatchOpenVdb) {
    // A fog volume: a 64^3 tile of density 1 with a Gaussian fall-off in voxels around it.
    auto grid = FloatGrid::create(0.0f);
    grid->setGridClass(GRID_FOG_VOLUME);
    grid->tree().fill(CoordBBox(Coord(0), Coord(63)), 1.0f, true);
    auto acc = grid->getAccessor();
    for (Int32 i = -8; i < 72; ++i)
        for (Int32 j = -8; j < 72; ++j)
            for (Int32 k = -8; k < 72; ++k) {
                const Coord ijk(i, j, k);
                const int outside = std::max({-i, i - 63, -j, j - 63, -k, k - 63});
                if (outside > 0)
                    acc.setValue(ijk, float(std::exp(-0.1 * outside * outside)));
            }
    const auto theirsGrid = toOpenVdb(*grid);
    for (const double iso : {0.5, 0.05}) {
        SCOPED_TRACE(iso);
        const TestMesh mine = test::meshOf(*grid, iso);
        std::vector<openvdb::Vec3s> points;
        std::vector<openvdb::Vec4I> quads;
        openvdb::tools::volumeToMesh(*theirsGrid, points, quads, iso);
        EXPECT_EQ(mine.points.size(), points.size());
        EXPECT_EQ(mine.quads.size(), quads.size());
        TestMesh theirs;
        for (const auto& p : points)
            theirs.points.emplace_back(p[0], p[1], p[2]);
        for (const auto& q : quads)
            theirs.quads.emplace_back(q[0], q[1], q[2], q[3]);
        EXPECT_LT(test::hausdorff(mine, theirs, 1.0, kSpacing), 0.25);
        // Fog volumes wind the other way round in both libraries: the inside is above.
        EXPECT_LT(test::signedVolume(mine), 0.0);
        EXPECT_NEAR(test::signedVolume(mine) / test::signedVolume(theirs), 1.0, 1e-3);
    }
}

}  // namespace
}  // namespace vdb
