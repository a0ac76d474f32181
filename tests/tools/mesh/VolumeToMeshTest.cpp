// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic signed distance functions (sphere, torus, box, two touching spheres, a
// plate one voxel thick) for vertex positions, enclosed volume and area; the edge map and
// vertex fans of MeshMetrics.h for topology; the same grid with every tile written out as
// voxels for tiles; random fields for the ambiguous configurations smooth shapes never show.

#include <vdb/tools/VolumeToMesh.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/vdb.h>

#include "AnalyticLevelSets.h"
#include "MeshMetrics.h"
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <string>

namespace vdb::tools {
namespace {

using test::kBox128;
using test::kCube;
using test::kSphere;
using test::kTorus;
using test::largestDistance;
using test::levelSetOf;
using test::meshOf;
using test::Sdf;
using test::sdfAt;
using test::TestMesh;
constexpr double kPi = std::numbers::pi;

double relativeError(double value, double exact) {
    return std::abs(value - exact) / exact;
}

/// The sorted points and the number of quads, which must not depend on tiles.
std::pair<std::vector<std::array<float, 3>>, size_t> pointSet(const TestMesh& mesh) {
    std::vector<std::array<float, 3>> points;
    for (const Vec3s& p : mesh.points)
        points.push_back({p[0], p[1], p[2]});
    std::sort(points.begin(), points.end());
    return {points, mesh.quads.size()};
}

// ---- Analytic shapes at adaptivity 0 ----

/// The checks of a smooth closed shape at adaptivity 0: closed, two-manifold, the Euler
/// characteristic of its genus, quads only, every vertex within 0.05 voxel of the surface,
/// OpenVDB's (clockwise) winding, volume and area within 1%.
void expectSmoothShape(const Sdf& sdf, long euler, double volume, double area) {
    const TestMesh mesh = meshOf(*levelSetOf(sdf, kBox128));
    const auto topology = test::topologyOf(mesh);
    EXPECT_TRUE(topology.closedManifold());
    EXPECT_EQ(topology.euler, euler);
    EXPECT_TRUE(mesh.triangles.empty());
    EXPECT_LT(largestDistance(mesh, sdf), 0.05);
    const double signedVol = signedVolume(mesh);
    EXPECT_LT(signedVol, 0.0) << "OpenVDB's winding: clockwise seen from outside";
    EXPECT_LT(relativeError(-signedVol, volume), 0.01);
    EXPECT_LT(relativeError(surfaceArea(mesh), area), 0.01);
}

TEST(VolumeToMesh, SphereVerticesLieOnTheSurfaceOfAClosedMesh) {
    expectSmoothShape(kSphere, 2, 4.0 / 3.0 * kPi * 40.0 * 40.0 * 40.0, 4.0 * kPi * 40.0 * 40.0);
}

TEST(VolumeToMesh, TorusIsClosedWithOneHandle) {
    expectSmoothShape(kTorus, 0, 2.0 * kPi * kPi * 36.0 * 14.0 * 14.0,
                      4.0 * kPi * kPi * 36.0 * 14.0);
}

TEST(VolumeToMesh, BoxKeepsItsVolumeAndLosesOnlyItsEdges) {
    const Sdf& box = kCube;
    const TestMesh mesh = meshOf(*levelSetOf(box, kBox128));
    const auto topology = test::topologyOf(mesh);
    EXPECT_TRUE(topology.closedManifold());
    EXPECT_EQ(topology.euler, 2);
    EXPECT_LT(relativeError(-signedVolume(mesh), 80.0 * 80.0 * 80.0), 0.01);
    // Vertices are means of the edge crossings, as OpenVDB places them, so each of the 12
    // sharp edges is cut by a bevel about half a voxel wide: 1.2% of the area at this size.
    EXPECT_LT(relativeError(surfaceArea(mesh), 6.0 * 80.0 * 80.0), 0.015);
    // Faces stay flat: off the edges, every vertex lies on the box.
    for (const Vec3s& p : mesh.points) {
        const Vec3d q = Vec3d(p) - Vec3d(64.3, 63.8, 64.1);
        const int atFace =
            int(std::abs(q[0]) > 39.0) + int(std::abs(q[1]) > 39.0) + int(std::abs(q[2]) > 39.0);
        const double edgeDistance = 40.0 - std::max({std::abs(q[0]) > 39.0 ? 0.0 : std::abs(q[0]),
                                                     std::abs(q[1]) > 39.0 ? 0.0 : std::abs(q[1]),
                                                     std::abs(q[2]) > 39.0 ? 0.0 : std::abs(q[2])});
        if (atFace == 1 && edgeDistance > 2.0) {
            ASSERT_LT(std::abs(sdfAt(box, Vec3d(p))), 1e-4) << Vec3d(p)[0] << " " << Vec3d(p)[1];
        }
        ASSERT_LT(std::abs(sdfAt(box, Vec3d(p))), 0.5);
    }
}

TEST(VolumeToMesh, TouchingSpheresStayTwoManifold) {
    const TestMesh mesh = meshOf(*levelSetOf(test::kTouchingSpheres, kBox128));
    const auto topology = test::topologyOf(mesh);
    EXPECT_TRUE(topology.closedManifold());
    EXPECT_LT(relativeError(-signedVolume(mesh), 2.0 * 4.0 / 3.0 * kPi * 30.0 * 30.0 * 30.0), 0.01);
    EXPECT_LT(relativeError(surfaceArea(mesh), 2.0 * 4.0 * kPi * 30.0 * 30.0), 0.01);
}

TEST(VolumeToMesh, PlateOneVoxelThickGetsTwoSheets) {
    const Sdf& plate = test::kPlate;
    const auto grid = levelSetOf(plate, kBox128);
    const TestMesh mesh = meshOf(*grid);
    const auto topology = test::topologyOf(mesh);
    EXPECT_TRUE(topology.closedManifold());
    EXPECT_EQ(topology.euler, 2);
    // Away from the rim, one sheet lies exactly on each face of the plate.
    size_t top = 0, bottom = 0;
    for (const Vec3s& p : mesh.points) {
        const Vec3d q(p);
        if (std::abs(q[0] - 64.3) < 48.0 && std::abs(q[1] - 63.8) < 48.0) {
            ASSERT_TRUE(std::abs(q[2] - 64.5) < 1e-4 || std::abs(q[2] - 63.5) < 1e-4) << q[2];
            (q[2] > 64.0 ? top : bottom) += 1;
        }
        ASSERT_LT(std::abs(sdfAt(plate, q)), 0.5);
    }
    EXPECT_EQ(top, bottom);
    EXPECT_GT(top, 90u * 90u);
    // The sampled distances see only half a voxel of the rim, which rounds it off: the
    // volume and area lose about 2% (OpenVDB's meshes lose the same).
    EXPECT_LT(relativeError(-signedVolume(mesh), 100.0 * 100.0), 0.03);
    EXPECT_LT(relativeError(surfaceArea(mesh), 2.0 * 100.0 * 100.0 + 400.0), 0.03);
}

TEST(VolumeToMesh, ValuesAtTheIsovalueGiveNoCoincidentVertices) {
    // A cube whose faces pass through voxel centres: a layer of values exactly 0.
    const test::Sdf cube = test::boxSdf(64.0, 64.0, 64.0, 30.0, 20.0, 25.0);
    const TestMesh mesh = meshOf(*levelSetOf(cube, kBox128));
    EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
    const auto points = pointSet(mesh).first;
    EXPECT_EQ(std::adjacent_find(points.begin(), points.end()), points.end());
    // Within two thirds of a voxel, at the cube's corners (the mean of three crossings).
    EXPECT_LT(largestDistance(mesh, cube), 0.67);
}

// ---- Adaptivity ----

TEST(VolumeToMesh, AdaptivityMergesFlatRegionsAndKeepsTopology) {
    const struct {
        const char* name;
        Sdf sdf;
        double vertexTolerance;
    } shapes[] = {{"sphere", kSphere, 0.05}, {"torus", kTorus, 0.05}, {"box", kCube, 0.5}};
    for (const auto& shape : shapes) {
        SCOPED_TRACE(shape.name);
        const auto grid = levelSetOf(shape.sdf, kBox128);
        const TestMesh fine = meshOf(*grid);
        const auto fineTopology = test::topologyOf(fine);
        size_t previous = fine.primitiveCount();
        for (const double adaptivity : {0.1, 0.5, 1.0}) {
            SCOPED_TRACE(adaptivity);
            const TestMesh coarse = meshOf(*grid, 0.0, adaptivity);
            const auto topology = test::topologyOf(coarse);
            EXPECT_TRUE(topology.closedManifold());
            EXPECT_EQ(topology.euler, fineTopology.euler);
            EXPECT_LT(coarse.primitiveCount(), fine.primitiveCount() / 4);
            EXPECT_LE(coarse.primitiveCount(), previous);
            previous = coarse.primitiveCount();
            EXPECT_LT(largestDistance(coarse, shape.sdf), shape.vertexTolerance);
            EXPECT_LT(signedVolume(coarse), 0.0);
            EXPECT_LT(relativeError(signedVolume(coarse), signedVolume(fine)), 0.05);
        }
    }
}

TEST(VolumeToMesh, TrianglesAppearOnlyBetweenRegionsOfDifferentSizes) {
    const auto grid = levelSetOf(kSphere, kBox128);
    const TestMesh uniform = meshOf(*grid, 0.0, 0.0);
    EXPECT_TRUE(uniform.triangles.empty());
    const TestMesh adaptive = meshOf(*grid, 0.0, 0.05);
    EXPECT_FALSE(adaptive.triangles.empty());
    EXPECT_GT(adaptive.quads.size(), adaptive.triangles.size());
    for (const Vec3I& t : adaptive.triangles)
        ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
}

// ---- Ambiguous configurations ----

/// A field of uniform random values in (-1, 1) over an n^3 block (+1 on its border, so the
/// surface is closed), optionally added to a sphere's distance: every cell configuration,
/// ambiguous faces included, occurs many times.
FloatGrid::Ptr noiseField(unsigned seed, int n, double sphereWeight) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> noise(-1.0f, 1.0f);
    auto grid = FloatGrid::create(1.0f);
    grid->setGridClass(GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                float v = noise(rng);
                if (sphereWeight > 0.0)
                    v += float((Vec3d(i, j, k) - Vec3d(n / 2.0)).length() - n / 3.0) *
                         float(sphereWeight);
                const bool border =
                    i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
                acc.setValue(Coord(i - 5, j - 3, k - 7), border ? 1.0f : v);
            }
    return grid;
}

TEST(VolumeToMesh, NoiseFieldsGiveClosedTwoManifoldMeshes) {
    for (unsigned seed = 0; seed < 6; ++seed) {
        SCOPED_TRACE(seed);
        const auto grid = noiseField(seed, 22, 0.0);
        const TestMesh fine = meshOf(*grid);
        const auto topology = test::topologyOf(fine);
        ASSERT_TRUE(topology.closedManifold())
            << topology.unpairedEdges << " unpaired, " << topology.repeatedEdges << " repeated, "
            << topology.badVertices << " bad vertices";
        EXPECT_LT(signedVolume(fine), 0.0);
        for (const double adaptivity : {0.5, 1.0}) {
            const auto coarse = test::topologyOf(meshOf(*grid, 0.0, adaptivity));
            EXPECT_TRUE(coarse.closedManifold());
            EXPECT_EQ(coarse.euler, topology.euler);
        }
    }
    // A rough sphere (with a few bubbles): large regions merge across the noise.
    const auto grid = noiseField(7, 40, 2.0);
    const TestMesh fine = meshOf(*grid);
    const auto fineTopology = test::topologyOf(fine);
    EXPECT_TRUE(fineTopology.closedManifold());
    for (const double adaptivity : {0.5, 1.0}) {
        const TestMesh coarse = meshOf(*grid, 0.0, adaptivity);
        const auto topology = test::topologyOf(coarse);
        EXPECT_TRUE(topology.closedManifold());
        EXPECT_EQ(topology.euler, fineTopology.euler);
        EXPECT_LT(coarse.primitiveCount(), fine.primitiveCount() * 3 / 4);
    }
}

// ---- Tiles ----

/// A copy of `grid` over `box` with every value written as a voxel: no tiles.
template <typename GridT>
typename GridT::Ptr voxelized(const GridT& grid, const CoordBBox& box) {
    auto out = GridT::create(grid.background());
    out->setGridClass(grid.getGridClass());
    auto acc = out->getAccessor();
    const auto src = grid.getConstAccessor();
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                acc.setValue(Coord(i, j, k), src.getValue(Coord(i, j, k)));
    return out;
}

/// Meshes `grid`, and a copy over `box` (which must hold every tile and voxel, with a margin)
/// that has no tiles; both meshes must be the same.
template <typename GridT>
void expectTilesMeshLikeVoxels(const GridT& grid, const CoordBBox& box, double isovalue) {
    const auto dense = voxelized(grid, box);
    const TestMesh tiled = meshOf(grid, isovalue), voxels = meshOf(*dense, isovalue);
    EXPECT_TRUE(test::topologyOf(tiled).closedManifold());
    EXPECT_FALSE(tiled.quads.empty());
    EXPECT_EQ(pointSet(tiled), pointSet(voxels));
}

TEST(VolumeToMesh, TilesAtEveryLevelAreMeshedAsVoxels) {
    {
        SCOPED_TRACE("a fog volume of a 128^3 tile, 8^3 tiles, voxels, and a hole");
        auto grid = FloatGrid::create(0.0f);
        grid->setGridClass(GRID_FOG_VOLUME);
        grid->tree().fill(CoordBBox(Coord(-8, 0, 0), Coord(135, 127, 127)), 1.0f, true);
        grid->tree().fill(CoordBBox(Coord(130, 3, 5), Coord(150, 20, 33)), 0.0f, true);
        grid->tree().setValue(Coord(200, 5, 5), 1.0f);
        grid->tree().setValue(Coord(136, 64, 64), 0.2f);
        EXPECT_GT(grid->tree().activeTileCount(), 0u);
        expectTilesMeshLikeVoxels(*grid, CoordBBox(Coord(-10, -2, -2), Coord(202, 130, 130)), 0.5);
    }
    {
        SCOPED_TRACE("root tiles of a small configuration");
        using SmallTree = tree::Tree<
            tree::RootNode<tree::InternalNode<tree::InternalNode<tree::LeafNode<float, 2>, 2>, 2>>>;
        auto grid = Grid<SmallTree>::create(0.0f);
        grid->setGridClass(GRID_FOG_VOLUME);
        grid->tree().fill(CoordBBox(Coord(0), Coord(63)), 1.0f, true);
        grid->tree().fill(CoordBBox(Coord(64, 0, 0), Coord(127, 63, 63)), 0.7f, true);
        grid->tree().fill(CoordBBox(Coord(-64), Coord(-1)), 1.0f, false);
        grid->tree().setValue(Coord(10, 70, 3), 1.0f);
        EXPECT_GT(grid->tree().activeTileCount(), 0u);
        expectTilesMeshLikeVoxels(*grid, CoordBBox(Coord(-66), Coord(130, 72, 66)), 0.5);
    }
    {
        SCOPED_TRACE("a level set whose inside is tiles, with a pocket of tiles");
        auto grid = FloatGrid::create(3.0f);
        grid->setGridClass(GRID_LEVEL_SET);
        grid->tree().fill(CoordBBox(Coord(0), Coord(127)), -3.0f, false);
        grid->tree().fill(CoordBBox(Coord(16), Coord(31)), 3.0f, true);
        grid->tree().setValue(Coord(64, 64, 64), 1.5f);
        expectTilesMeshLikeVoxels(*grid, CoordBBox(Coord(-2), Coord(130)), 0.0);
    }
    {
        SCOPED_TRACE("a bounded tree, tiles against the domain's edge");
        auto grid = Grid<tree::FixedTree643<float>>::create(0.0f);
        grid->setGridClass(GRID_FOG_VOLUME);
        grid->tree().fill(CoordBBox(Coord(-2048), Coord(-1921)), 1.0f, true);
        grid->tree().fill(CoordBBox(Coord(-1900), Coord(-1893)), 1.0f, true);
        grid->tree().setValue(Coord(-1800), 1.0f);
        const TestMesh mesh = meshOf(*grid, 0.5);
        // The domain's faces are not meshed: beyond them lies the background, 0.
        EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
        const auto dense = voxelized(*grid, CoordBBox(Coord(-2048), Coord(-1795)));
        EXPECT_EQ(pointSet(mesh), pointSet(meshOf(*dense, 0.5)));
    }
}

// ---- Fog volumes, isovalues, orientation ----

TEST(VolumeToMesh, FogVolumeAtAnIsovalueIsItsLevelSurface) {
    // A Gaussian blob: density exp(-r^2 / s^2) is 0.5 at r = s sqrt(ln 2).
    const double s = 20.0;
    auto grid = FloatGrid::create(0.0f);
    grid->setGridClass(GRID_FOG_VOLUME);
    auto acc = grid->getAccessor();
    const Vec3d c(0.3, -0.2, 0.1);
    for (Int32 i = -48; i <= 48; ++i)
        for (Int32 j = -48; j <= 48; ++j)
            for (Int32 k = -48; k <= 48; ++k) {
                const double r2 = (Vec3d(i, j, k) - c).lengthSqr();
                if (r2 < 46.0 * 46.0)
                    acc.setValue(Coord(i, j, k), float(std::exp(-r2 / (s * s))));
            }
    for (const double iso : {0.5, 0.1}) {
        SCOPED_TRACE(iso);
        const double radius = s * std::sqrt(-std::log(iso));
        const TestMesh mesh = meshOf(*grid, iso);
        EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
        EXPECT_LT(signedVolume(mesh), 0.0) << "inside (above the isovalue) to the right";
        double worst = 0.0;
        for (const Vec3s& p : mesh.points)
            worst = std::max(worst, std::abs((Vec3d(p) - c).length() - radius));
        // Linear interpolation of an exponential: a little more than for distances.
        EXPECT_LT(worst, 0.1);
    }
}

TEST(VolumeToMesh, OrientationFollowsTheGridClass) {
    auto grid = levelSetOf(kSphere, kBox128);
    EXPECT_LT(signedVolume(meshOf(*grid)), 0.0);
    grid->setGridClass(GRID_UNKNOWN);  // inside is above the isovalue: the sphere's exterior
    EXPECT_GT(signedVolume(meshOf(*grid)), 0.0);
    grid->setGridClass(GRID_FOG_VOLUME);
    EXPECT_GT(signedVolume(meshOf(*grid)), 0.0);
}

TEST(VolumeToMesh, EmptyAndUniformGridsGiveEmptyMeshes) {
    TestMesh mesh;
    mesh.points.resize(3);
    mesh.quads.resize(1);
    mesh.triangles.resize(1);
    volumeToMesh(*FloatGrid::create(1.0f), mesh.points, mesh.triangles, mesh.quads);
    EXPECT_TRUE(mesh.points.empty() && mesh.quads.empty() && mesh.triangles.empty());

    auto uniform = FloatGrid::create(1.0f);
    uniform->tree().fill(CoordBBox(Coord(0), Coord(40)), 2.0f, true);
    uniform->tree().setValue(Coord(100), 5.0f);
    EXPECT_EQ(meshOf(*uniform).primitiveCount(), 0u);

    // An isovalue outside the values: nothing crosses it.
    const auto sphere = levelSetOf(kSphere, kBox128);
    EXPECT_EQ(meshOf(*sphere, 10.0).primitiveCount(), 0u);
    EXPECT_EQ(meshOf(*sphere, -10.0, 0.5).primitiveCount(), 0u);
}

TEST(VolumeToMesh, BadArgumentsAndValuesThrow) {
    auto grid = levelSetOf(kSphere, kBox128);
    TestMesh mesh;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(volumeToMesh(*grid, mesh.points, mesh.quads, nan), ValueError);
    EXPECT_THROW(volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads, 0.0, -0.5),
                 ValueError);
    EXPECT_THROW(volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads, 0.0, nan),
                 ValueError);
    // A NaN next to the surface (its neighbour is inside): no silent hole.
    Coord ijk(103, 64, 63);
    while (grid->tree().getValue(ijk) >= 0.0f)
        ijk[0] -= 1;
    grid->tree().setValue(ijk.offsetBy(1, 0, 0), std::numeric_limits<float>::quiet_NaN());
    EXPECT_THROW(volumeToMesh(*grid, mesh.points, mesh.quads), ValueError);
}

