// SPDX-License-Identifier: Apache-2.0
// Oracles: the exact distance to the mesh by brute force over every triangle (closest point
// by Voronoi regions, tests/support/TestMeshes.h), inside/outside by ray casting in three skew
// directions, and the analytic sphere for the mesh with a hole. Every voxel of the mesh's
// bounding box grown by the band is checked: active exactly within the band, values within
// 1e-4 voxels of the oracle, signs and the inactive values beyond the band from the oracle.

#include <vdb/tools/MeshToVolume.h>
#include <vdb/vdb.h>

#include "GridContents.h"
#include "Oracles.h"
#include "TestMeshes.h"
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

namespace vdb::tools {
namespace {

using test::OracleMesh;
using test::TestMesh;

constexpr double kTolerance = 1e-4;  // voxels

struct BandCheck {
    double exBand = 3.0, inBand = 3.0;
    bool isSigned = true;
    /// Checks only every `stride`-th voxel (by i + j + k) that lies beyond the band.
    int farStride = 5;
};

/// True for the voxels the oracle is asked about. A full workload asks about all of them; a
/// reduced one (VDB_TEST_WORKLOAD, the sanitizer runs) about a fixed pseudo-random one in
/// round(1 / workload) of them: the conversion still runs whole, on the same meshes, and the
/// brute-force distances, which cost the mesh's triangle count per voxel, are the part cut.
bool sampled(const Coord& ijk) {
    static const uint32_t every = uint32_t(std::lround(1.0 / test::workloadScale()));
    return every <= 1 || ijk.hash() % every == 0;
}

/// Compares every voxel of the mesh's box grown by the band with the oracles (a sample of
/// them under a reduced test workload: sampled()).
::testing::AssertionResult matchesOracle(const FloatGrid& grid, const OracleMesh& mesh,
                                         double voxelSize, const BandCheck& check) {
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3d& p : mesh.points) {
        lo = Vec3d::minComponent(lo, p);
        hi = Vec3d::maxComponent(hi, p);
    }
    const double grow = std::max(check.exBand, check.inBand) + 2.0;
    const Coord a = math::floorToCoord(lo - grow), b = math::floorToCoord(hi + grow) + Coord(1);
    const float outside = float(check.exBand * voxelSize);
    const float inside = float(-check.inBand * voxelSize);
    const auto acc = grid.getConstAccessor();
    int failures = 0;
    std::ostringstream msg;
    const auto fail = [&](const Coord& ijk, const std::string& what) {
        if (++failures <= 8)
            msg << "\n  " << ijk << ": " << what;
    };
    Index64 checkedActive = 0;
    for (Int32 i = a[0]; i <= b[0]; ++i) {
        for (Int32 j = a[1]; j <= b[1]; ++j) {
            for (Int32 k = a[2]; k <= b[2]; ++k) {
                const Coord ijk(i, j, k);
                if (!sampled(ijk))
                    continue;
                const Vec3d p(ijk);
                const double d = mesh.distance(p);
                const double band = std::max(check.exBand, check.inBand);
                if (d >= band + 1e-9 && (i + j + k) % check.farStride != 0)
                    continue;
                const bool in = check.isSigned && d > 1e-6 && mesh.inside(p);
                const double bandOfSide = in ? check.inBand : check.exBand;
                float value = 0;
                const bool on = acc.probeValue(ijk, value);
                if (std::abs(d - bandOfSide) < 1e-9)
                    continue;  // on the band's edge: either state is right
                if (on != (d < bandOfSide)) {
                    fail(ijk, std::string(on ? "active" : "inactive") + " at distance " +
                                  std::to_string(d));
                    continue;
                }
                if (on) {
                    ++checkedActive;
                    const double expected = in ? -d : d;
                    if (!(std::abs(double(value) / voxelSize - expected) < kTolerance)) {
                        fail(ijk, "value " + std::to_string(value / voxelSize) + " expected " +
                                      std::to_string(expected));
                    }
                } else if (d > 1e-6) {
                    const float expected = in ? inside : outside;
                    if (value != expected) {
                        fail(ijk, "inactive value " + std::to_string(value) + " expected " +
                                      std::to_string(expected));
                    }
                }
            }
        }
    }
    if (checkedActive == 0)
        return ::testing::AssertionFailure() << "no active voxel was checked";
    if (failures > 0)
        return ::testing::AssertionFailure() << failures << " voxels differ:" << msg.str();
    return ::testing::AssertionSuccess() << checkedActive << " active voxels match";
}

FloatGrid::Ptr convert(const TestMesh& mesh, double voxelSize, const MeshToVolumeOptions& options,
                       const Vec3d& offset = Vec3d(0.0)) {
    auto xform = math::Transform::createLinearTransform(voxelSize);
    xform->postTranslate(offset);
    return meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, options);
}

