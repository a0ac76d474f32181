// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of the `vdb` command-line tool: each subcommand runs on small inputs in a
// temporary folder and its output is read back with the library and compared with the same
// operation done through the library (or with analytic values); bad inputs must give one
// error line, a non-zero exit status and no output file.

#include <vdb/io/File.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/GridOperators.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/ParticlesToLevelSet.h>
#include <vdb/tools/Prune.h>

#include "CliFixture.h"
#include "GridContents.h"
#include "ToolRunner.h"
#include <gtest/gtest.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace vdb {
namespace {

namespace fs = std::filesystem;
using test::Picture;
using test::readPng;
using test::Result;

class Cli : public test::ToolTest {
protected:
    /// Writes a sphere of radius `r` (world units) at `center`, voxel size 0.1, half width 3.
    FloatGrid::Ptr writeSphere(const std::string& name, float r, Vec3f center) {
        auto grid = tools::createLevelSetSphere<FloatGrid>(r, center, 0.1f, 3.0f);
        grid->setName("sphere");
        io::File(path(name)).write(GridPtrVec{grid});
        return grid;
    }

    static GridBase::Ptr readFirst(const std::string& file) {
        io::File in(file);
        in.open();
        auto grids = in.getGrids();
        EXPECT_FALSE(grids->empty());
        return grids->empty() ? nullptr : grids->front();
    }

    template <typename TreeT>
    static void expectSameVoxels(const TreeT& a, const TreeT& b) {
        EXPECT_EQ(a.activeVoxelCount(), b.activeVoxelCount());
        for (auto it = a.cbeginValueOn(); it; ++it) {
            ASSERT_TRUE(b.isValueOn(it.getCoord())) << it.getCoord();
            ASSERT_EQ(b.getValue(it.getCoord()), *it) << it.getCoord();
        }
    }
};

TEST_F(Cli, SphereWritesTheLevelSetTheLibraryBuilds) {
    const Result r = ok({"sphere", "-o", path("s.vdb"), "--radius", "1.5", "--center", "0.5,0,-1",
                         "--voxel-size", "0.1", "--half-width", "3", "--name", "ball"});
    EXPECT_NE(r.out.find("active voxels"), std::string::npos) << r.out;
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("s.vdb")));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "ball");
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    auto expected = tools::createLevelSetSphere<FloatGrid>(1.5f, Vec3f(0.5f, 0, -1), 0.1f, 3.0f);
    expectSameVoxels(grid->tree(), expected->tree());
    // Analytic check: every active value is the distance to the sphere within a voxel's rounding.
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        const Vec3d xyz = grid->indexToWorld(Vec3d(it.getCoord()));
        const double d = std::sqrt((xyz[0] - 0.5) * (xyz[0] - 0.5) + xyz[1] * xyz[1] +
                                   (xyz[2] + 1) * (xyz[2] + 1)) -
                         1.5;
        ASSERT_NEAR(*it, d, 1e-5);
    }
}

TEST_F(Cli, InfoReportsCountsInTextAndJson) {
    auto grid = writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    const std::string count = std::to_string(grid->activeVoxelCount());
    const Result text = ok({"info", "-l", path("s.vdb")});
    EXPECT_NE(text.out.find("sphere"), std::string::npos);
    EXPECT_NE(text.out.find("Tree_float_5_4_3"), std::string::npos);
    EXPECT_NE(text.out.find("level set"), std::string::npos);
    const Result json = ok({"info", "--json", path("s.vdb")});
    EXPECT_NE(json.out.find("\"activeVoxels\": " + count), std::string::npos) << json.out;
    EXPECT_NE(json.out.find("\"leaves\": " + std::to_string(grid->leafCount())), std::string::npos);
    EXPECT_NE(json.out.find("\"name\": \"sphere\""), std::string::npos);
    EXPECT_EQ(json.out.front(), '{');
}

TEST_F(Cli, MorphDilatesAndErodesAsTheLibraryDoes) {
    auto grid = writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"morph", "dilate", "2", path("s.vdb"), "-o", path("d.vdb"), "--nn", "vertex"});
    auto dilated = gridPtrCast<FloatGrid>(readFirst(path("d.vdb")));
    ASSERT_TRUE(dilated);
    auto expected = grid->deepCopy();
    tools::dilateActiveValues(expected->tree(), 2, tools::NN_FACE_EDGE_VERTEX);
    expectSameVoxels(dilated->tree(), expected->tree());
    EXPECT_GT(dilated->activeVoxelCount(), grid->activeVoxelCount());

    ok({"morph", "erode", "1", path("s.vdb"), "-o", path("e.vdb")});
    auto eroded = gridPtrCast<FloatGrid>(readFirst(path("e.vdb")));
    ASSERT_TRUE(eroded);
    expected = grid->deepCopy();
    tools::erodeActiveValues(expected->tree(), 1, tools::NN_FACE);
    expectSameVoxels(eroded->tree(), expected->tree());
    EXPECT_LT(eroded->activeVoxelCount(), grid->activeVoxelCount());
}