TEST(VolumeToMesh, GridsOfOtherValueTypesAreATypeError) {
    TestMesh mesh;
    const GridBase::Ptr grids[] = {Vec3SGrid::create(), Int32Grid::create(), BoolGrid::create(),
                                   MaskGrid::create()};
    for (const auto& grid : grids)
        EXPECT_THROW(volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads), TypeError);
    const GridBase::Ptr sphere = levelSetOf(kSphere, kBox128);
    volumeToMesh(*sphere, mesh.points, mesh.triangles, mesh.quads);
    EXPECT_EQ(pointSet(mesh), pointSet(meshOf(*gridPtrCast<FloatGrid>(sphere))));
}

// ---- Threads, value types, transforms ----

TEST(VolumeToMesh, ResultDoesNotDependOnTheThreadCount) {
    const auto grids = {noiseField(3, 40, 2.0), levelSetOf(kTorus, kBox128)};
    for (const auto& grid : grids) {
        for (const double adaptivity : {0.0, 0.5}) {
            const TestMesh many = meshOf(*grid, 0.0, adaptivity);
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            const TestMesh single = meshOf(*grid, 0.0, adaptivity);
            EXPECT_EQ(many.points, single.points);
            EXPECT_EQ(many.quads, single.quads);
            EXPECT_EQ(many.triangles, single.triangles);
        }
    }
}