TEST(MeshToVolume, SphereMatchesBruteForceDistancesAndRayCastSigns) {
    const double dx = 0.1;
    const TestMesh mesh = test::makeSphereMesh(Vec3d(0.13, -0.21, 0.07), 1.2, 16, 30);
    const auto grid = convert(mesh, dx, {});
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    EXPECT_FLOAT_EQ(grid->background(), 0.3f);
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {}));
    // Far from the band: the centre is an inside tile or voxel, a far point the background.
    EXPECT_FLOAT_EQ(grid->tree().getValue(Coord(1, -2, 1)), -0.3f);
    EXPECT_FLOAT_EQ(grid->tree().getValue(Coord(500, 0, 0)), 0.3f);
}

TEST(MeshToVolume, CubeOfQuadsMatchesBruteForceWithUnequalBands) {
    const double dx = 0.25;
    const TestMesh mesh = test::makeCubeMesh(Vec3d(-1.03, -0.97, -1.11), 4.1, 4, /*quads=*/true);
    MeshToVolumeOptions options;
    options.exteriorBandWidth = 2.0f;
    options.interiorBandWidth = 4.5f;
    const auto grid = convert(mesh, dx, options);
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {2.0, 4.5, true, 5}));
}

TEST(MeshToVolume, DenseMeshAtACoarseVoxelSizeMatchesBruteForce) {
    // About 3,500 triangles on a sphere of radius 8 voxels, 4.4 triangles per voxel of area,
    // with a band of 5 voxels: each leaf is reached by well over a thousand triangles, so the
    // distances come from the per-voxel queries of the triangle hierarchy, not the raster.
    const double dx = 0.1;
    const TestMesh mesh = test::makeSphereMesh(Vec3d(0.013, -0.021, 0.007), 0.8, 30, 60);
    MeshToVolumeOptions options;
    options.exteriorBandWidth = 5.0f;
    options.interiorBandWidth = 5.0f;
    const auto grid = convert(mesh, dx, options);
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {5.0, 5.0, true, 7}));
    // The same grid with one thread.
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_TRUE(test::sameContents(grid->tree(), convert(mesh, dx, options)->tree()));
}

TEST(MeshToVolume, QuadsEqualTheirSplitTriangles) {
    const TestMesh quads = test::makeCubeMesh(Vec3d(0.3, 0.2, 0.1), 3.0, 3, true);
    TestMesh tris = quads;
    tris.triangles = quads.allTriangles();
    tris.quads.clear();
    EXPECT_TRUE(
        test::sameContents(convert(quads, 0.2, {})->tree(), convert(tris, 0.2, {})->tree()));
}

TEST(MeshToVolume, TorusMatchesBruteForceDistancesAndRayCastSigns) {
    const double dx = 0.05;
    const TestMesh mesh = test::makeTorusMesh(Vec3d(0.01, 0.02, -0.03), 0.8, 0.3, 32, 12);
    const auto grid = convert(mesh, dx, {});
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {}));
    // The hole of the torus is outside.
    EXPECT_GT(grid->tree().getValue(Coord(0, 0, 0)), 0.0f);
}

TEST(MeshToVolume, ReversedOrientationGivesTheSameLevelSet) {
    // Same band, same signs; values may differ in the last bits (vertex order changes the
    // arithmetic).
    TestMesh mesh = test::makeTorusMesh(Vec3d(0.0), 0.8, 0.3, 24, 10);
    const auto grid = convert(mesh, 0.07, {});
    for (Vec3I& t : mesh.triangles)
        std::swap(t[1], t[2]);
    const auto reversed = convert(mesh, 0.07, {});
    EXPECT_EQ(grid->activeVoxelCount(), reversed->activeVoxelCount());
    for (auto it = grid->tree().cbeginValueAll(); it; ++it) {
        float value = 0;
        const bool on = reversed->tree().probeValue(it.getCoord(), value);
        ASSERT_EQ(on, it.isValueOn()) << it.getCoord();
        ASSERT_NEAR(value, *it, 1e-6) << it.getCoord();
    }
}