TEST_F(Cli, FloodFillSignsTheInsideOfABand) {
    // The band of a sphere with every inactive value at +background: the inside is unsigned.
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.1f, 3.0f);
    auto band = FloatGrid::create(sphere->background());
    band->setTransform(sphere->transform().copy());
    band->setGridClass(GRID_LEVEL_SET);
    band->setName("band");
    for (auto it = sphere->cbeginValueOn(); it; ++it)
        band->tree().setValueOn(it.getCoord(), *it);
    io::File(path("band.vdb")).write(GridPtrVec{band});
    ASSERT_GT(band->tree().getValue(Coord(0, 0, 0)), 0.0f);

    ok({"floodfill", path("band.vdb"), "-o", path("filled.vdb")});
    auto filled = gridPtrCast<FloatGrid>(readFirst(path("filled.vdb")));
    ASSERT_TRUE(filled);
    EXPECT_EQ(filled->tree().getValue(Coord(0, 0, 0)), -sphere->background());
    EXPECT_EQ(filled->tree().getValue(Coord(30, 0, 0)), sphere->background());
    expectSameVoxels(filled->tree(), band->tree());
}

TEST_F(Cli, PruneCollapsesConstantLeavesAndKeepsValues) {
    auto grid = FloatGrid::create(0.0f);
    grid->setName("density");
    grid->tree().fill(CoordBBox(Coord(0), Coord(15)), 2.0f, true);
    grid->tree().setValueOn(Coord(100, 0, 0), 1.0f);
    // fill() may already make tiles; make sure leaves exist by touching them.
    for (int i = 0; i < 16; i += 8)
        for (int j = 0; j < 16; j += 8)
            for (int k = 0; k < 16; k += 8)
                grid->tree().touchLeaf(Coord(i, j, k));
    const Index32 leavesBefore = grid->leafCount();
    io::File(path("in.vdb")).write(GridPtrVec{grid});
    ok({"prune", path("in.vdb"), "-o", path("out.vdb")});
    auto pruned = gridPtrCast<FloatGrid>(readFirst(path("out.vdb")));
    ASSERT_TRUE(pruned);
    EXPECT_EQ(pruned->leafCount(), 1u);
    EXPECT_LT(pruned->leafCount(), leavesBefore);
    EXPECT_EQ(pruned->activeVoxelCount(), grid->activeVoxelCount());
    EXPECT_EQ(pruned->tree().getValue(Coord(5, 9, 3)), 2.0f);
    EXPECT_EQ(pruned->tree().getValue(Coord(100, 0, 0)), 1.0f);
}

TEST_F(Cli, CsgMatchesTheLibraryAndTheAnalyticUnion) {
    auto a = writeSphere("a.vdb", 1.0f, Vec3f(0.0f));
    auto b = writeSphere("b.vdb", 1.0f, Vec3f(0.8f, 0, 0));
    for (const std::string op : {"union", "intersection", "difference"}) {
        ok({"csg", op, path("a.vdb"), path("b.vdb"), "-o", path(op + ".vdb")});
        auto result = gridPtrCast<FloatGrid>(readFirst(path(op + ".vdb")));
        ASSERT_TRUE(result);
        auto expected = op == "union"          ? tools::csgUnionCopy(*a, *b)
                        : op == "intersection" ? tools::csgIntersectionCopy(*a, *b)
                                               : tools::csgDifferenceCopy(*a, *b);
        expectSameVoxels(result->tree(), expected->tree());
    }
    // The union's zero crossing lies on the analytic union of the two spheres.
    auto u = gridPtrCast<FloatGrid>(readFirst(path("union.vdb")));
    EXPECT_NEAR(u->tree().getValue(Coord(18, 0, 0)), 0.0f, 1e-5f);   // x = 1.8: right surface
    EXPECT_NEAR(u->tree().getValue(Coord(-10, 0, 0)), 0.0f, 1e-5f);  // x = -1: left surface
    EXPECT_LT(u->tree().getValue(Coord(9, 0, 0)), 0.0f);             // inside both
}

TEST_F(Cli, ConvertChangesStorageButNotTheGrid) {
    auto grid = writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"convert", path("s.vdb"), "-o", path("raw.vdb"), "--compression", "none"});
    ok({"convert", path("s.vdb"), "-o", path("half.vdb"), "--compression", "zip", "--half"});
    auto raw = gridPtrCast<FloatGrid>(readFirst(path("raw.vdb")));
    auto half = gridPtrCast<FloatGrid>(readFirst(path("half.vdb")));
    ASSERT_TRUE(raw && half);
    expectSameVoxels(raw->tree(), grid->tree());
    EXPECT_TRUE(half->saveFloatAsHalf());
    EXPECT_EQ(half->activeVoxelCount(), grid->activeVoxelCount());
    for (auto it = grid->cbeginValueOn(); it; ++it)
        ASSERT_NEAR(half->tree().getValue(it.getCoord()), *it, 1e-3f * std::abs(*it) + 1e-6f);
    EXPECT_LT(fs::file_size(path("half.vdb")), fs::file_size(path("raw.vdb")));
}

