// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of the `vdb` tool's world coordinates far from the origin and of empty
// results. A command either computes such positions in double (its output is checked against
// the analytic answer) or refuses them with one line where floats are spaced more than 1/8 of
// the voxel size; and no command writes an empty grid, mesh or picture as a success.

#include <vdb/io/File.h>
#include <vdb/tools/LevelSetSphere.h>

#include "CliFixture.h"
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;

// 1.0737e9 world units at voxel size 1: inside the index space (2^31 is 2.147e9), where floats
// are 64 apart (just below 2^30).
constexpr double kFar = 1.0737e9;

class PrecisionCli : public test::ToolTest {
protected:
    GridBase::Ptr readFirst(const std::string& name) {
        io::File file(path(name));
        file.open();
        const auto grids = file.getGrids();
        return grids->empty() ? nullptr : grids->front();
    }

    void writeText(const std::string& name, const std::string& text) {
        std::ofstream(path(name)) << text;
    }

    /// An OBJ file of the cube [x0, x0 + size] x [0, size] x [0, size], 12 triangles.
    void writeCube(const std::string& name, double x0, double size) {
        std::string text;
        char line[128];
        for (int i = 0; i < 8; ++i) {
            std::snprintf(line, sizeof line, "v %.17g %.17g %.17g\n", x0 + size * (i & 1),
                          size * ((i >> 1) & 1), size * ((i >> 2) & 1));
            text += line;
        }
        // Counter-clockwise seen from outside; vertices 1-based.
        const int faces[12][3] = {{1, 3, 4}, {1, 4, 2}, {5, 6, 8}, {5, 8, 7}, {1, 2, 6}, {1, 6, 5},
                                  {3, 7, 8}, {3, 8, 4}, {1, 5, 7}, {1, 7, 3}, {2, 4, 8}, {2, 8, 6}};
        for (const auto& f : faces) {
            std::snprintf(line, sizeof line, "f %d %d %d\n", f[0], f[1], f[2]);
            text += line;
        }
        writeText(name, text);
    }

    /// A level set sphere of radius 10 voxels (voxel size 1) centred at (kFar, 0, 0), made by
    /// the library in double precision.
    void writeFarSphere(const std::string& name) {
        auto grid = tools::createLevelSetSphere<FloatGrid>(10.0, Vec3d(kFar, 0, 0), 1.0, 3.0);
        grid->setName("far");
        ASSERT_GT(grid->activeVoxelCount(), 0u);
        io::File(path(name)).write(GridPtrVec{grid});
    }
};

TEST_F(PrecisionCli, SphereBelowOneAndAHalfVoxelsIsRefusedNotWrittenEmpty) {
    // The default radius 1 at voxel size 1: nothing a level set can hold.
    fails({"sphere", "-o", path("s.vdb"), "--center", "1.0737e9,0,0", "--voxel-size", "1"}, 2,
          "below the 1.5 voxels");
    fails({"sphere", "-o", path("s.vdb"), "--voxel-size", "1"}, 2, "below the 1.5 voxels");
}

TEST_F(PrecisionCli, SphereFarFromTheOriginIsRoundAndInPlace) {
    ok({"sphere", "-o", path("s.vdb"), "--radius", "10", "--center", "1.0737e9,0,0", "--voxel-size",
        "1", "--quiet"});
    const auto grid = gridPtrCast<FloatGrid>(readFirst("s.vdb"));
    ASSERT_TRUE(grid);
    ASSERT_GT(grid->activeVoxelCount(), 4000u);  // the band of a sphere of radius 10 voxels
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const Vec3d p = grid->transform().indexToWorld(it.getCoord());
        const double d = (p - Vec3d(kFar, 0, 0)).length() - 10.0;
        ASSERT_NEAR(*it, d, 1e-3) << it.getCoord();
    }
}

TEST_F(PrecisionCli, SpheresWhereFloatsAreCoarseAreRefused) {
    writeText("far.txt", "1.0737e9 0 0 5\n");
    fails({"spheres", "-o", path("s.vdb"), "--input", path("far.txt"), "--voxel-size", "1"}, 2,
          "float coordinates are 64 apart");
    // The same sphere near the origin is drawn where it is.
    writeText("near.txt", "100 0 0 5\n");
    ok({"spheres", "-o", path("s.vdb"), "--input", path("near.txt"), "--voxel-size", "1",
        "--quiet"});
    const auto grid = gridPtrCast<FloatGrid>(readFirst("s.vdb"));
    ASSERT_TRUE(grid);
    EXPECT_LT(grid->tree().getValue(Coord(100, 0, 0)), 0.0f);
    EXPECT_TRUE(grid->tree().isValueOn(Coord(105, 0, 0)));
}

TEST_F(PrecisionCli, SpheresAllTooSmallAreRefusedNotWrittenEmpty) {
    writeText("small.txt", "0 0 0 0.5\n3 0 0 0.7\n");
    fails({"spheres", "-o", path("s.vdb"), "--input", path("small.txt"), "--voxel-size", "1"}, 2,
          "no active values");
}

TEST_F(PrecisionCli, MeshWhereFloatsAreCoarseIsRefused) {
    writeCube("far.obj", kFar, 20.0);
    fails({"mesh", path("far.obj"), "-o", path("m.vdb"), "--voxel-size", "1"}, 2,
          "float coordinates are 64 apart");
    // At voxel size 256 the spacing of 64 is still 1/4 of a voxel.
    fails({"mesh", path("far.obj"), "-o", path("m.vdb"), "--voxel-size", "256"}, 2, "1/8");
    writeCube("near.obj", 0.0, 20.0);
    ok({"mesh", path("near.obj"), "-o", path("m.vdb"), "--voxel-size", "1", "--quiet"});
    const auto grid = gridPtrCast<FloatGrid>(readFirst("m.vdb"));
    ASSERT_TRUE(grid);
    EXPECT_LT(grid->tree().getValue(Coord(10, 10, 10)), 0.0f);
    EXPECT_NEAR(grid->tree().getValue(Coord(10, 10, 0)), 0.0f, 1e-4f);
}

