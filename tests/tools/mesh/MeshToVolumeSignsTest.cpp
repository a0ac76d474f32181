// SPDX-License-Identifier: Apache-2.0
// Signs of meshes with defects (holes, a face turned over, T-junctions, a non-manifold fin,
// duplicated points, overlapping closed parts), against independent oracles: the exact
// generalized winding number by brute force over every triangle (L'Huilier's spherical excess,
// tests/support/TestMeshes.h), or, for a closed mesh with a face turned over, the parity of ray
// crossings (which ignores orientation). Points are sampled from the band and from a lattice
// over the box around the mesh; those within half a voxel of the surface or three voxels of an
// open edge are left out. Also: which mode MeshSign::Auto picks and why, bit-for-bit equality
// with MeshSign::FloodFill on closed meshes, and independence of the thread count.

#include <vdb/tools/MeshToVolume.h>
#include <vdb/vdb.h>

#include "GridContents.h"
#include "TestMeshes.h"
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <vector>

namespace vdb::tools {
namespace {

using test::OracleMesh;
using test::TestMesh;

constexpr double kNearSurface = 0.5;    // voxels
constexpr double kNearOpenEdges = 3.0;  // voxels

FloatGrid::Ptr convert(const TestMesh& mesh, double voxelSize, MeshSign sign,
                       MeshToVolumeReport* report = nullptr, bool threaded = true) {
    const auto xform = math::Transform::createLinearTransform(voxelSize);
    MeshToVolumeOptions options;
    options.sign = sign;
    options.threaded = threaded;
    return meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, options,
                                   report);
}

/// Signs of `grid` against the winding-number oracle of `mesh` (index space), or against the
/// ray-crossing parity when `byWinding` is false.
test::SignTally checkSigns(const FloatGrid& grid, const OracleMesh& mesh, bool byWinding = true,
                           int stride = 13, int boxStride = 3) {
    const auto acc = grid.getConstAccessor();
    return test::compareSigns(
        mesh, test::signSamples(grid, mesh, stride, boxStride), kNearSurface, kNearOpenEdges,
        [&](const Vec3d& p) { return acc.getValue(math::floorToCoord(p + 0.5)) < 0.0f; },
        [&](const Vec3d& p) { return byWinding ? mesh.insideByWinding(p) : mesh.inside(p); });
}

/// A sphere (radius 1.2) with three holes: two small ones and one a fifth of its size.
TestMesh sphereWithHoles() {
    const TestMesh sphere = test::makeSphereMesh(Vec3d(0.03, -0.02, 0.01), 1.2, 16, 32);
    const Vec3d dirs[3] = {Vec3d(0.0, 0.0, 1.0), Vec3d(0.8, 0.6, 0.0), Vec3d(-0.6, 0.0, -0.8)};
    const double cosines[3] = {0.97, 0.99, 0.98};
    return test::withoutTriangles(sphere, [&](const Vec3d& c) {
        const Vec3d d = (c - Vec3d(0.03, -0.02, 0.01)).unitSafe();
        for (int h = 0; h < 3; ++h) {
            if (d.dot(dirs[h]) > cosines[h])
                return true;
        }
        return false;
    });
}

TEST(MeshToVolumeSigns, AutoSignsClosedMeshesByFloodFillBitForBit) {
    const TestMesh meshes[] = {
        test::makeSphereMesh(Vec3d(0.1, 0.0, -0.1), 1.0, 12, 24),
        test::makeTorusMesh(Vec3d(0.0), 0.9, 0.3, 24, 10),
        test::makeCubeMesh(Vec3d(-0.5, -0.45, -0.55), 1.1, 3, /*quads=*/true),
    };
    for (const TestMesh& mesh : meshes) {
        MeshToVolumeReport report;
        const auto automatic = convert(mesh, 0.06, MeshSign::Auto, &report);
        EXPECT_EQ(report.sign, MeshSign::FloodFill);
        EXPECT_EQ(report.holes + report.boundaryEdges + report.nonManifoldEdges +
                      report.misorientedEdges + report.flippedFaces + report.mergedPoints,
                  0u);
        EXPECT_TRUE(test::sameContents(automatic->tree(),
                                       convert(mesh, 0.06, MeshSign::FloodFill)->tree()));
    }
    // The defaults of meshToLevelSet() are MeshSign::Auto.
    const auto xform = math::Transform::createLinearTransform(0.06);
    EXPECT_TRUE(test::sameContents(
        meshToLevelSet<FloatGrid>(*xform, meshes[0].points, meshes[0].triangles)->tree(),
        convert(meshes[0], 0.06, MeshSign::FloodFill)->tree()));
}

TEST(MeshToVolumeSigns, SphereWithHolesMatchesTheWindingNumberAwayFromTheHoles) {
    const double dx = 0.05;
    const TestMesh mesh = sphereWithHoles();
    const OracleMesh oracle = test::toIndexSpace(mesh, dx);
    MeshToVolumeReport report;
    const auto grid = convert(mesh, dx, MeshSign::Auto, &report);
    EXPECT_EQ(report.sign, MeshSign::WindingNumber);
    // Each hole is one loop, or two where its rim touches itself at a point.
    EXPECT_GE(report.holes, 3u);
    EXPECT_LE(report.holes, 6u);
    EXPECT_GT(report.boundaryEdges, 30u);
    const test::SignTally tally = checkSigns(*grid, oracle, true, 19, 4);
    EXPECT_GT(tally.checked, 1000);
    EXPECT_EQ(tally.wrong, 0) << "of " << tally.checked;
    // The scanlines of a flood fill run through the holes.
    EXPECT_GT(checkSigns(*convert(mesh, dx, MeshSign::FloodFill), oracle, true, 19, 4).wrong, 10);
}

TEST(MeshToVolumeSigns, FaceTurnedOverInAClosedCubeIsTurnedBack) {
    const TestMesh cube = test::makeCubeMesh(Vec3d(-0.52, -0.47, -0.49), 1.0, 3, false);
    TestMesh flipped = cube;
    // The face x = max: its 18 triangles, turned over.
    int turned = 0;
    for (Vec3I& t : flipped.triangles) {
        if (flipped.points[t[0]][0] > 0.47f && flipped.points[t[1]][0] > 0.47f &&
            flipped.points[t[2]][0] > 0.47f) {
            std::swap(t[1], t[2]);
            ++turned;
        }
    }
    ASSERT_EQ(turned, 18);
    MeshToVolumeReport report;
    const auto grid = convert(flipped, 0.04, MeshSign::Auto, &report);
    EXPECT_EQ(report.sign, MeshSign::FloodFill);
    EXPECT_EQ(report.flippedFaces, 18u);
    EXPECT_EQ(report.misorientedEdges, 12u);  // the face's border: 4 sides of 3 edges
    EXPECT_EQ(report.holes, 0u);
    EXPECT_TRUE(test::sameContents(grid->tree(), convert(cube, 0.04, MeshSign::Auto)->tree()));
    const OracleMesh oracle = test::toIndexSpace(flipped, 0.04);
    const test::SignTally tally = checkSigns(*grid, oracle, /*byWinding=*/false, 7, 2);
    EXPECT_GT(tally.checked, 1000);
    EXPECT_EQ(tally.wrong, 0);
    // WindingNumber keeps the faces as given: the turned face counts against the others.
    EXPECT_GT(
        checkSigns(*convert(flipped, 0.04, MeshSign::WindingNumber), oracle, false, 7, 2).wrong,
        10);
}

TEST(MeshToVolumeSigns, TJunctionsLeaveTheMeshClosed) {
    // A cube of 2 x 2 quads per face whose face x = min is two triangles over its corners:
    // the midpoints of that face's sides lie on its edges, where the neighbours meet them.
    TestMesh cube = test::makeCubeMesh(Vec3d(-0.51, -0.49, -0.48), 1.0, 2, /*quads=*/false);
    std::vector<Vec3I> kept;
    std::vector<Index32> corners;
    for (const Vec3I& t : cube.triangles) {
        bool onFace = true;
        for (int k = 0; k < 3; ++k)
            onFace = onFace && cube.points[t[k]][0] < -0.5f;
        if (!onFace)
            kept.push_back(t);
    }
    const auto at = [&](float y, float z) {
        for (Index32 i = 0; i < cube.points.size(); ++i) {
            const Vec3s& p = cube.points[i];
            if (p[0] < -0.5f && std::abs(p[1] - y) < 1e-4f && std::abs(p[2] - z) < 1e-4f)
                return i;
        }
        return Index32(0);
    };
    const Index32 a = at(-0.49f, -0.48f), b = at(0.51f, -0.48f), c = at(0.51f, 0.52f),
                  d = at(-0.49f, 0.52f);
    kept.emplace_back(a, c, b);  // seen from -x, counter-clockwise
    kept.emplace_back(a, d, c);
    cube.triangles = kept;
    MeshToVolumeReport report;
    const auto grid = convert(cube, 0.04, MeshSign::Auto, &report);
    EXPECT_EQ(report.boundaryEdges, 12u);  // 4 long edges and 8 halves
    EXPECT_EQ(report.holes, 0u);           // their loops enclose no area
    EXPECT_EQ(report.sign, MeshSign::FloodFill);
    const test::SignTally tally = checkSigns(*grid, test::toIndexSpace(cube, 0.04), true, 7, 2);
    EXPECT_GT(tally.checked, 1000);
    EXPECT_EQ(tally.wrong, 0);
}

TEST(MeshToVolumeSigns, NonManifoldFinIsSignedByWindingNumbers) {
    // A closed cube with a fin on one of its edges: three faces share that edge.
    TestMesh mesh = test::makeCubeMesh(Vec3d(-0.5), 1.0, 1, /*quads=*/false);
    Index32 e0 = 0, e1 = 0;
    for (Index32 i = 0; i < mesh.points.size(); ++i) {
        const Vec3s& p = mesh.points[i];
        if (p[0] > 0.4f && p[1] > 0.4f)
            (p[2] > 0.0f ? e1 : e0) = i;
    }
    mesh.points.emplace_back(1.0f, 1.0f, 0.0f);
    mesh.triangles.emplace_back(e0, e1, Index32(mesh.points.size() - 1));
    MeshToVolumeReport report;
    const auto grid = convert(mesh, 0.04, MeshSign::Auto, &report);
    EXPECT_EQ(report.nonManifoldEdges, 1u);
    EXPECT_EQ(report.boundaryEdges, 2u);
    EXPECT_EQ(report.holes, 1u);
    EXPECT_EQ(report.sign, MeshSign::WindingNumber);
    const test::SignTally tally = checkSigns(*grid, test::toIndexSpace(mesh, 0.04), true, 7, 2);
    EXPECT_GT(tally.checked, 1000);
    EXPECT_EQ(tally.wrong, 0);
}

TEST(MeshToVolumeSigns, DuplicatedPointsAreWelded) {
    const TestMesh sphere = test::makeSphereMesh(Vec3d(0.0), 1.0, 10, 20);
    const TestMesh soup = test::withDuplicatedPoints(sphere);
    MeshToVolumeReport report;
    const auto grid = convert(soup, 0.05, MeshSign::Auto, &report);
    EXPECT_EQ(report.mergedPoints, soup.points.size() - sphere.points.size());
    EXPECT_EQ(report.boundaryEdges, 0u);
    EXPECT_EQ(report.sign, MeshSign::FloodFill);
    EXPECT_TRUE(test::sameContents(grid->tree(), convert(sphere, 0.05, MeshSign::Auto)->tree()));
}

TEST(MeshToVolumeSigns, OverlappingClosedPartsAreTheirUnion) {
    const double dx = 0.04;
    const TestMesh mesh = test::merged(test::makeSphereMesh(Vec3d(-0.3, 0.0, 0.0), 0.7, 12, 24),
                                       test::makeSphereMesh(Vec3d(0.3, 0.05, 0.0), 0.6, 12, 24));
    MeshToVolumeReport report;
    const auto grid = convert(mesh, dx, MeshSign::Auto, &report);
    EXPECT_EQ(report.sign, MeshSign::FloodFill);
    // Where the spheres overlap the winding number is 2: inside.
    EXPECT_LT(grid->tree().getValue(Coord(0, 1, 0)), 0.0f);
    const OracleMesh oracle = test::toIndexSpace(mesh, dx);
    ASSERT_NEAR(oracle.windingNumber(Vec3d(0.0, 1.0, 0.0)), 2.0, 1e-9);
    const test::SignTally tally = checkSigns(*grid, oracle, true, 11, 3);
    EXPECT_GT(tally.checked, 1000);
    EXPECT_EQ(tally.wrong, 0);
}

TEST(MeshToVolumeSigns, HoleSignsDoNotDependOnTheThreadCount) {
    const TestMesh mesh = sphereWithHoles();
    const auto threaded = convert(mesh, 0.03, MeshSign::Auto);
    ASSERT_GT(threaded->tree().leafCount(), 300u);
    EXPECT_TRUE(test::sameContents(threaded->tree(),
                                   convert(mesh, 0.03, MeshSign::Auto, nullptr, false)->tree()));
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_TRUE(test::sameContents(threaded->tree(), convert(mesh, 0.03, MeshSign::Auto)->tree()));
}

}  // namespace
}  // namespace vdb::tools
