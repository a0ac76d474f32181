// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `vdb tomesh`, `vdb rebuild` and the mesh of `vdb demo`: outputs are read
// back with the library (readMesh, io::File) and compared with the same operation done through
// the library, with the analytic sphere, and with the mesh a file started from; bad requests
// must fail with status 2, one error line and no output file.

#include <vdb/io/File.h>
#include <vdb/meshio/MeshReader.h>
#include <vdb/meshio/MeshWriter.h>
#include <vdb/tools/LevelSetRebuild.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/VolumeToMesh.h>

#include "GridContents.h"
#include "MeshMetrics.h"
#include "ToolRunner.h"
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;
using test::TestMesh;

class ToMeshCli : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        mDir = fs::path(test::tempPath("vdb-tomesh-", info->name()));
        fs::create_directories(mDir);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(mDir, ec);
    }
    std::string path(const std::string& name) const { return (mDir / name).string(); }

    test::Result run(const std::vector<std::string>& args) {
        return test::runTool(VDB_TOOL_PATH, args, mDir.string());
    }
    /// The folder's files after `args` failed with status 2 and one error line naming `needle`.
    std::vector<std::string> failure(const std::vector<std::string>& args,
                                     const std::string& needle) {
        const test::Result r = run(args);
        EXPECT_EQ(r.status, 2) << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(mDir))
            names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }

    /// A sphere of radius `radius` (voxel size 0.1) saved as grid "sphere", plus a fog
    /// volume "density" that is 1 inside it, saved in the same file.
    FloatGrid::Ptr writeGrids(const std::string& name, float radius) {
        auto sphere = tools::createLevelSetSphere<FloatGrid>(radius, Vec3f(0.2f), 0.1f, 3.0f);
        sphere->setName("sphere");
        auto density = FloatGrid::create(0.0f);
        density->setName("density");
        density->setGridClass(GRID_FOG_VOLUME);
        density->setTransform(sphere->transformPtr());
        auto acc = density->getAccessor();
        const CoordBBox box = sphere->evalActiveVoxelBoundingBox();
        for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
            for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                    const float d = sphere->tree().getValue(Coord(i, j, k));
                    if (d < 0.3f)
                        acc.setValue(Coord(i, j, k), std::clamp(0.5f - d / 0.2f, 0.0f, 1.0f));
                }
        auto vectors = Vec3SGrid::create();
        vectors->setName("velocity");
        vectors->tree().setValue(Coord(0), Vec3s(1.0f));
        io::File(path(name)).write(GridPtrVec{vectors, density, sphere});
        return sphere;
    }

    static TestMesh read(const std::string& file) {
        const meshio::Mesh m = meshio::readMesh(file);
        return TestMesh{m.points, m.triangles, m.quads};
    }

    fs::path mDir;
};

uint64_t jsonCount(const std::string& json, const std::string& key) {
    const std::string needle = "\"" + key + "\": ";
    const size_t at = json.find(needle);
    return at == std::string::npos ? ~uint64_t(0) : std::stoull(json.substr(at + needle.size()));
}

TEST_F(ToMeshCli, WritesTheLevelSetsSurfaceCounterClockwiseInEveryFormat) {
    const auto sphere = writeGrids("in.vdb", 1.5f);
    TestMesh expected;
    tools::volumeToMesh(*sphere, expected.points, expected.triangles, expected.quads);
    const double exactVolume = 4.0 / 3.0 * std::numbers::pi * 1.5 * 1.5 * 1.5;
    for (const char* ext : {".obj", ".ply", ".stl"}) {
        SCOPED_TRACE(ext);
        const std::string out = path(std::string("sphere") + ext);
        const test::Result r = run({"tomesh", path("in.vdb"), "-o", out, "--json"});
        ASSERT_EQ(r.status, 0) << r.err;
        EXPECT_EQ(jsonCount(r.out, "points"), expected.points.size()) << r.out;
        EXPECT_EQ(jsonCount(r.out, "quads"), expected.quads.size());
        EXPECT_EQ(jsonCount(r.out, "triangles"), 0u);
        EXPECT_NE(r.out.find("\"seconds\": "), std::string::npos);
        const TestMesh mesh = read(out);
        EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
        EXPECT_EQ(mesh.points.size(), expected.points.size());
        // Files wind counter-clockwise seen from outside: a positive volume.
        EXPECT_NEAR(test::signedVolume(mesh), exactVolume, 0.01 * exactVolume);
    }
    // Adaptivity: fewer polygons; chords across merged regions of this small sphere (15 voxels)
    // cut off about a tenth of its volume.
    const test::Result r =
        run({"tomesh", path("in.vdb"), "-o", path("coarse.ply"), "--adaptivity", "0.5"});
    ASSERT_EQ(r.status, 0) << r.err;
    const TestMesh coarse = read(path("coarse.ply"));
    EXPECT_LT(coarse.primitiveCount(), expected.quads.size() / 2);
    EXPECT_TRUE(test::topologyOf(coarse).closedManifold());
    EXPECT_GT(test::signedVolume(coarse), 0.8 * exactVolume);
    EXPECT_LT(test::signedVolume(coarse), exactVolume);
}

