// SPDX-License-Identifier: Apache-2.0
// Mesh export (vdb::meshio::writeMesh): meshes written in every format are read back with
// readMesh() and compared point by point with what was written, their orientation checked by
// the sign of the enclosed volume (positive: counter-clockwise seen from outside, the files'
// convention) and STL's facet normals against the facets' corners, decoded here byte by byte.
// Replacing files: permissions kept, links followed, FIFOs written directly, nothing left
// behind when writing fails.

#include <vdb/meshio/MeshReader.h>
#include <vdb/meshio/MeshWriter.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/VolumeToMesh.h>

#include "GridContents.h"
#include "MeshMetrics.h"
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

namespace vdb::meshio {
namespace {

namespace fs = std::filesystem;
using test::TestMesh;

std::string tempFile(const std::string& name) {
    return test::tempPath("vdb-meshwriter-", name);
}

Mesh toMesh(const TestMesh& t) {
    return Mesh{t.points, t.triangles, t.quads};
}
TestMesh toTest(const Mesh& m) {
    return TestMesh{m.points, m.triangles, m.quads};
}

/// The files in the folder of `path` whose names start with its name (the file and any
/// temporary file beside it).
std::vector<std::string> filesLike(const std::string& path) {
    std::vector<std::string> out;
    const std::string prefix = fs::path(path).filename().string();
    for (const auto& entry : fs::directory_iterator(fs::path(path).parent_path())) {
        const std::string name = entry.path().filename().string();
        if (name.compare(0, prefix.size(), prefix) == 0)
            out.push_back(name);
    }
    return out;
}

/// A closed mesh of quads from volumeToMesh: clockwise, OpenVDB's winding.
TestMesh sphereFromVolume() {
    const auto grid = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.2f, -0.1f, 0.3f), 0.1f);
    TestMesh mesh;
    tools::volumeToMesh(*grid, mesh.points, mesh.triangles, mesh.quads, 0.0, 0.2);
    return mesh;
}

class MeshWriterFormats : public ::testing::TestWithParam<std::string> {};

TEST_P(MeshWriterFormats, VolumeMeshReadsBackCounterClockwise) {
    const TestMesh mesh = sphereFromVolume();
    ASSERT_FALSE(mesh.quads.empty());
    ASSERT_FALSE(mesh.triangles.empty());
    ASSERT_LT(test::signedVolume(mesh), 0.0);
    const std::string path = tempFile("sphere" + GetParam());
    writeMesh(path, toMesh(mesh));
    const TestMesh back = toTest(readMesh(path));
    EXPECT_TRUE(test::topologyOf(back).closedManifold());
    EXPECT_NEAR(test::signedVolume(back), -test::signedVolume(mesh),
                1e-5 * std::abs(test::signedVolume(mesh)));
    EXPECT_EQ(back.points.size(), mesh.points.size());
    if (GetParam() == ".stl") {
        EXPECT_TRUE(back.quads.empty());
        EXPECT_EQ(back.triangles.size(), mesh.triangles.size() + 2 * mesh.quads.size());
    } else {
        EXPECT_EQ(back.quads.size(), mesh.quads.size());
        EXPECT_EQ(back.triangles.size(), mesh.triangles.size());
    }
    // Every point comes back exactly (floats are written with all their digits).
    EXPECT_EQ(test::largestPointGap(back, mesh, 1e-3), 0.0);
    EXPECT_EQ(test::largestPointGap(mesh, back, 1e-3), 0.0);
    EXPECT_EQ(filesLike(path).size(), 1u) << "no temporary file is left";
}