TEST(VolumeToMesh, DoubleGridGivesTheFloatGridsMesh) {
    const auto f = levelSetOf<FloatGrid>(kTorus, kBox128);
    const auto d = levelSetOf<DoubleGrid>(
        [](double x, double y, double z) { return double(float(kTorus(x, y, z))); }, kBox128);
    for (const double adaptivity : {0.0, 0.5}) {
        const TestMesh a = meshOf(*f, 0.0, adaptivity), b = meshOf(*d, 0.0, adaptivity);
        EXPECT_EQ(a.points, b.points);
        EXPECT_EQ(a.quads, b.quads);
        EXPECT_EQ(a.triangles, b.triangles);
    }
}

TEST(VolumeToMesh, PointsAreInWorldSpace) {
    auto grid = levelSetOf(kTorus, kBox128);
    const TestMesh index = meshOf(*grid);
    auto xform = math::Transform::createLinearTransform(0.25);
    xform->postTranslate(Vec3d(-3.0, 7.5, 100.0));
    grid->setTransform(xform);
    const TestMesh world = meshOf(*grid);
    ASSERT_EQ(world.points.size(), index.points.size());
    EXPECT_EQ(world.quads, index.quads);
    for (size_t n = 0; n < world.points.size(); ++n) {
        const Vec3d expected = xform->indexToWorld(Vec3d(index.points[n]));
        ASSERT_LT((Vec3d(world.points[n]) - expected).length(), 1e-4);
    }
}