/// The cube [-0.5, 0.5]^3 as 12 triangles in an OBJ file.
void writeCubeObj(const std::string& file) {
    std::ofstream obj(file);
    for (int i = 0; i < 8; ++i)
        obj << "v " << ((i & 1) ? 0.5 : -0.5) << ' ' << ((i & 2) ? 0.5 : -0.5) << ' '
            << ((i & 4) ? 0.5 : -0.5) << '\n';
    // Two triangles per face, counter-clockwise seen from outside (1-based indices).
    const int faces[6][4] = {{1, 3, 4, 2}, {5, 6, 8, 7}, {1, 2, 6, 5},
                             {3, 7, 8, 4}, {1, 5, 7, 3}, {2, 4, 8, 6}};
    for (const auto& f : faces)
        obj << "f " << f[0] << ' ' << f[1] << ' ' << f[2] << "\nf " << f[0] << ' ' << f[2] << ' '
            << f[3] << '\n';
}

/// Signed distance to the cube [-0.5, 0.5]^3.
double cubeDistance(const Vec3d& p) {
    const Vec3d q(std::abs(p[0]) - 0.5, std::abs(p[1]) - 0.5, std::abs(p[2]) - 0.5);
    const Vec3d outside(std::max(q[0], 0.0), std::max(q[1], 0.0), std::max(q[2], 0.0));
    return outside.length() + std::min(std::max({q[0], q[1], q[2]}), 0.0);
}

/// The number after "key": in a JSON document (NaN when absent).
double jsonNumber(const std::string& json, const std::string& key) {
    const size_t at = json.find("\"" + key + "\":");
    if (at == std::string::npos)
        return std::nan("");
    return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

TEST_F(Cli, MeshGivesTheExactDistanceToACube) {
    writeCubeObj(path("cube.obj"));
    ok({"mesh", path("cube.obj"), "-o", path("cube.vdb"), "--voxel-size", "0.05", "--half-width",
        "3", "--name", "cube"});
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("cube.vdb")));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getName(), "cube");
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    ASSERT_GT(grid->activeVoxelCount(), 1000u);
    for (auto it = grid->tree().cbeginValueOn(); it; ++it) {
        const Vec3d p = grid->transform().indexToWorld(it.getCoord());
        ASSERT_NEAR(*it, cubeDistance(p), 1e-5) << it.getCoord();
    }
    // The centre is inside, far outside is outside.
    EXPECT_LT(grid->tree().getValue(Coord(0)), 0.0f);
    EXPECT_GT(grid->tree().getValue(Coord(40, 0, 0)), 0.0f);

    // --resolution: voxels across the largest side; the robust sign agrees on a closed mesh.
    ok({"mesh", path("cube.obj"), "-o", path("cube20.vdb"), "--resolution", "20", "--sign",
        "robust"});
    auto coarse = gridPtrCast<FloatGrid>(readFirst(path("cube20.vdb")));
    ASSERT_TRUE(coarse);
    EXPECT_NEAR(coarse->voxelSize()[0], 0.05, 1e-9);
    expectSameVoxels(coarse->tree(), grid->tree());
}

TEST_F(Cli, SpheresFromAFileGiveTheDistanceToTheirUnion) {
    const std::vector<std::array<double, 4>> spheres = {
        {0.0, 0.0, 0.0, 0.5}, {0.6, 0.1, 0.0, 0.4}, {-0.3, 0.7, 0.2, 0.3}};
    {
        std::ofstream list(path("spheres.csv"));
        list << "x,y,z,radius\n# three spheres\n";
        for (const auto& s : spheres)
            list << s[0] << ", " << s[1] << ", " << s[2] << ", " << s[3] << '\n';
    }
    ok({"spheres", "-o", path("s.vdb"), "--input", path("spheres.csv"), "--voxel-size", "0.05"});
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("s.vdb")));
    ASSERT_TRUE(grid);
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
    ASSERT_GT(grid->activeVoxelCount(), 1000u);
    for (auto it = grid->tree().cbeginValueOn(); it; ++it) {
        const Vec3d p = grid->transform().indexToWorld(it.getCoord());
        double d = 1e30;
        for (const auto& s : spheres)
            d = std::min(d, (p - Vec3d(s[0], s[1], s[2])).length() - s[3]);
        ASSERT_NEAR(*it, d, 1e-5) << it.getCoord();
    }
}