TEST_F(ToMeshCli, FogVolumesMeshAtHalfDensityByDefault) {
    writeGrids("in.vdb", 1.5f);
    const test::Result r =
        run({"tomesh", path("in.vdb"), "-o", path("fog.obj"), "--grid", "density", "--json"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("\"isovalue\": 0.5"), std::string::npos) << r.out;
    const TestMesh mesh = read(path("fog.obj"));
    EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
    // Density 0.5 where the distance is 0: the same sphere, outward (positive volume).
    const double exactVolume = 4.0 / 3.0 * std::numbers::pi * 1.5 * 1.5 * 1.5;
    EXPECT_NEAR(test::signedVolume(mesh), exactVolume, 0.02 * exactVolume);
}

TEST_F(ToMeshCli, MeshFileRoundTripKeepsItsOrientation) {
    // A counter-clockwise torus file -> vdb mesh -> vdb tomesh -> file.
    const TestMesh torus = test::makeTorusMesh(Vec3d(0.0), 1.0, 0.4, 48, 24);
    meshio::writeMesh(path("torus.obj"), meshio::Mesh{torus.points, torus.triangles, torus.quads},
                      meshio::Winding::CounterClockwise);
    ASSERT_EQ(
        run({"mesh", path("torus.obj"), "-o", path("torus.vdb"), "--resolution", "64"}).status, 0);
    const test::Result r = run({"tomesh", path("torus.vdb"), "-o", path("back.stl")});
    ASSERT_EQ(r.status, 0) << r.err;
    const TestMesh back = read(path("back.stl"));
    EXPECT_TRUE(test::topologyOf(back).closedManifold());
    EXPECT_NEAR(test::signedVolume(back) / test::signedVolume(torus), 1.0, 0.03);
}

TEST_F(ToMeshCli, RebuildMakesTheLibrarysLevelSet) {
    writeGrids("in.vdb", 1.5f);
    const test::Result r = run({"rebuild", path("in.vdb"), "-o", path("out.vdb"), "--grid",
                                "density", "--half-width", "4", "--voxel-size", "0.05"});
    ASSERT_EQ(r.status, 0) << r.err;
    io::File in(path("out.vdb"));
    in.open();
    const auto grid = gridPtrCast<FloatGrid>(in.readGrid("density"));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    EXPECT_DOUBLE_EQ(grid->voxelSize()[0], 0.05);

    io::File source(path("in.vdb"));
    source.open();
    const auto density = gridPtrCast<FloatGrid>(source.readGrid("density"));
    const auto xform = math::Transform::createLinearTransform(0.05);
    const auto expected = tools::levelSetRebuild(*density, 0.5f, 4.0f, xform.get());
    EXPECT_EQ(grid->activeVoxelCount(), expected->activeVoxelCount());
    for (auto it = expected->cbeginValueOn(); it; ++it)
        ASSERT_EQ(grid->tree().getValue(it.getCoord()), *it) << it.getCoord();
}

TEST_F(ToMeshCli, DemoWritesTheUnionAsAClosedMesh) {
    const test::Result r = run({"demo", "-o", mDir.string(), "--spheres", "2000", "--resolution",
                                "96", "--width", "64", "--height", "48", "--adaptivity", "0.3"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("demo.ply"), std::string::npos) << r.out;
    const TestMesh mesh = read(path("demo.ply"));
    EXPECT_GT(mesh.primitiveCount(), 1000u);
    EXPECT_TRUE(test::topologyOf(mesh).closedManifold());
    EXPECT_GT(test::signedVolume(mesh), 0.0);
}

TEST_F(ToMeshCli, BadRequestsFailWithoutOutput) {
    writeGrids("in.vdb", 1.0f);
    const auto before = failure({"tomesh", path("in.vdb"), "-o", path("x.fbx")}, "x.fbx");
    EXPECT_EQ(before, std::vector<std::string>{"in.vdb"});
    EXPECT_EQ(
        failure({"tomesh", path("in.vdb"), "-o", path("x.obj"), "--grid", "velocity"}, "velocity"),
        before);
    EXPECT_EQ(
        failure({"tomesh", path("in.vdb"), "-o", path("x.obj"), "--grid", "nothing"}, "nothing"),
        before);
    EXPECT_EQ(failure({"tomesh", path("in.vdb"), "-o", path("none/x.obj")}, "does not exist"),
              before);
    EXPECT_EQ(
        failure({"tomesh", path("in.vdb"), "-o", path("x.obj"), "--adaptivity", "2"}, "adaptivity"),
        before);
    EXPECT_EQ(
        failure({"tomesh", path("in.vdb"), "-o", path("x.obj"), "--isovalue", "nan"}, "isovalue"),
        before);
    EXPECT_EQ(failure({"rebuild", path("in.vdb"), "-o", path("x.vdb"), "--half-width", "0.5"},
                      "half-width"),
              before);
    const test::Result missing = run({"tomesh", path("missing.vdb"), "-o", path("x.obj")});
    EXPECT_NE(missing.status, 0);
    EXPECT_NE(missing.err.find("missing.vdb"), std::string::npos);
    EXPECT_FALSE(fs::exists(path("x.obj")));
    for (const char* cmd : {"tomesh", "rebuild"}) {
        const test::Result help = run({cmd, "--help"});
        EXPECT_EQ(help.status, 0);
        EXPECT_NE(help.out.find("Example"), std::string::npos) << cmd;
        EXPECT_NE(help.out.find("--threads"), std::string::npos) << cmd;
    }
}

}  // namespace
}  // namespace vdb
