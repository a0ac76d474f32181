// SPDX-License-Identifier: Apache-2.0
// End-to-end tests of `vdb resample`: the outputs are read back with the library and compared
// with the same resampling done through tools::resampleToMatch (the oracle for what the
// command computes) and with the analytic sphere; bad requests must fail with status 2, one
// error line, no new file and the existing output untouched.

#include <vdb/io/File.h>
#include <vdb/tools/GridTransformer.h>
#include <vdb/tools/LevelSetRebuild.h>
#include <vdb/tools/LevelSetSphere.h>

#include "CliFixture.h"
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace vdb {
namespace {

class ResampleCli : public test::ToolTest {
protected:
    /// A level set sphere "sphere" (voxel size 0.1, radius 1) and a fog volume "density"
    /// that is the sphere's interior, in one file.
    void writeInput(const std::string& name) {
        auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.05f), 0.1f);
        sphere->setName("sphere");
        auto density = FloatGrid::create(0.0f);
        density->setName("density");
        density->setGridClass(GRID_FOG_VOLUME);
        density->setTransform(sphere->transform().copy());
        auto acc = density->getAccessor();
        for (auto it = sphere->tree().cbeginValueOn(); it; ++it) {
            if (*it < 0.0f)
                acc.setValue(it.getCoord(), std::min(1.0f, -*it / 0.2f));
        }
        io::File(path(name)).write({sphere, density});
    }
    /// The grid named `grid` of file `name`.
    FloatGrid::Ptr grid(const std::string& name, const std::string& grid) {
        for (const auto& g : read(name)) {
            if (g->getName() == grid)
                return gridPtrCast<FloatGrid>(g);
        }
        ADD_FAILURE() << name << " has no float grid " << grid;
        return FloatGrid::create();
    }
    GridPtrVec read(const std::string& name) {
        io::File file(path(name));
        file.open();
        GridPtrVec grids = *file.getGrids();
        file.close();
        return grids;
    }
};

TEST_F(ResampleCli, VoxelSizeResamplesEveryGridLikeTheLibrary) {
    writeInput("in.vdb");
    ok({"resample", path("in.vdb"), "-o", path("out.vdb"), "--voxel-size", "0.2", "-q"});
    const GridPtrVec in = read("in.vdb"), out = read("out.vdb");
    ASSERT_EQ(out.size(), 2u);
    for (size_t g = 0; g < 2; ++g) {
        const auto src = gridPtrCast<FloatGrid>(in[g]);
        const auto got = gridPtrCast<FloatGrid>(out[g]);
        ASSERT_TRUE(got);
        EXPECT_EQ(got->getName(), src->getName());
        EXPECT_EQ(got->getGridClass(), src->getGridClass());
        EXPECT_NEAR(got->voxelSize()[0], 0.2, 1e-12);
        auto expected = FloatGrid::create();
        expected->setTransform(got->transform().copy());
        tools::resampleToMatch<tools::BoxSampler>(*src, *expected);
        EXPECT_TRUE(test::sameContents(got->tree(), expected->tree())) << src->getName();
    }
    // The sphere is still a sphere: its zero crossing within a coarse voxel of radius 1.
    const auto sphere = grid("out.vdb", "sphere");
    const float inside = sphere->tree().getValue(
        sphere->transform().worldToIndexCellCentered(Vec3d(0.05, 0.05, 0.05)));
    EXPECT_LT(inside, 0.0f);
    const Coord rim = sphere->transform().worldToIndexCellCentered(Vec3d(1.05, 0.05, 0.05));
    EXPECT_LT(std::abs(sphere->tree().getValue(rim)), 0.2f);
}

TEST_F(ResampleCli, ScaleAndMatchAndSamplerChooseTheTargetAndReconstruction) {
    writeInput("in.vdb");
    // --scale 0.5: twice the resolution; the point sampler for the fog volume.
    ok({"resample", path("in.vdb"), "-o", path("fine.vdb"), "--scale", "0.5", "--sampler", "point",
        "-g", "density", "-q"});
    const auto density = grid("in.vdb", "density");
    const auto fineDensity = grid("fine.vdb", "density");
    EXPECT_NEAR(fineDensity->voxelSize()[0], 0.05, 1e-8);  // 0.1 was stored as a float
    auto expected = FloatGrid::create();
    expected->setTransform(fineDensity->transform().copy());
    tools::resampleToMatch<tools::PointSampler>(*density, *expected);
    EXPECT_TRUE(test::sameContents(fineDensity->tree(), expected->tree()));
    // The sphere was not selected: it is written unchanged.
    EXPECT_TRUE(
        test::sameContents(grid("fine.vdb", "sphere")->tree(), grid("in.vdb", "sphere")->tree()));

    // --match: the transform of the first grid of another file.
    auto ref = FloatGrid::create();
    Mat4d m = Mat4d::scale(Vec3d(0.07, 0.09, 0.08));
    m.postRotate(math::Axis::Z, 0.4);
    ref->setTransform(math::Transform::createLinearTransform(m));
    ref->setName("ref");
    io::File(path("ref.vdb")).write({ref});
    ok({"resample", path("in.vdb"), "-o", path("matched.vdb"), "--match", path("ref.vdb"),
        "--sampler", "quadratic", "-q"});
    const GridPtrVec matched = read("matched.vdb");
    for (const auto& g : matched)
        EXPECT_TRUE(g->transform() == ref->transform()) << g->getName();
    auto quadratic = FloatGrid::create();
    quadratic->setTransform(ref->transform().copy());
    tools::resampleToMatch<tools::QuadraticSampler>(*density, *quadratic);
    EXPECT_TRUE(test::sameContents(grid("matched.vdb", "density")->tree(), quadratic->tree()));
}