TEST(MeshToVolume, UnsignedDistancesMatchBruteForce) {
    const double dx = 0.1;
    const TestMesh mesh = test::makeSphereMesh(Vec3d(0.0), 0.9, 10, 20);
    MeshToVolumeOptions options;
    options.sign = MeshSign::Unsigned;
    options.exteriorBandWidth = 2.5f;
    const auto grid = convert(mesh, dx, options);
    EXPECT_EQ(grid->getGridClass(), GRID_UNKNOWN);
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {2.5, 2.5, false, 5}));
    EXPECT_FLOAT_EQ(grid->tree().getValue(Coord(0, 0, 0)), 0.25f);
}

TEST(MeshToVolume, DenseTiltedMeshesFarFromTheOriginMatchBruteForce) {
    // Dense meshes take the per-voxel queries, whose hierarchy bounds each node's triangles
    // by an axis-aligned box and by a box along their mean normal: a tilted plate (a thin
    // oriented box), and a dense sphere at index coordinates near 1e6 (where the rounding of
    // the oriented boxes is largest).
    const double dx = 0.1;
    MeshToVolumeOptions options;
    options.exteriorBandWidth = 5.0f;
    options.interiorBandWidth = 5.0f;
    {
        TestMesh plate = test::makeCubeMesh(Vec3d(-0.8, -0.8, -0.8), 1.6, 16, /*quads=*/false);
        const double c = std::cos(0.6), s = std::sin(0.6), c2 = std::cos(0.4), s2 = std::sin(0.4);
        for (Vec3s& q : plate.points) {
            Vec3d p(q[0], q[1], 0.3 * q[2]);  // the cube flattened into a plate
            p = Vec3d(c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]);
            q = Vec3s(Vec3d(p[0], c2 * p[1] - s2 * p[2], s2 * p[1] + c2 * p[2]));
        }
        const auto grid = convert(plate, dx, options);
        EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(plate, dx), dx, {5.0, 5.0, true, 7}));
    }
    {
        TestMesh sphere = test::makeSphereMesh(Vec3d(0.0), 0.8, 24, 48);
        sphere.translate(Vec3d(1.0e5, -2.0e5, 0.5e5));
        const auto grid = convert(sphere, dx, options);
        EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(sphere, dx), dx, {5.0, 5.0, true, 7}));
    }
}

TEST(MeshToVolume, MeshFarFromTheOriginMatchesBruteForce) {
    // World coordinates near 1e5 (index coordinates near 1e6): the points are floats, the
    // index-space arithmetic is double.
    const double dx = 0.1;
    const Vec3d offset(1.0e5, -2.0e5, 0.5e5);
    TestMesh mesh = test::makeSphereMesh(Vec3d(0.0), 1.0, 12, 20);
    mesh.translate(offset);
    const auto grid = convert(mesh, dx, {});
    EXPECT_TRUE(matchesOracle(*grid, test::toIndexSpace(mesh, dx), dx, {}));
}