TEST_P(MeshWriterFormats, CounterClockwiseMeshesKeepTheirWinding) {
    const TestMesh cube = test::makeCubeMesh(Vec3d(-0.5, 0.25, 1.0), 2.0, 3, true);
    ASSERT_GT(test::signedVolume(cube), 0.0);
    const std::string path = tempFile("cube" + GetParam());
    writeMesh(path, toMesh(cube), Winding::CounterClockwise);
    EXPECT_NEAR(test::signedVolume(toTest(readMesh(path))), 8.0, 1e-4);
    writeMesh(path, toMesh(cube), Winding::Clockwise);
    EXPECT_NEAR(test::signedVolume(toTest(readMesh(path))), -8.0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(AllFormats, MeshWriterFormats, ::testing::Values(".obj", ".ply", ".stl"),
                         [](const auto& info) { return info.param.substr(1); });

TEST(MeshWriter, StlFacetNormalsPointOutward) {
    const TestMesh mesh = sphereFromVolume();
    const std::string path = tempFile("normals.STL");
    writeMesh(path, toMesh(mesh));
    const std::vector<uint8_t> bytes = test::fileBytes(path);
    ASSERT_GE(bytes.size(), 84u);
    uint32_t count = 0;
    std::memcpy(&count, bytes.data() + 80, 4);
    ASSERT_EQ(bytes.size(), 84u + 50u * count);
    EXPECT_EQ(count, mesh.triangles.size() + 2 * mesh.quads.size());
    const Vec3d center(0.2, -0.1, 0.3);
    for (uint32_t t = 0; t < count; ++t) {
        float f[12];
        std::memcpy(f, bytes.data() + 84 + 50 * t, sizeof f);
        const Vec3d n(f[0], f[1], f[2]), a(f[3], f[4], f[5]), b(f[6], f[7], f[8]),
            c(f[9], f[10], f[11]);
        const Vec3d corners = (b - a).cross(c - a).unitSafe();
        ASSERT_NEAR(n.length(), 1.0, 1e-5);
        ASSERT_GT(n.dot(corners), 0.9999) << "the facet normal is the corners' normal";
        ASSERT_GT(n.dot((a + b + c) / 3.0 - center), 0.0) << "and points outward";
    }
}

TEST(MeshWriter, ReplacingAFileKeepsItsPermissionsAndFollowsLinks) {
    const TestMesh cube = test::makeCubeMesh(Vec3d(0.0), 1.0, 2, true);
    const std::string target = tempFile("kept.ply");
    writeMesh(target, toMesh(cube));
    ASSERT_EQ(::chmod(target.c_str(), 0640), 0);
    writeMesh(target, toMesh(cube));
    struct stat st {};
    ASSERT_EQ(::stat(target.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 07777, 0640u);

    const std::string link = tempFile("link.ply");
    fs::remove(link);
    fs::create_symlink(target, link);
    const TestMesh moved = test::makeCubeMesh(Vec3d(5.0), 1.0, 2, true);
    writeMesh(link, toMesh(moved));
    EXPECT_TRUE(fs::is_symlink(link)) << "the link stays a link";
    EXPECT_GT(readMesh(target).points.front()[0], 4.0f) << "its target was replaced";
    EXPECT_EQ(filesLike(link).size(), 1u);
}

TEST(MeshWriter, FifoIsWrittenDirectly) {
    const std::string fifo = tempFile("pipe.obj");
    fs::remove(fifo);
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    std::string received;
    std::thread reader([&] {
        std::ifstream in(fifo, std::ios::binary);
        received.assign(std::istreambuf_iterator<char>(in), {});
    });
    writeMesh(fifo, toMesh(test::makeCubeMesh(Vec3d(0.0), 1.0, 1, true)));
    reader.join();
    EXPECT_NE(received.find("\nf "), std::string::npos);
    EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST(MeshWriter, FailuresNameTheFileAndLeaveNothingBehind) {
    const Mesh cube = toMesh(test::makeCubeMesh(Vec3d(0.0), 1.0, 1, true));
    const std::string missing = tempFile("no-such-folder") + "/out.obj";
    try {
        writeMesh(missing, cube);
        FAIL() << "no error";
    } catch (const IoError& e) {
        EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(fs::path(missing).parent_path()));

    // A folder nothing can be created in (even by root).
    EXPECT_THROW(writeMesh("/proc/vdb-mesh-writer-test.obj", cube), IoError);
    EXPECT_FALSE(fs::exists("/proc/vdb-mesh-writer-test.obj"));

    const std::string folder = tempFile("folder.obj");
    fs::create_directories(folder);
    EXPECT_THROW(writeMesh(folder, cube), IoError);
    EXPECT_THROW(writeMesh(tempFile("mesh.off"), cube), IoError);
    EXPECT_THROW(writeMesh(tempFile("mesh"), cube), IoError);

    Mesh bad = cube;
    bad.quads.back()[2] = uint32_t(bad.points.size());
    EXPECT_THROW(writeMesh(tempFile("bad.ply"), bad), ValueError);
    bad = cube;
    bad.points[3][1] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(writeMesh(tempFile("nan.stl"), bad), ValueError);
    EXPECT_FALSE(fs::exists(tempFile("bad.ply")));
    EXPECT_FALSE(fs::exists(tempFile("nan.stl")));

    // An existing file is left as it was when the new one cannot be written.
    const std::string kept = tempFile("unchanged.obj");
    writeMesh(kept, cube);
    const std::vector<uint8_t> before = test::fileBytes(kept);
    bad = cube;
    bad.triangles.emplace_back(0, 1, 99);
    EXPECT_THROW(writeMesh(kept, bad), ValueError);
    EXPECT_EQ(test::fileBytes(kept), before);
}

TEST(MeshWriter, EmptyMeshGivesAnEmptyFile) {
    for (const char* ext : {".obj", ".ply", ".stl"}) {
        const std::string path = tempFile(std::string("empty") + ext);
        writeMesh(path, Mesh{});
        EXPECT_TRUE(fs::exists(path)) << ext;
    }
    const std::vector<uint8_t> stl = test::fileBytes(tempFile("empty.stl"));
    ASSERT_EQ(stl.size(), 84u);
}

}  // namespace
}  // namespace vdb::meshio
