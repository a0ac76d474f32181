// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's meshToVolume / meshToLevelSet. The same mesh (float points, the same
// triangles and quads) and the same transform go through both libraries and the level sets
// are compared voxel by voxel, with tolerances in voxels that follow from how the two differ
// (MeshCompat, closed meshes; MeshDefectCompat, at the end, compares the signs of meshes with
// defects with an exact winding-number oracle):
//
// - This library stores, at every band voxel, the exact distance to the closest triangle
//   (computed in double over every triangle within reach; tests/tools/mesh checks it against brute
//   force to 1e-4 voxels). OpenVDB computes exact distances only at the voxels the triangles
//   cross, then grows the band by dilation, giving each new voxel the distance to the closest
//   of the triangles its neighbours found. A neighbour's triangle is not always the closest
//   one, so away from the surface OpenVDB's magnitudes can be larger than the exact ones (up
//   to about 0.6 voxels on these meshes, most at the cube's edges and corners and the
//   sphere's poles), never smaller. Its points are in index space in single precision, which
//   moves them by up to one float ulp of the index coordinate (about 0.002 voxels 16,000
//   voxels from the origin): kUlpSlack.
// - "exact" runs OpenVDB without its renormalization (DISABLE_RENORMALIZATION): there, with
//   e = 1e-4 + kUlpSlack, |theirs| >= |ours| - e everywhere, ||theirs| - |ours|| <= e at the
//   voxels within one voxel of the surface, and |theirs| - |ours| <= kDilationSlack (0.75).
// - "default" is meshToLevelSet as OpenVDB ships it: its renormalization then smooths the
//   values near the surface by a few tenths of a voxel, so |theirs - ours| <= 0.3 everywhere.
// - Topology: a voxel active only in ours has |d| > w - kDilationSlack (OpenVDB's larger
//   estimate fell out of the band); one active only in OpenVDB has |d| >= w - e in ours.
// - Signs agree at every voxel of the band's bounding box whose distance exceeds half a voxel
//   (closer to the surface, OpenVDB's sign of a voxel a few hundredths of a voxel away can
//   differ from the exact one).

#include <vdb/Grid.h>
#include <vdb/tools/MeshToVolume.h>
#ifdef VDB_TEST_MESHIO
#include <vdb/meshio/MeshReader.h>
#endif