TEST_F(Cli, SpheresOnTheHelixEqualTheLibrarysRasterization) {
    ok({"spheres", "-o", path("helix.vdb"), "--count", "3000", "--radius", "0.02", "--voxel-size",
        "0.01"});
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("helix.vdb")));
    ASSERT_TRUE(grid);
    auto expected = FloatGrid::create(0.03f);
    expected->setTransform(math::Transform::createLinearTransform(0.01));
    expected->setGridClass(GRID_LEVEL_SET);
    tools::ParticlesToLevelSet<FloatGrid> raster(*expected);
    const auto list = tools::torusKnotHelixSpheres(3000, 0.02f);
    raster.rasterizeSpheres(list.positions, list.radii);
    raster.finalize();
    ASSERT_GT(expected->activeVoxelCount(), 10000u);
    expectSameVoxels(grid->tree(), expected->tree());
}

TEST_F(Cli, DemoWritesTheUnionOfItsLevelSetsAndAPicture) {
    const Result r = ok({"demo", "-o", mDir.string(), "--spheres", "5000", "--resolution", "128",
                         "--width", "160", "--height", "120"});
    EXPECT_NE(r.out.find("demo done"), std::string::npos) << r.out;
    io::File in(path("demo.vdb"));
    in.open();
    auto helix = gridPtrCast<FloatGrid>(in.readGrid("helix"));
    auto mesh = gridPtrCast<FloatGrid>(in.readGrid("mesh"));
    auto both = gridPtrCast<FloatGrid>(in.readGrid("union"));
    ASSERT_TRUE(helix && mesh && both);
    ASSERT_GT(helix->activeVoxelCount(), 1000u);
    ASSERT_GT(mesh->activeVoxelCount(), 1000u);
    tools::csgUnion(*helix, *mesh);
    expectSameVoxels(both->tree(), helix->tree());
    const Picture picture = readPng(path("demo.png"));
    ASSERT_EQ(picture.width, 160u);
    ASSERT_EQ(picture.height, 120u);
    // The shapes cover a good part of the frame: pixels unlike the corner (the background).
    size_t shape = 0;
    for (size_t n = 0; n < picture.width * picture.height; ++n)
        shape += !std::equal(&picture.rgba[4 * n], &picture.rgba[4 * n + 3], &picture.rgba[0]);
    EXPECT_GT(shape, picture.width * picture.height / 10);
}

TEST_F(Cli, AdvectMovesASphereByTheConstantVelocity) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"advect", path("s.vdb"), "-o", path("moved.vdb"), "--field", "constant", "--velocity",
        "1,0,0", "--time", "0.5"});
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("moved.vdb")));
    ASSERT_TRUE(grid);
    // The sphere of radius 1 now sits at (0.5, 0, 0): zero crossings at x = -0.5 and 1.5.
    const auto& tree = grid->tree();
    EXPECT_NEAR(tree.getValue(Coord(15, 0, 0)), 0.0f, 0.03f);
    EXPECT_NEAR(tree.getValue(Coord(-5, 0, 0)), 0.0f, 0.03f);
    EXPECT_NEAR(tree.getValue(Coord(5, 10, 0)), 0.0f, 0.03f);
    EXPECT_LT(tree.getValue(Coord(5, 0, 0)), 0.0f);
    EXPECT_GT(tree.getValue(Coord(-8, 0, 0)), 0.0f);
}

TEST_F(Cli, EnrightReportsFramesAndVolume) {
    const Result r =
        ok({"enright", "--resolution", "48", "--frames", "2", "--time", "0.2", "--json"});
    const double loss = jsonNumber(r.out, "volumeLoss");
    ASSERT_TRUE(std::isfinite(loss)) << r.out;
    // A fifth of a second of a divergence-free field keeps the volume to a few percent.
    EXPECT_LT(std::abs(loss), 0.05) << r.out;
    EXPECT_NE(r.out.find("\"samples\""), std::string::npos) << r.out;
}

TEST_F(Cli, FilterSmoothsLevelSetsAndValueGridsAsTheLibraryDoes) {
    auto sphere = writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"filter", path("s.vdb"), "-o", path("g.vdb"), "--op", "gaussian", "--width", "2"});
    auto smoothed = gridPtrCast<FloatGrid>(readFirst(path("g.vdb")));
    ASSERT_TRUE(smoothed);
    auto expected = sphere->deepCopy();
    tools::LevelSetFilter<FloatGrid>(*expected).gaussian(2);
    expectSameVoxels(smoothed->tree(), expected->tree());

    // A value grid: a mean filter, three iterations, over its active values only.
    auto density = FloatGrid::create(0.0f);
    density->setName("density");
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
            for (int k = 0; k < 12; ++k)
                density->tree().setValue(Coord(i, j, k), float((i * 7 + j * 3 + k) % 5));
    io::File(path("d.vdb")).write(GridPtrVec{density});
    ok({"filter", path("d.vdb"), "-o", path("dm.vdb"), "--op", "mean", "--iterations", "3"});
    auto mean = gridPtrCast<FloatGrid>(readFirst(path("dm.vdb")));
    ASSERT_TRUE(mean);
    tools::Filter<FloatGrid>(*density).mean(1, 3);
    expectSameVoxels(mean->tree(), density->tree());
}