TEST_F(ResampleCli, BadRequestsFailWithOneLineAndLoseNothing) {
    writeInput("in.vdb");
    ok({"resample", path("in.vdb"), "-o", path("out.vdb"), "--scale", "2", "-q"});
    const std::vector<uint8_t> before = test::fileBytes(path("out.vdb"));
    // No target, two targets, a bad value, a bad sampler, a missing file.
    fails({"resample", path("in.vdb"), "-o", path("out.vdb")}, 2, "exactly one of");
    fails(
        {"resample", path("in.vdb"), "-o", path("out.vdb"), "--scale", "2", "--voxel-size", "0.1"},
        2, "exactly one of");
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--scale", "-1"}, 2, "scale");
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--voxel-size", "nan"}, 2,
          "voxel-size");
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--scale", "2", "--sampler", "cubic"},
          2, "sampler");
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--match", path("missing.vdb")}, 1,
          "missing.vdb");
    fails({"resample", path("missing.vdb"), "-o", path("out.vdb"), "--scale", "2"}, 1,
          "missing.vdb");
    // An output far too large for the memory limit is refused before any work.
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--voxel-size", "1e-6"}, 2, "limit");
    // Refusals for other reasons do not point at --max-memory.
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--voxel-size", "1e300"}, 2,
          "matrix");
    EXPECT_EQ(run({"resample", path("in.vdb"), "-o", path("out.vdb"), "--voxel-size", "1e300"})
                  .err.find("--max-memory"),
              std::string::npos);
    // A frustum reference.
    auto frustum = FloatGrid::create();
    frustum->setTransform(
        math::Transform::createFrustumTransform(BBoxd(Vec3d(0), Vec3d(31)), 0.5, 2.0));
    io::File(path("frustum.vdb")).write({frustum});
    fails({"resample", path("in.vdb"), "-o", path("out.vdb"), "--match", path("frustum.vdb")}, 2,
          "frustum");
    // A grid type the command does not handle.
    auto ints = Int32Grid::create(0);
    ints->setName("labels");
    ints->tree().setValue(Coord(1, 2, 3), 7);
    io::File(path("ints.vdb")).write({ints});
    fails({"resample", path("ints.vdb"), "-o", path("out.vdb"), "--scale", "2"}, 2, "int32");
    EXPECT_EQ(test::fileBytes(path("out.vdb")), before);
}

}  // namespace
}  // namespace vdb

namespace vdb {
namespace {

// `vdb rebuild` of a level set whose transform is linear with a non-uniform scale rebuilds it in
// that transform's index space, exactly as tools::levelSetRebuild does; --voxel-size moves it
// to cubic voxels instead (main refused both).
TEST_F(ResampleCli, RebuildTakesANonUniformTransformLikeTheLibrary) {
    auto sphere = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.05f), 0.1f);
    auto target = FloatGrid::create(0.3f);
    target->setGridClass(GRID_LEVEL_SET);
    auto xform = math::Transform::createLinearTransform(0.1);
    xform->preScale(Vec3d(1.0, 1.4, 1.2));
    target->setTransform(xform);
    tools::resampleToMatch<tools::BoxSampler>(*sphere, *target);
    target->setName("ls");
    io::File(path("in.vdb")).write({target});

    ok({"rebuild", path("in.vdb"), "-o", path("out.vdb"), "-q"});
    const FloatGrid::Ptr ours = grid("out.vdb", "ls");
    const auto expected = tools::levelSetRebuild(*target, 0.0f, 3.0f, &target->transform());
    EXPECT_TRUE(ours->transform() == target->transform());
    EXPECT_EQ(ours->activeVoxelCount(), expected->activeVoxelCount());
    EXPECT_GT(ours->activeVoxelCount(), 0u);
    auto acc = expected->getConstAccessor();
    size_t differ = 0;
    for (auto it = ours->tree().cbeginValueOn(); it; ++it)
        differ += !acc.isValueOn(it.getCoord()) || acc.getValue(it.getCoord()) != *it;
    EXPECT_EQ(differ, 0u);

    ok({"rebuild", path("in.vdb"), "-o", path("cubic.vdb"), "--voxel-size", "0.1", "-q"});
    const Vec3d size = grid("cubic.vdb", "ls")->voxelSize();
    EXPECT_DOUBLE_EQ(size[0], 0.1);
    EXPECT_DOUBLE_EQ(size[1], 0.1);
    EXPECT_DOUBLE_EQ(size[2], 0.1);
}

}  // namespace
}  // namespace vdb