TEST(MeshToVolume, BoundingResolutionAbove4096Works) {
    // Two small closed spheres 5000 voxels apart in one mesh, checked near both.
    const double dx = 1.0;
    TestMesh mesh = test::makeSphereMesh(Vec3d(-2500.3, 7.1, 3.2), 6.0, 10, 16);
    const TestMesh other = test::makeSphereMesh(Vec3d(2500.6, -3.7, 2500.2), 5.0, 10, 16);
    const Index32 base = Index32(mesh.points.size());
    mesh.points.insert(mesh.points.end(), other.points.begin(), other.points.end());
    for (const Vec3I& t : other.triangles)
        mesh.triangles.emplace_back(t[0] + base, t[1] + base, t[2] + base);
    const auto grid = convert(mesh, dx, {});
    CoordBBox bbox;
    ASSERT_TRUE(grid->tree().evalActiveVoxelBoundingBox(bbox));
    EXPECT_GT(bbox.dim()[0], 4096);
    // Check around each sphere (the box of the whole mesh is too large to visit).
    const OracleMesh oracle = test::toIndexSpace(mesh, dx);
    const auto near = [&](const Vec3d& c, double r) {
        int bad = 0;
        for (Int32 i = -Int32(r) - 5; i <= Int32(r) + 5; ++i) {
            for (Int32 j = -Int32(r) - 5; j <= Int32(r) + 5; ++j) {
                for (Int32 k = -Int32(r) - 5; k <= Int32(r) + 5; ++k) {
                    const Coord ijk = math::floorToCoord(c) + Coord(i, j, k);
                    const double d = oracle.distance(Vec3d(ijk));
                    if (d >= 3.0 || d < 1e-6)
                        continue;
                    const bool in = oracle.inside(Vec3d(ijk));
                    float value = 0;
                    if (!grid->tree().probeValue(ijk, value) ||
                        !(std::abs(value - (in ? -d : d)) < kTolerance)) {
                        ++bad;
                    }
                }
            }
        }
        return bad;
    };
    EXPECT_EQ(near(Vec3d(-2500.3, 7.1, 3.2), 6.0), 0);
    EXPECT_EQ(near(Vec3d(2500.6, -3.7, 2500.2), 5.0), 0);
}

TEST(MeshToVolume, WindingNumberSignsAMeshWithAHoleAwayFromTheHole) {
    // A sphere without its polar cap (z > 0.8 r). Every voxel of the box around it that lies
    // more than 0.4 r from the missing cap, active or not, has the sign of the analytic sphere.
    const double dx = 0.1, r = 1.5;
    const Vec3d c(0.02, -0.04, 0.03);
    TestMesh mesh = test::makeSphereMesh(c, r, 20, 32);
    std::vector<Vec3I> kept;
    for (const Vec3I& t : mesh.triangles) {
        double z = 0;
        for (int v = 0; v < 3; ++v)
            z = std::max(z, double(mesh.points[t[v]][2]) - c[2]);
        if (z < 0.8 * r)
            kept.push_back(t);
    }
    ASSERT_LT(kept.size(), mesh.triangles.size());
    mesh.triangles = kept;

    const auto classify = [&](MeshSign sign) {
        MeshToVolumeOptions options;
        options.sign = sign;
        const auto grid = convert(mesh, dx, options);
        const auto acc = grid->getConstAccessor();
        int wrong = 0, checked = 0;
        const Int32 reach = Int32(3.0 * r / dx);
        for (Int32 i = -reach; i <= reach; ++i) {
            for (Int32 j = -reach; j <= reach; ++j) {
                for (Int32 k = -reach; k <= reach; ++k) {
                    const Vec3d q = Vec3d(Coord(i, j, k)) * dx - c;
                    // Distance to the missing cap: to the sphere above the rim, else to the
                    // rim circle (radius 0.6 r at height 0.8 r).
                    const double sd = q.length() - r;
                    const double toCap =
                        q[2] > 0.8 * q.length()
                            ? std::abs(sd)
                            : std::hypot(std::hypot(q[0], q[1]) - 0.6 * r, q[2] - 0.8 * r);
                    if (toCap < 0.4 * r)
                        continue;
                    // The facets lie up to 0.007 inside the analytic sphere: skip voxels that
                    // close to it.
                    if (std::abs(sd) < 0.03)
                        continue;
                    ++checked;
                    if ((sd < 0.0) != (acc.getValue(Coord(i, j, k)) < 0.0f))
                        ++wrong;
                }
            }
        }
        EXPECT_GT(checked, 100000);
        return wrong;
    };
    EXPECT_EQ(classify(MeshSign::WindingNumber), 0);
    // The scanline flood fill assumes a closed mesh: lines through the hole go wrong.
    EXPECT_GT(classify(MeshSign::FloodFill), 0);
}

TEST(MeshToVolume, WindingNumberMatchesFloodFillOnClosedMeshes) {
    const TestMesh mesh = test::makeTorusMesh(Vec3d(0.1, 0.0, 0.0), 0.9, 0.35, 28, 12);
    MeshToVolumeOptions options;
    options.sign = MeshSign::WindingNumber;
    EXPECT_TRUE(
        test::sameContents(convert(mesh, 0.06, {})->tree(), convert(mesh, 0.06, options)->tree()));
}