TEST_F(Cli, FilterOffsetMovesTheSurfaceOutwardsForPositiveAmounts) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"filter", path("s.vdb"), "-o", path("o.vdb"), "--op", "offset", "--amount", "0.2"});
    auto grid = gridPtrCast<FloatGrid>(readFirst(path("o.vdb")));
    ASSERT_TRUE(grid);
    // The surface now crosses the x axis at 1.2 (voxel 12), within a hundredth of a voxel.
    EXPECT_NEAR(grid->tree().getValue(Coord(12, 0, 0)), 0.0f, 0.001f);
    EXPECT_NEAR(grid->tree().getValue(Coord(0, -12, 0)), 0.0f, 0.001f);
    EXPECT_EQ(grid->getGridClass(), GRID_LEVEL_SET);
}

TEST_F(Cli, MeasureReportsTheAnalyticAreaVolumeAndGenusOfASphere) {
    const double r = 1.0;
    writeSphere("s.vdb", float(r), Vec3f(0.0f));
    const Result json = ok({"measure", path("s.vdb"), "--json"});
    const double pi = std::numbers::pi;
    EXPECT_NEAR(jsonNumber(json.out, "area"), 4 * pi * r * r, 0.01 * 4 * pi) << json.out;
    EXPECT_NEAR(jsonNumber(json.out, "volume"), 4.0 / 3.0 * pi, 0.01 * 4.0 / 3.0 * pi);
    EXPECT_NEAR(jsonNumber(json.out, "averageMeanCurvature"), 1.0 / r, 0.02);
    EXPECT_EQ(jsonNumber(json.out, "eulerCharacteristic"), 2.0);
    EXPECT_EQ(jsonNumber(json.out, "genus"), 0.0);
    const Result text = ok({"measure", path("s.vdb")});
    EXPECT_NE(text.out.find("genus 0"), std::string::npos) << text.out;
}

TEST_F(Cli, StatsReportsTheValuesAndTheirHistogram) {
    // Active values 1, 2, 3, 4 (one each) and an inactive 100 that must not count.
    auto grid = FloatGrid::create(0.0f);
    grid->setName("v");
    for (int i = 1; i <= 4; ++i)
        grid->tree().setValue(Coord(i, 0, 0), float(i));
    grid->tree().setValueOff(Coord(9, 0, 0), 100.0f);
    io::File(path("v.vdb")).write(GridPtrVec{grid});
    const Result json = ok({"stats", path("v.vdb"), "--bins", "2", "--json"});
    EXPECT_EQ(jsonNumber(json.out, "count"), 4.0) << json.out;
    EXPECT_EQ(jsonNumber(json.out, "min"), 1.0);
    EXPECT_EQ(jsonNumber(json.out, "max"), 4.0);
    EXPECT_EQ(jsonNumber(json.out, "mean"), 2.5);
    EXPECT_NEAR(jsonNumber(json.out, "stdDev"), std::sqrt(1.25), 1e-12);
    // Two bins, [1, 2.5) and [2.5, 4]: two values each.
    const size_t hist = json.out.find("\"histogram\"");
    ASSERT_NE(hist, std::string::npos);
    EXPECT_EQ(jsonNumber(json.out.substr(hist), "count"), 2.0);
    const size_t second = json.out.find("\"count\"", json.out.find("\"count\"", hist) + 1);
    ASSERT_NE(second, std::string::npos);
    EXPECT_EQ(jsonNumber(json.out.substr(second), "count"), 2.0);
}

TEST_F(Cli, OperatorsAndFogWriteWhatTheLibraryComputes) {
    auto sphere = writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    ok({"gradient", path("s.vdb"), "-o", path("g.vdb")});
    auto gradient = gridPtrCast<Vec3SGrid>(readFirst(path("g.vdb")));
    ASSERT_TRUE(gradient);
    EXPECT_EQ(gradient->getName(), "sphere_gradient");
    expectSameVoxels(gradient->tree(), tools::gradient(*sphere)->tree());

    ok({"laplacian", path("s.vdb"), "-o", path("l.vdb")});
    auto laplacian = gridPtrCast<FloatGrid>(readFirst(path("l.vdb")));
    ASSERT_TRUE(laplacian);
    expectSameVoxels(laplacian->tree(), tools::laplacian(*sphere)->tree());

    ok({"divergence", path("g.vdb"), "-o", path("d.vdb")});
    auto divergence = gridPtrCast<FloatGrid>(readFirst(path("d.vdb")));
    ASSERT_TRUE(divergence);
    EXPECT_EQ(divergence->getName(), "sphere_gradient_divergence");
    expectSameVoxels(divergence->tree(), tools::divergence(*gradient)->tree());

    ok({"curl", path("g.vdb"), "-o", path("c.vdb")});
    auto curl = gridPtrCast<Vec3SGrid>(readFirst(path("c.vdb")));
    ASSERT_TRUE(curl);
    expectSameVoxels(curl->tree(), tools::curl(*gradient)->tree());

    ok({"fog", path("s.vdb"), "-o", path("f.vdb")});
    auto fog = gridPtrCast<FloatGrid>(readFirst(path("f.vdb")));
    ASSERT_TRUE(fog);
    EXPECT_EQ(fog->getGridClass(), GRID_FOG_VOLUME);
    auto expected = sphere->deepCopy();
    tools::sdfToFogVolume(*expected);
    expectSameVoxels(fog->tree(), expected->tree());
    EXPECT_EQ(fog->tree().getValue(Coord(0)), 1.0f);  // the centre: deep inside
}