#include "OpenVdbConvert.h"
#include "TestMeshes.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace vdb {
namespace {

using test::toOvdb;

constexpr double kDilationSlack = 0.75;  // voxels: OpenVDB's band growth by dilation
constexpr double kRenormalized = 0.3;    // voxels: OpenVDB's renormalization near the surface

/// One float ulp of the largest index coordinate `extent` (voxels).
double ulpSlack(double extent) {
    return extent * std::numeric_limits<float>::epsilon();
}

struct Case {
    std::string name;
    test::TestMesh mesh;
    double voxelSize;
    float halfWidth;
};

std::vector<Case> cases() {
    return {
        {"sphere", test::makeSphereMesh(Vec3d(0.13, -0.07, 0.02), 1.0, 24, 48), 0.05, 3.0f},
        {"cube-quads", test::makeCubeMesh(Vec3d(-0.52, -0.49, -0.47), 1.0, 4, true), 0.03, 3.0f},
        {"torus", test::makeTorusMesh(Vec3d(0.3, 0.1, -0.2), 1.0, 0.35, 48, 24), 0.04, 2.0f},
        {"sphere-far", test::makeSphereMesh(Vec3d(1000.3, -500.2, 250.1), 1.0, 16, 32), 0.06, 4.0f},
    };
}

/// OpenVDB's level set of the case's mesh with meshToVolume `flags` (0: as meshToLevelSet
/// makes it). Like meshToLevelSet, the points go to index space in single precision.
openvdb::FloatGrid::Ptr openVdbLevelSet(const Case& c, int flags) {
    const auto xform = openvdb::math::Transform::createLinearTransform(c.voxelSize);
    std::vector<openvdb::Vec3s> points;
    for (const Vec3s& p : c.mesh.points)
        points.emplace_back(xform->worldToIndex(openvdb::Vec3d(p[0], p[1], p[2])));
    std::vector<openvdb::Vec4I> polygons;
    for (const Vec3I& t : c.mesh.triangles)
        polygons.emplace_back(t[0], t[1], t[2], openvdb::util::INVALID_IDX);
    for (const Vec4I& q : c.mesh.quads)
        polygons.emplace_back(q[0], q[1], q[2], q[3]);
    const openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec4I> mesh(points,
                                                                                          polygons);
    return openvdb::tools::meshToVolume<openvdb::FloatGrid>(mesh, *xform, c.halfWidth, c.halfWidth,
                                                            flags);
}

class MeshCompat : public ::testing::TestWithParam<std::tuple<size_t, int>> {};

TEST_P(MeshCompat, MeshToLevelSetMatchesOpenVdb) {
    const Case c = cases()[std::get<0>(GetParam())];
    openvdb::initialize();
    const auto xform = math::Transform::createLinearTransform(c.voxelSize);
    const auto ours = tools::meshToLevelSet<FloatGrid>(*xform, c.mesh.points, c.mesh.triangles,
                                                       c.mesh.quads, c.halfWidth);

    const auto theirs = openVdbLevelSet(c, std::get<1>(GetParam()));
    const double dx = c.voxelSize, w = c.halfWidth;
    EXPECT_FLOAT_EQ(ours->background(), theirs->background());
    const auto theirAcc = theirs->getConstAccessor();

    const bool exact = std::get<1>(GetParam()) != 0;
    const auto bbox = ours->evalActiveVoxelBoundingBox();
    Int32 extent = 1;
    for (int k = 0; k < 3; ++k)
        extent = std::max({extent, std::abs(bbox.min()[k]), std::abs(bbox.max()[k])});
    const double e = 1e-4 + ulpSlack(extent);

    uint64_t both = 0, onlyOurs = 0, onlyTheirs = 0, failures = 0;
    double maxDiff = 0.0;
    std::ostringstream msg;
    const auto check = [&](bool ok, const Coord& ijk, double a, double b, const char* what) {
        if (!ok && ++failures <= 8)
            msg << "\n  " << ijk << ": ours " << a << ", OpenVDB " << b << ": " << what;
    };
    for (auto it = ours->tree().cbeginValueOn(); it; ++it) {
        const Coord ijk = it.getCoord();
        const double a = double(*it) / dx;
        float value = 0;
        if (!theirAcc.probeValue(toOvdb(ijk), value)) {
            ++onlyOurs;
            check(std::abs(a) > w - kDilationSlack, ijk, a, value / dx, "active only in ours");
            continue;
        }
        ++both;
        const double b = double(value) / dx, gap = std::abs(b) - std::abs(a);
        maxDiff = std::max(maxDiff, std::abs(a - b));
        if (exact) {
            check(gap >= -e, ijk, a, b, "OpenVDB is closer than the closest triangle");
            check(gap <= kDilationSlack, ijk, a, b, "OpenVDB is too far");
            check(std::abs(a) >= 1.0 || std::abs(gap) <= e, ijk, a, b, "differ at the surface");
        } else {
            check(std::abs(a - b) <= kRenormalized, ijk, a, b, "differ");
        }
    }
    const auto ourAcc = ours->getConstAccessor();
    for (auto it = theirs->tree().cbeginValueOn(); it; ++it) {
        const openvdb::Coord o = it.getCoord();
        const Coord ijk(o.x(), o.y(), o.z());
        if (ourAcc.isValueOn(ijk))
            continue;
        ++onlyTheirs;
        const double a = double(ourAcc.getValue(ijk)) / dx;
        check(std::abs(a) >= w - e, ijk, a, double(*it) / dx, "active only in OpenVDB");
    }
    EXPECT_EQ(failures, 0u) << c.name << ": " << failures << " voxels differ" << msg.str();
    EXPECT_GT(both, 10000u);
    EXPECT_LE(onlyOurs + onlyTheirs, both / 20) << onlyOurs << " / " << onlyTheirs;

    // Signs over the bounding box grown by the band.
    uint64_t signFailures = 0, inside = 0;
    for (Int32 i = bbox.min()[0]; i <= bbox.max()[0]; ++i) {
        for (Int32 j = bbox.min()[1]; j <= bbox.max()[1]; ++j) {
            for (Int32 k = bbox.min()[2]; k <= bbox.max()[2]; ++k) {
                const Coord ijk(i, j, k);
                const float a = ourAcc.getValue(ijk), b = theirAcc.getValue(toOvdb(ijk));
                if (std::abs(a) < 0.5 * dx && std::abs(b) < 0.5 * dx)
                    continue;  // on the surface
                inside += a < 0;
                if ((a < 0) != (b < 0) && ++signFailures <= 8)
                    ADD_FAILURE() << c.name << " " << ijk << ": ours " << a << ", OpenVDB " << b;
            }
        }
    }
    EXPECT_EQ(signFailures, 0u);
    EXPECT_GT(inside, 1000u);
    std::printf(
        "%s %s: max |ours - OpenVDB| %.3g voxels; active in both %llu, only ours %llu, "
        "only OpenVDB %llu\n",
        c.name.c_str(), exact ? "exact" : "default", maxDiff, (unsigned long long)both,
        (unsigned long long)onlyOurs, (unsigned long long)onlyTheirs);
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, MeshCompat,
    ::testing::Combine(::testing::Range<size_t>(0, 4),
                       ::testing::Values(0, int(openvdb::tools::DISABLE_RENORMALIZATION))),
    [](const auto& info) {
        std::string n = cases()[std::get<0>(info.param)].name;
        std::replace(n.begin(), n.end(), '-', '_');
        return n + (std::get<1>(info.param) ? "_exact" : "_default");
    });

// ---- Signs of meshes with defects ----
//
// Oracle: the exact generalized winding number by brute force (tests/support/TestMeshes.h), or
// the parity of ray crossings for a closed mesh with a face turned over (where the winding
// number itself is wrong). Both libraries convert the mesh with their defaults (OpenVDB:
// meshToLevelSet, which flood-fills the exterior through the voxels and signs the voxels at
// the surface from their closest triangles); their signs are compared with the oracle at the
// same points: about every 17th active voxel of either level set and every 5th voxel of the box
// around the mesh, more than half a voxel from the surface and three voxels from an open edge.
// Ours must agree everywhere there, and so at least as often as OpenVDB.

struct DefectCase {
    std::string name;
    test::TestMesh mesh;
    bool byWinding = true;  // oracle: winding number (else ray parity)
};

std::vector<DefectCase> defectCases() {
    std::vector<DefectCase> out;
    // A sphere with three holes, one a fifth of its size.
    const Vec3d c(0.03, -0.02, 0.01);
    const Vec3d dirs[3] = {Vec3d(0.0, 0.0, 1.0), Vec3d(0.8, 0.6, 0.0), Vec3d(-0.6, 0.0, -0.8)};
    const double cosines[3] = {0.9, 0.99, 0.98};
    out.push_back({"sphere-with-holes",
                   test::withoutTriangles(test::makeSphereMesh(c, 1.2, 16, 32),
                                          [&](const Vec3d& p) {
                                              const Vec3d d = (p - c).unitSafe();
                                              for (int h = 0; h < 3; ++h) {
                                                  if (d.dot(dirs[h]) > cosines[h])
                                                      return true;
                                              }
                                              return false;
                                          }),
                   true});
    // A closed cube with one face turned over.
    test::TestMesh cube = test::makeCubeMesh(Vec3d(-0.52, -0.47, -0.49), 1.0, 3, false);
    for (Vec3I& t : cube.triangles) {
        if (cube.points[t[0]][0] > 0.47f && cube.points[t[1]][0] > 0.47f &&
            cube.points[t[2]][0] > 0.47f) {
            std::swap(t[1], t[2]);
        }
    }
    out.push_back({"cube-turned-face", cube, false});
    // Two overlapping spheres: the overlap has winding number 2.
    out.push_back({"overlapping-spheres",
                   test::merged(test::makeSphereMesh(Vec3d(-0.3, 0.0, 0.0), 0.7, 12, 24),
                                test::makeSphereMesh(Vec3d(0.3, 0.05, 0.0), 0.6, 12, 24)),
                   true});
#ifdef VDB_TEST_MESHIO
    // Real meshes of the Debian package assimp-testmodels, when installed.
    for (const char* model : {"PLY/Wuson.ply", "OBJ/spider.obj", "OBJ/regr01.obj",
                              "STL/sphereWithHole.stl", "STL/Spider_binary.stl"}) {
        const std::string path = std::string("/usr/share/assimp/models/") + model;
        if (!std::filesystem::exists(path)) {
            out.push_back({model, {}, true});  // skipped
            continue;
        }
        const meshio::Mesh mesh = meshio::readMesh(path);
        out.push_back({model, {mesh.points, mesh.triangles, mesh.quads}, true});
    }
#endif
    return out;
}

class MeshDefectCompat : public ::testing::TestWithParam<size_t> {};

TEST_P(MeshDefectCompat, SignsAreAtLeastAsRightAsOpenVdbs) {
    const auto cases = defectCases();
    if (GetParam() >= cases.size() || cases[GetParam()].mesh.points.empty())
        GTEST_SKIP() << "model not available (package assimp-testmodels, vdb::meshio)";
    const DefectCase& c = cases[GetParam()];
    openvdb::initialize();
    Vec3d lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const Vec3s& p : c.mesh.points) {
        lo = Vec3d::minComponent(lo, Vec3d(p));
        hi = Vec3d::maxComponent(hi, Vec3d(p));
    }
    const double dx = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}) / 80.0;
    const auto xform = math::Transform::createLinearTransform(dx);
    const auto ours = tools::meshToLevelSet<FloatGrid>(*xform, c.mesh.points, c.mesh.triangles,
                                                       c.mesh.quads, 3.0f);
    const Case asCase{c.name, c.mesh, dx, 3.0f};
    const auto theirs = openVdbLevelSet(asCase, 0);

    const test::OracleMesh oracle = test::toIndexSpace(c.mesh, dx);
    std::vector<Vec3d> points = test::signSamples(*ours, oracle, 17, 5);
    for (auto it = theirs->tree().cbeginValueOn(); it; ++it) {
        if ((it.getCoord().x() + it.getCoord().y() + it.getCoord().z()) % 17 == 0)
            points.emplace_back(it.getCoord().x(), it.getCoord().y(), it.getCoord().z());
    }
    const auto ourAcc = ours->getConstAccessor();
    const auto theirAcc = theirs->getConstAccessor();
    const auto oracleInside = [&](const Vec3d& p) {
        return c.byWinding ? oracle.insideByWinding(p) : oracle.inside(p);
    };
    const auto expected = test::oracleSigns(oracle, points, 0.5, 3.0, oracleInside);
    const test::SignTally ourTally = test::compareSigns(expected, [&](const Vec3d& p) {
        return ourAcc.getValue(math::floorToCoord(p + 0.5)) < 0.0f;
    });
    const test::SignTally theirTally = test::compareSigns(expected, [&](const Vec3d& p) {
        return theirAcc.getValue(toOvdb(math::floorToCoord(p + 0.5))) < 0.0f;
    });
    EXPECT_GT(ourTally.checked, 1000);
    EXPECT_EQ(ourTally.wrong, 0);
    EXPECT_LE(ourTally.wrong, theirTally.wrong);
    std::printf("%s: %d points; signs unlike the %s: ours %d, OpenVDB %d\n", c.name.c_str(),
                ourTally.checked, c.byWinding ? "winding number" : "ray parity", ourTally.wrong,
                theirTally.wrong);
}

/// The test names of defectCases(), in order.
constexpr const char* kDefectNames[] = {
    "sphere_with_holes", "cube_turned_face", "overlapping_spheres", "Wuson_ply",
    "spider_obj",        "regr01_obj",       "sphereWithHole_stl",  "Spider_binary_stl"};

INSTANTIATE_TEST_SUITE_P(Meshes, MeshDefectCompat,
                         ::testing::Range<size_t>(0, std::size(kDefectNames)),
                         [](const auto& info) { return std::string(kDefectNames[info.param]); });

}  // namespace
}  // namespace vdb