TEST(MeshToVolume, ResultDoesNotDependOnTheThreadCount) {
    const TestMesh mesh = test::makeTorusMesh(Vec3d(0.3, 0.1, -0.2), 3.0, 1.0, 64, 24);
    const auto threaded = convert(mesh, 0.05, {});
    ASSERT_GT(threaded->tree().leafCount(), 1000u);
    MeshToVolumeOptions serial;
    serial.threaded = false;
    EXPECT_TRUE(test::sameContents(threaded->tree(), convert(mesh, 0.05, serial)->tree()));
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        EXPECT_TRUE(test::sameContents(threaded->tree(), convert(mesh, 0.05, {})->tree()));
    }
    MeshToVolumeOptions winding;
    winding.sign = MeshSign::WindingNumber;
    const auto a = convert(mesh, 0.2, winding);
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    EXPECT_TRUE(test::sameContents(a->tree(), convert(mesh, 0.2, winding)->tree()));
}

TEST(MeshToVolume, DegenerateTrianglesChangeNothing) {
    TestMesh mesh = test::makeSphereMesh(Vec3d(0.0), 1.0, 10, 16);
    const auto grid = convert(mesh, 0.1, {});
    // Repeated vertices and a triangle along an existing edge.
    const Vec3I t0 = mesh.triangles[5];
    mesh.triangles.emplace_back(t0[0], t0[0], t0[1]);
    mesh.triangles.emplace_back(t0[2], t0[2], t0[2]);
    mesh.points.push_back(Vec3s((Vec3d(mesh.points[t0[0]]) + Vec3d(mesh.points[t0[1]])) * 0.5));
    mesh.triangles.emplace_back(t0[0], Index32(mesh.points.size() - 1), t0[1]);
    EXPECT_TRUE(test::sameContents(grid->tree(), convert(mesh, 0.1, {})->tree()));
}

TEST(MeshToVolume, EmptyMeshGivesAnEmptyGrid) {
    const auto grid = convert(TestMesh{}, 0.1, {});
    EXPECT_TRUE(grid->tree().empty());
    EXPECT_FLOAT_EQ(grid->background(), 0.3f);
}

TEST(MeshToVolume, BadInputThrowsValueError) {
    const auto xform = math::Transform::createLinearTransform(0.1);
    const std::vector<Vec3s> points = {Vec3s(0, 0, 0), Vec3s(1, 0, 0), Vec3s(0, 1, 0)};
    EXPECT_THROW(meshToLevelSet<FloatGrid>(*xform, points, {Vec3I(0, 1, 3)}), ValueError);
    EXPECT_THROW(meshToLevelSet<FloatGrid>(*xform, points, {}, {Vec4I(0, 1, 2, 7)}), ValueError);
    std::vector<Vec3s> nan = points;
    nan[1][0] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(meshToLevelSet<FloatGrid>(*xform, nan, {Vec3I(0, 1, 2)}), ValueError);
    std::vector<Vec3s> far = points;
    far[2][1] = 1e30f;
    EXPECT_THROW(meshToLevelSet<FloatGrid>(*xform, far, {Vec3I(0, 1, 2)}), ValueError);
    EXPECT_THROW(meshToLevelSet<FloatGrid>(*xform, points, {Vec3I(0, 1, 2)}, 0.5f), ValueError);
    MeshToVolumeOptions options;
    options.interiorBandWidth = std::numeric_limits<float>::infinity();
    EXPECT_THROW(meshToVolume<FloatGrid>(*xform, points, {Vec3I(0, 1, 2)}, {}, options),
                 ValueError);
}

TEST(MeshToVolume, DoubleGridMatchesFloatGrid) {
    const TestMesh mesh = test::makeSphereMesh(Vec3d(0.0), 1.0, 10, 16);
    const auto xform = math::Transform::createLinearTransform(0.1);
    const auto f = meshToLevelSet<FloatGrid>(*xform, mesh.points, mesh.triangles);
    const auto d = meshToLevelSet<DoubleGrid>(*xform, mesh.points, mesh.triangles);
    EXPECT_EQ(f->activeVoxelCount(), d->activeVoxelCount());
    for (auto it = d->tree().cbeginValueOn(); it; ++it)
        ASSERT_EQ(f->tree().getValue(it.getCoord()), float(*it)) << it.getCoord();
}

}  // namespace
}  // namespace vdb::tools