TEST_F(Cli, ToolboxCommandsRefuseBadInputs) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    auto vectors = Vec3SGrid::create(Vec3s(0.0f));
    vectors->setName("vel");
    vectors->tree().setValueOn(Coord(1, 2, 3), Vec3s(1.0f, 0.0f, 0.0f));
    io::File(path("vel.vdb")).write(GridPtrVec{vectors});
    const std::string out = path("out.vdb");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "mean", "--width", "0"}, 2, "--width");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "mean", "--width", "1000000"}, 2, "--width");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "median", "--width", "100"}, 2, "median");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "offset"}, 2, "--amount");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "mean", "--amount", "1"}, 2, "--amount");
    fails({"filter", path("s.vdb"), "-o", out, "--op", "blur"}, 2, "blur");
    fails({"filter", path("vel.vdb"), "-o", out, "--op", "curvature"}, 2, "level set");
    fails({"filter", path("vel.vdb"), "-o", out, "--op", "median", "--grid", "vel"}, 2, "vec3s");
    fails({"gradient", path("vel.vdb"), "-o", out, "--grid", "vel"}, 2, "vec3s");
    fails({"curl", path("s.vdb"), "-o", out}, 2, "vec3s");
    fails({"measure", path("vel.vdb")}, 2, "level set");
    fails({"fog", path("vel.vdb"), "-o", out}, 2, "level set");
    fails({"stats", path("missing.vdb")}, 1, "missing.vdb");
}

TEST_F(Cli, BadGeometryInputsGiveOneErrorLineAndNoOutput) {
    const std::string out = path("out.vdb");
    {
        std::ofstream bad(path("bad.obj"));
        bad << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";  // index out of range
    }
    {
        std::ofstream nan(path("nan.obj"));
        nan << "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n";
    }
    {
        std::ofstream list(path("bad.txt"));
        list << "0 0 0 1\n1 2 three 1\n";
    }
    {
        std::ofstream list(path("neg.txt"));
        list << "0 0 0 -1\n";
    }
    writeCubeObj(path("cube.obj"));
    fails({"mesh", path("missing.obj"), "-o", out, "--voxel-size", "0.1"}, 1, "missing.obj");
    fails({"mesh", path("bad.obj"), "-o", out, "--voxel-size", "0.1"}, 1, "bad.obj");
    fails({"mesh", path("nan.obj"), "-o", out, "--voxel-size", "0.1"}, 1, "nan.obj");
    fails({"mesh", path("cube.obj"), "-o", out}, 2, "--voxel-size");
    fails({"mesh", path("cube.obj"), "-o", out, "--voxel-size", "0.1", "--sign", "maybe"}, 2,
          "maybe");
    fails({"mesh", path("cube.obj"), "-o", out, "--voxel-size", "1e-7"}, 2, "memory");
    fails({"spheres", "-o", out, "--input", path("bad.txt")}, 2, "bad.txt:2");
    fails({"spheres", "-o", out, "--input", path("neg.txt")}, 2, "radius");
    fails({"spheres", "-o", out, "--input", path("missing.txt")}, 2, "missing.txt");
    fails({"spheres", "-o", out, "--count", "0"}, 2, "count");
    fails({"demo", "-o", path("no/such/dir")}, 2, "does not exist");
    fails({"advect", path("missing.vdb"), "-o", out, "--time", "1"}, 1, "missing.vdb");
    fails({"enright", "--resolution", "4"}, 2, "resolution");
}

TEST_F(Cli, EveryCommandHasHelpWithExamples) {
    for (const std::string cmd :
         {"info", "sphere",  "spheres", "mesh",     "morph",     "floodfill",  "prune",
          "csg",  "convert", "advect",  "enright",  "render",    "demo",       "filter",
          "fog",  "measure", "stats",   "gradient", "laplacian", "divergence", "curl"}) {
        const Result r = ok({cmd, "--help"});
        EXPECT_NE(r.out.find("Example"), std::string::npos) << cmd;
        EXPECT_NE(r.out.find("--threads"), std::string::npos) << cmd;
    }
    const Result top = ok({"--help"});
    EXPECT_NE(top.out.find("csg"), std::string::npos);
}