TEST(VolumeToMesh, QuadOverloadIsAdaptivityZero) {
    const auto grid = levelSetOf(kTorus, kBox128);
    TestMesh a;
    volumeToMesh(*grid, a.points, a.quads);
    const TestMesh b = meshOf(*grid);
    EXPECT_EQ(a.points, b.points);
    EXPECT_EQ(a.quads, b.quads);
}

TEST(VolumeToMesh, OtherLeafSizesGiveTheSameSurface) {
    const auto standard = levelSetOf(kSphere, kBox128);
    const auto small = levelSetOf<Grid<tree::HashTree432<float>>>(kSphere, kBox128);
    const auto large = levelSetOf<Grid<tree::FixedTree6544<float>>>(kSphere, kBox128);
    // Vertices are computed relative to their leaf, so their last bits may differ.
    const TestMesh reference = meshOf(*standard);
    for (const auto& mesh : {meshOf(*small), meshOf(*large)}) {
        EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
        EXPECT_EQ(mesh.points.size(), reference.points.size());
        EXPECT_EQ(mesh.quads.size(), reference.quads.size());
        EXPECT_LT(test::largestPointGap(mesh, reference, 0.01), 1e-4);
        EXPECT_LT(test::largestPointGap(reference, mesh, 0.01), 1e-4);
    }
}

TEST(VolumeToMesh, RelaxingDisorientedTrianglesKeepsTheMeshClosed) {
    const auto grid = noiseField(11, 40, 2.0);
    const TestMesh relaxed = meshOf(*grid, 0.0, 1.0, true);
    const TestMesh kept = meshOf(*grid, 0.0, 1.0, false);
    EXPECT_EQ(relaxed.quads, kept.quads);
    EXPECT_EQ(relaxed.triangles, kept.triangles);
    EXPECT_TRUE(test::topologyOf(relaxed).closedManifold());
    EXPECT_NE(relaxed.points, kept.points);
}

}  // namespace
}  // namespace vdb::tools