TEST_F(PrecisionCli, SurfacesWhereFloatsAreCoarseAreRefusedByEveryMeshingCommand) {
    writeFarSphere("far.vdb");
    // rebuild and resample (level sets are rebuilt) and tomesh take the surface as float points.
    fails({"rebuild", path("far.vdb"), "-o", path("r.vdb")}, 2, "float coordinates");
    fails({"resample", path("far.vdb"), "-o", path("r.vdb"), "--scale", "2"}, 2,
          "float coordinates");
    fails({"tomesh", path("far.vdb"), "-o", path("r.obj")}, 2, "float coordinates");
    // Index-space commands are exact there: redistance keeps the sphere.
    ok({"redistance", path("far.vdb"), "-o", path("d.vdb"), "--quiet"});
    EXPECT_GT(readFirst("d.vdb")->activeVoxelCount(), 0u);
}

TEST_F(PrecisionCli, ClipFarFromTheOriginIsExactAndAnEmptyClipIsRefused) {
    auto grid = FloatGrid::create(0.0f);
    grid->setName("density");
    const Int32 x0 = Int32(kFar);
    for (Int32 i = 0; i < 10; ++i)
        grid->tree().setValueOn(Coord(x0 + i, 0, 0), float(i));
    io::File(path("in.vdb")).write(GridPtrVec{grid});
    // World [x0 + 2, x0 + 5.5]: voxels x0 + 2 to x0 + 5.
    char box[128];
    std::snprintf(box, sizeof box, "%d,-1,-1,%.1f,1,1", x0 + 2, double(x0) + 5.5);
    ok({"clip", path("in.vdb"), "-o", path("out.vdb"), "--bbox", box, "--quiet"});
    const auto out = gridPtrCast<FloatGrid>(readFirst("out.vdb"));
    ASSERT_TRUE(out);
    EXPECT_EQ(out->activeVoxelCount(), 4u);
    for (Int32 i = 2; i <= 5; ++i)
        EXPECT_TRUE(out->tree().isValueOn(Coord(x0 + i, 0, 0))) << i;
    // A box that holds none of the voxels: refused, nothing written.
    fails({"clip", path("in.vdb"), "-o", path("none.vdb"), "--bbox", "0,0,0,1,1,1"}, 2,
          "no active values");
}

TEST_F(PrecisionCli, EditsAndCombinationsThatLeaveNothingAreRefused) {
    ok({"sphere", "-o", path("a.vdb"), "--radius", "1", "--voxel-size", "0.1", "--quiet"});
    ok({"sphere", "-o", path("b.vdb"), "--radius", "1", "--center", "5,0,0", "--voxel-size", "0.1",
        "--quiet"});
    fails({"csg", "intersection", path("a.vdb"), path("b.vdb"), "-o", path("i.vdb")}, 2,
          "no active values");
    fails({"morph", "erode", "10", path("a.vdb"), "-o", path("e.vdb")}, 2, "no active values");
    fails({"tomesh", path("a.vdb"), "-o", path("m.obj"), "--isovalue", "5"}, 2, "no surface");
}

TEST_F(PrecisionCli, RenderThatSeesNothingIsRefused) {
    ok({"sphere", "-o", path("s.vdb"), "--radius", "1", "--voxel-size", "0.1", "--quiet"});
    // Looking away from the sphere.
    fails({"render", path("s.vdb"), "-o", path("away.png"), "--width", "32", "--height", "32",
           "--position", "0,0,10", "--look-at", "0,0,20"},
          2, "covers no pixel");
    // From 1.0737e9 away the sphere is far below a pixel.
    fails({"render", path("s.vdb"), "-o", path("far.png"), "--width", "32", "--height", "32",
           "--position", "1.0737e9,0,0", "--look-at", "0,0,0"},
          2, "covers no pixel");
    ok({"render", path("s.vdb"), "-o", path("near.png"), "--width", "32", "--height", "32",
        "--position", "0,0,10", "--look-at", "0,0,0", "--quiet"});
    EXPECT_GT(test::readPng(path("near.png")).coveredCount(), 0u);
}

TEST_F(PrecisionCli, AdvectNamesFramesByTheRenderRule) {
    ok({"sphere", "-o", path("s.vdb"), "--radius", "0.3", "--voxel-size", "0.05", "--quiet"});
    const std::vector<std::string> advect{"advect", path("s.vdb"), "--field", "constant", "--time",
                                          "0.1",    "--frames",    "2",       "--quiet"};
    auto with = [&](const std::string& out) {
        std::vector<std::string> args = advect;
        args.insert(args.end(), {"-o", path(out)});
        return args;
    };
    // Several frames need # in the name.
    fails(with("moved.vdb"), 2, "needs #");
    ok(with("f_#.vdb"));
    EXPECT_TRUE(fs::exists(path("f_0001.vdb")));
    EXPECT_TRUE(fs::exists(path("f_0002.vdb")));
    ok(with("g_##.vdb"));
    EXPECT_TRUE(fs::exists(path("g_01.vdb")));
    EXPECT_TRUE(fs::exists(path("g_02.vdb")));
}

}  // namespace
}  // namespace vdb