TEST_F(Cli, BadInputsGiveOneErrorLineAndNoOutput) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    {
        std::ofstream junk(path("junk.vdb"), std::ios::binary);
        junk << "this is not a vdb file, only some text that is long enough";
    }
    const std::string out = path("out.vdb");
    fails({"info", path("missing.vdb")}, 1, "missing.vdb");
    fails({"info", path("junk.vdb")}, 1, "junk.vdb");
    fails({"morph", "dilate", "1", path("junk.vdb"), "-o", out}, 1, "junk.vdb");
    fails({"morph", "grow", "1", path("s.vdb"), "-o", out}, 2, "grow");
    fails({"morph", "dilate", "0", path("s.vdb"), "-o", out}, 2, "iterations");
    fails({"morph", "dilate", "1", path("s.vdb"), "-o", path("no/such/dir/out.vdb")}, 2,
          "does not exist");
    fails({"morph", "dilate", "1", path("s.vdb"), "-o", out, "--grid", "nope"}, 2, "nope");
    fails({"prune", path("missing.vdb"), "-o", out}, 1, "missing.vdb");
    fails({"floodfill", path("s.vdb")}, 2, "--output");
    fails({"convert", path("s.vdb"), "-o", out, "--compression", "lzma"}, 2, "lzma");
    fails({"convert", path("s.vdb"), "-o", out, "--half", "--full"}, 2, "--full");
    fails({"sphere", "-o", out, "--radius", "-1"}, 2, "radius");
    fails({"sphere", "-o", out, "--radius", "1000", "--voxel-size", "0.0001"}, 2, "memory");
    fails({"csg", "union", path("s.vdb"), path("junk.vdb"), "-o", out}, 1, "junk.vdb");
    fails({"frobnicate"}, 2, "frobnicate");
    fails({}, 2, "subcommand");

    // A grid of the wrong type for the command.
    auto ints = Int32Grid::create(0);
    ints->setName("labels");
    ints->tree().setValueOn(Coord(1, 2, 3), 7);
    io::File(path("ints.vdb")).write(GridPtrVec{ints});
    fails({"floodfill", path("ints.vdb"), "-o", out, "--grid", "labels"}, 2, "labels");
    fails({"csg", "union", path("s.vdb"), path("ints.vdb"), "-o", out}, 2, "level set");

    // Grids in different index spaces.
    auto moved = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.05f, 3.0f);
    io::File(path("fine.vdb")).write(GridPtrVec{moved});
    fails({"csg", "union", path("s.vdb"), path("fine.vdb"), "-o", out}, 2, "transforms");
}

TEST_F(Cli, RenderDrawsALevelSetSphereWithItsProjectedDisc) {
    // A sphere of radius 1 seen from 4 units away through a 30 degree field of view: its
    // silhouette is a disc of angular radius asin(1/4) about the image centre.
    ok({"sphere", "-o", path("s.vdb"), "--radius", "1", "--voxel-size", "0.02"});
    const size_t w = 96, h = 72;
    const Result r = ok({"render", path("s.vdb"), "-o", path("s.png"), "--width", std::to_string(w),
                         "--height", std::to_string(h), "--position", "0,0,4", "--look-at", "0,0,0",
                         "--fov", "30", "--quiet"});
    EXPECT_TRUE(r.out.empty()) << r.out;
    const Picture pic = readPng(path("s.png"));
    ASSERT_EQ(pic.width, w);
    ASSERT_EQ(pic.height, h);
    const double tanHalfFov = std::tan(15.0 * std::numbers::pi / 180.0);
    const double radius = std::tan(std::asin(0.25)) / tanHalfFov * 0.5 * double(h);  // pixels
    const double disc = std::numbers::pi * radius * radius;
    EXPECT_NEAR(double(pic.litCount()), disc, 0.04 * disc);
    EXPECT_TRUE(pic.lit(w / 2, h / 2));
    EXPECT_FALSE(pic.lit(0, 0));
    EXPECT_FALSE(pic.lit(w - 1, h - 1));
    // The sphere is shaded: the light (0.5, 0.8, 0.6) makes the upper half brighter.
    const auto luma = [&](size_t x, size_t y) {
        const uint8_t* p = &pic.rgba[4 * (y * w + x)];
        return int(p[0]) + int(p[1]) + int(p[2]);
    };
    EXPECT_GT(luma(w / 2, h / 2 - size_t(0.6 * radius)), luma(w / 2, h / 2 + size_t(0.6 * radius)));

    // The normals picture: same size, lit where the sphere is.
    ok({"render", path("s.vdb"), "-o", path("t.png"), "--width", "40", "--height", "30",
        "--normals", path("n.png"), "--quiet"});
    const Picture normals = readPng(path("n.png"));
    EXPECT_EQ(normals.width, 40u);
    EXPECT_EQ(normals.height, 30u);
    EXPECT_EQ(normals.litCount(), readPng(path("t.png")).litCount());
}

