// SPDX-License-Identifier: Apache-2.0
// Oracle: the input mesh itself. Meshes go to level sets (meshToVolume) and back (volumeToMesh);
// the result must be closed and two-manifold and lie within one voxel of the input, measured
// both ways by the sampled Hausdorff distance of MeshMetrics.h. Open meshes (signed by winding
// numbers) must come back closed and within a voxel of the input wherever the input is more
// than two voxels from its holes. Files read, converted and written keep their orientation.
// The real meshes come from the Debian package assimp-testmodels (skipped when absent).

#include <vdb/meshio/MeshReader.h>
#include <vdb/meshio/MeshWriter.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/VolumeToMesh.h>

#include "GridContents.h"
#include "MeshMetrics.h"
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdb::tools {
namespace {

using test::TestMesh;

constexpr double kVoxelsAcross = 64.0;  // voxels along the largest side of each mesh

double largestExtent(const TestMesh& mesh) {
    Vec3d lo(std::numeric_limits<double>::max()), hi(-lo[0]);
    for (const Vec3s& p : mesh.points) {
        lo = Vec3d::minComponent(lo, Vec3d(p));
        hi = Vec3d::maxComponent(hi, Vec3d(p));
    }
    return (hi - lo).maxComponent();
}

/// The mesh through a level set and back, with voxels of `voxelSize`.
TestMesh roundTrip(const TestMesh& mesh, double voxelSize, MeshSign sign) {
    const auto xform = math::Transform::createLinearTransform(voxelSize);
    MeshToVolumeOptions options;
    options.sign = sign;
    const auto grid =
        meshToVolume<FloatGrid>(*xform, mesh.points, mesh.triangles, mesh.quads, options);
    TestMesh out;
    volumeToMesh(*grid, out.points, out.triangles, out.quads);
    return out;
}

/// How far the round trip strays from the input, in voxels: the largest distance from the
/// output to the input, and from the input to the output over the input's points that lie in
/// no feature thinner than two voxels (a ball of one voxel fits on both sides of the surface
/// there; this leaves out a voxel around sharp edges, corners and thin walls) and no closer
/// than two voxels to the input's holes, sampled half a voxel apart.
struct Straying {
    double outputToInput = 0.0;
    double inputToOutput = 0.0;
    size_t checked = 0;  ///< input samples measured
};

Straying straying(const TestMesh& input, const TestMesh& output, double voxel,
                  const std::vector<Vec3d>& holeRims) {
    Straying out;
    out.outputToInput = test::directedHausdorff(output, input, 3.0 * voxel, 0.5 * voxel) / voxel;
    const test::MeshDistance toInput(input, 3.0 * voxel, voxel),
        toOutput(output, 3.0 * voxel, voxel);
    TestMesh rims;
    for (const Vec3d& p : holeRims) {
        const uint32_t i = uint32_t(rims.points.size());
        rims.points.emplace_back(p);
        rims.triangles.emplace_back(i, i, i);
    }
    const test::MeshDistance toRim(rims, 2.0 * voxel);
    for (const Vec3I& t : input.allTriangles()) {
        const Vec3d a(input.points[t[0]]), b(input.points[t[1]]), c(input.points[t[2]]);
        const Vec3d n = (b - a).cross(c - a).unitSafe();
        TestMesh one;
        one.points = {Vec3s(a), Vec3s(b), Vec3s(c)};
        one.triangles = {Vec3I(0, 1, 2)};
        for (const Vec3d& p : test::surfaceSamples(one, 0.5 * voxel)) {
            if (n.lengthSqr() == 0.0 || toInput.distance(p - n * voxel) < 0.99 * voxel ||
                toInput.distance(p + n * voxel) < 0.99 * voxel)
                continue;
            if (!holeRims.empty() && toRim.distance(p) < 2.0 * voxel)
                continue;
            out.inputToOutput = std::max(out.inputToOutput, toOutput.distance(p) / voxel);
            ++out.checked;
        }
    }
    return out;
}

void report(const char* name, const Straying& s) {
    std::printf("  %-24s output to input %.3f voxels, input to output %.3f voxels (%zu samples)\n",
                name, s.outputToInput, s.inputToOutput, s.checked);
}

void expectClosedRoundTrip(const char* name, const TestMesh& mesh) {
    const double voxel = largestExtent(mesh) / kVoxelsAcross;
    const TestMesh back = roundTrip(mesh, voxel, MeshSign::FloodFill);
    EXPECT_TRUE(test::topologyOf(back).closedManifold());
    const Straying s = straying(mesh, back, voxel, {});
    report(name, s);
    EXPECT_LT(s.outputToInput, 1.0);
    EXPECT_LT(s.inputToOutput, 1.0);
    EXPECT_GT(s.checked, mesh.points.size());
    // Everywhere, sharp corners included, the input lies within 2 / sqrt(3) voxels of the
    // output (a corner's cell gets the mean of its three edge crossings).
    EXPECT_LT(test::directedHausdorff(mesh, back, 3.0 * voxel, 0.5 * voxel) / voxel, 1.16);
    // The input winds counter-clockwise seen from outside; volumeToMesh the other way.
    EXPECT_NEAR(test::signedVolume(back) / test::signedVolume(mesh), -1.0, 0.03);
}

TEST(MeshRoundTrip, GeneratedClosedMeshesComeBackWithinAVoxel) {
    const std::pair<const char*, TestMesh> meshes[] = {
        {"sphere", test::makeSphereMesh(Vec3d(0.13, -0.21, 0.07), 1.2, 24, 48)},
        {"torus", test::makeTorusMesh(Vec3d(0.3, 0.1, -0.2), 1.0, 0.35, 64, 32)},
        {"cube", test::makeCubeMesh(Vec3d(-1.03, -0.97, -1.11), 2.1, 4, true)},
    };
    for (const auto& [name, mesh] : meshes) {
        SCOPED_TRACE(name);
        expectClosedRoundTrip(name, mesh);
    }
}

/// The path of a model of assimp-testmodels, or "" when the package is not installed.
std::string model(const std::string& relative) {
    const std::string path = "/usr/share/assimp/models/" + relative;
    return std::filesystem::exists(path) ? path : std::string();
}

TestMesh readModel(const std::string& path) {
    const meshio::Mesh m = meshio::readMesh(path);
    return TestMesh{m.points, m.triangles, m.quads};
}

TEST(MeshRoundTrip, ClosedTestModelsComeBackWithinAVoxel) {
    for (const char* name :
         {"OBJ/box.obj", "OBJ/empty_mat.obj", "PLY/cube_uv.ply", "OFF/Cube.off"}) {
        SCOPED_TRACE(name);
        const std::string path = model(name);
        if (path.empty())
            GTEST_SKIP() << name << " not found (package assimp-testmodels)";
        const TestMesh mesh = readModel(path);
        ASSERT_TRUE(test::topologyOf(mesh).closedManifold());
        expectClosedRoundTrip(name, mesh);
    }
}

/// Points along the edges of `mesh` that belong to one face only (its holes' rims).
std::vector<Vec3d> holeRims(const TestMesh& mesh) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const Vec3I& t : mesh.allTriangles())
        for (int i = 0; i < 3; ++i) {
            const uint32_t a = t[i], b = t[(i + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
        }
    std::vector<Vec3d> rims;
    for (const auto& [edge, count] : edges) {
        if (count != 1)
            continue;
        const Vec3d a(mesh.points[edge.first]), b(mesh.points[edge.second]);
        for (int s = 0; s <= 8; ++s)
            rims.push_back(a + (b - a) * (s / 8.0));
    }
    return rims;
}

TEST(MeshRoundTrip, OpenTestModelsComeBackClosed) {
    for (const char* name : {"STL/sphereWithHole.stl", "PLY/Wuson.ply"}) {
        SCOPED_TRACE(name);
        const std::string path = model(name);
        if (path.empty())
            GTEST_SKIP() << name << " not found (package assimp-testmodels)";
        const TestMesh mesh = readModel(path);
        ASSERT_FALSE(test::topologyOf(mesh).closedManifold());
        const double voxel = largestExtent(mesh) / kVoxelsAcross;
        const TestMesh back = roundTrip(mesh, voxel, MeshSign::WindingNumber);
        EXPECT_TRUE(test::topologyOf(back).closedManifold());
        const std::vector<Vec3d> rims = holeRims(mesh);
        ASSERT_FALSE(rims.empty());
        const Straying s = straying(mesh, back, voxel, rims);
        report(name, s);
        EXPECT_GT(s.checked, mesh.points.size());
        EXPECT_LT(s.inputToOutput, 1.0);
    }
}

TEST(MeshRoundTrip, FilesKeepTheirOrientation) {
    // A counter-clockwise file through `vdb mesh` and `vdb tomesh`'s library calls.
    const TestMesh torus = test::makeTorusMesh(Vec3d(0.0), 1.0, 0.4, 48, 24);
    const std::string in = test::tempPath("vdb-roundtrip-", "torus.ply");
    meshio::writeMesh(in, meshio::Mesh{torus.points, torus.triangles, torus.quads},
                      meshio::Winding::CounterClockwise);
    const TestMesh read = readModel(in);
    ASSERT_GT(test::signedVolume(read), 0.0);
    const TestMesh back = roundTrip(read, largestExtent(read) / kVoxelsAcross, MeshSign::FloodFill);
    for (const char* ext : {".obj", ".ply", ".stl"}) {
        const std::string out = test::tempPath("vdb-roundtrip-", std::string("back") + ext);
        meshio::writeMesh(out, meshio::Mesh{back.points, back.triangles, back.quads});
        const double volume = test::signedVolume(readModel(out));
        EXPECT_NEAR(volume / test::signedVolume(read), 1.0, 0.03) << ext;
    }
}

}  // namespace
}  // namespace vdb::tools