TEST_F(Cli, RenderDrawsAFogVolumeBoxAsASquare) {
    // A cube of 32^3 voxels of density 1, seen face on by an orthographic camera whose window
    // is the cube's bounding box diagonal high: a lit square, black around it.
    const int n = 32;
    const double voxel = 0.05;
    auto fog = FloatGrid::create(0.0f);
    fog->setTransform(math::Transform::createLinearTransform(voxel));
    fog->setGridClass(GRID_FOG_VOLUME);
    fog->setName("density");
    fog->tree().fill(CoordBBox(Coord(0), Coord(n - 1)), 1.0f, true);
    io::File(path("fog.vdb")).write(GridPtrVec{fog});
    const double c = 0.5 * (n - 1) * voxel;
    const std::string centre = std::to_string(c) + "," + std::to_string(c) + ",";
    const size_t w = 80, h = 60;
    const Result r = ok({"render", path("fog.vdb"), "-o", path("fog.png"), "--camera", "ortho",
                         "--width", std::to_string(w), "--height", std::to_string(h), "--position",
                         centre + "10", "--look-at", centre + std::to_string(c), "--json"});
    EXPECT_NE(r.out.find("\"mode\": \"fog\""), std::string::npos) << r.out;
    const Picture pic = readPng(path("fog.png"));
    ASSERT_EQ(pic.width, w);
    ASSERT_EQ(pic.height, h);
    const double pixel = std::sqrt(3.0) * (n - 1) * voxel / double(h);  // world units
    // The trilinear density fades to zero within a voxel of the faces.
    const double lo = (n - 2) * voxel / pixel, hi = (n + 1) * voxel / pixel;
    EXPECT_GT(double(pic.litCount()), lo * lo);
    EXPECT_LT(double(pic.litCount()), hi * hi);
    EXPECT_TRUE(pic.lit(w / 2, h / 2));
    EXPECT_FALSE(pic.lit(w / 2 - size_t(0.6 * hi), h / 2));
    EXPECT_FALSE(pic.lit(0, 0));
}

TEST_F(Cli, RenderRejectsBadInputsWithoutWritingAPicture) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    auto ints = Int32Grid::create(0);
    ints->setName("labels");
    ints->tree().setValueOn(Coord(1, 2, 3), 7);
    io::File(path("ints.vdb")).write(GridPtrVec{ints});
    auto empty = FloatGrid::create(0.0f);
    empty->setName("nothing");
    io::File(path("empty.vdb")).write(GridPtrVec{empty});
    const std::string out = path("out.png");
    fails({"render", path("missing.vdb"), "-o", out}, 1, "missing.vdb");
    fails({"render", path("ints.vdb"), "-o", out}, 2, "float or double");
    fails({"render", path("ints.vdb"), "-o", out, "--grid", "labels"}, 2, "float or double");
    fails({"render", path("empty.vdb"), "-o", out}, 2, "empty");
    fails({"render", path("s.vdb"), "-o", out, "--width", "0"}, 2, "--width");
    fails({"render", path("s.vdb"), "-o", out, "--mode", "smoke"}, 2, "smoke");
    fails({"render", path("s.vdb"), "-o", out, "--view", "1,2"}, 2, "--view");
    fails({"render", path("s.vdb"), "-o", out, "--position", "0,0,5"}, 2, "--look-at");
    fails({"render", path("s.vdb"), "-o", out, "--position", "0,0,0", "--look-at", "0,0,0"}, 2,
          "look-at");
    fails({"render", path("s.vdb"), "-o", path("no/such/dir/out.png")}, 2, "does not exist");
    fails({"render", path("s.vdb")}, 2, "--output");
}

TEST_F(Cli, FailureKeepsTheFileThatWasThere) {
    writeSphere("s.vdb", 1.0f, Vec3f(0.0f));
    const auto before = test::fileBytes(path("s.vdb"));
    const Result r = run({"convert", path("missing.vdb"), "-o", path("s.vdb")});
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(test::fileBytes(path("s.vdb")), before);
}

TEST_F(Cli, CtrlCLeavesNoOutputBehind) {
    // A sphere big enough to take seconds; interrupted while it is built or written.
    const pid_t pid = spawn({"sphere", "-o", path("big.vdb"), "--enright", "2048", "--quiet"});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ASSERT_EQ(::kill(pid, SIGINT), 0);
    const Result r = wait(pid);
    EXPECT_EQ(r.status, 128 + SIGINT) << "the command ended before it was interrupted";
    EXPECT_NE(r.err.find("cancelled"), std::string::npos) << r.err;
    for (const auto& e : fs::directory_iterator(mDir))
        ADD_FAILURE() << "left behind: " << e.path().filename();
}

}  // namespace
}  // namespace vdb
