// SPDX-License-Identifier: Apache-2.0
// Samplers and resampling against OpenVDB 10 (tools/Interpolation.h, tools/GridTransformer.h)
// on the same grids: the point and box samplers give bit-identical values and activity, the
// quadratic and staggered ones the same to rounding; transformGrid and resampleToMatch give
// the same active voxels with values within 1e-4; a level set resampled to another voxel size
// or a rotated, non-uniformly scaled transform is no further from the analytic distance near
// the surface than OpenVDB's resampled band plus 0.05 voxel; a level set resampled to a rotated
// transform with unequal scales is rebuilt in its index space as OpenVDB's is (active voxels
// within 3%, equal backgrounds, values within 0.05 voxel near the surface).

// OpenVDB 10's GridResampler hands tbb::parallel_reduce an iterator range that does not model
// oneTBB's C++20 range concept; with the constraints on, its tile pass does not compile.
#define __TBB_USE_CONSTRAINTS 0

#include <vdb/tools/GridTransformer.h>
#include <vdb/tools/Interpolation.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/GridTransformer.h>
#include <openvdb/tools/Interpolation.h>

#include <cmath>
#include <random>

namespace vdb {
namespace {

using test::FloatPair;
using test::fromOvdb;
using test::toOvdb;
using test::Vec3SPair;

// A smooth field with sharp features: sine waves over a box, plus random voxels and (with
// `tile`) an active tile, in both libraries.
FloatPair valuesPair(bool tile = true) {
    const auto field = [](const Vec3d& p) {
        return float(std::sin(0.7 * p[0]) * std::cos(0.4 * p[1]) + 0.1 * p[2]);
    };
    FloatPair p = test::sampledPair<FloatPair>(CoordBBox(Coord(-12), Coord(12)), Vec3d(1.0),
                                               Vec3d(0.0), field, 0.25f);
    std::mt19937 rng(31);
    std::uniform_int_distribution<int> c(-30, 30);
    std::uniform_real_distribution<float> v(-2.0f, 2.0f);
    for (int n = 0; n < 300; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        const float x = v(rng);
        if (rng() % 4 == 0) {
            p.ours->tree().setValueOff(ijk, x);
            p.theirs->tree().setValueOff(toOvdb(ijk), x);
        } else {
            p.ours->tree().setValueOn(ijk, x);
            p.theirs->tree().setValueOn(toOvdb(ijk), x);
        }
    }
    if (!tile)
        return p;
    p.ours->tree().fill(CoordBBox(Coord(32, 0, 0), Coord(39, 7, 7)), -1.5f, true);
    p.theirs->tree().fill(openvdb::CoordBBox(openvdb::Coord(32, 0, 0), openvdb::Coord(39, 7, 7)),
                          -1.5f, true);
    return p;
}

// Sample points: random, on voxel centres, on halves (ties of the point sampler), negative.
std::vector<Vec3d> samplePoints() {
    std::mt19937 rng(32);
    std::uniform_real_distribution<double> u(-35.0, 42.0);
    std::vector<Vec3d> points;
    for (int n = 0; n < 4000; ++n)
        points.push_back(Vec3d(u(rng), u(rng), u(rng)));
    for (int n = 0; n < 500; ++n) {
        const Vec3d p = points[size_t(n)];
        points.push_back(Vec3d(std::round(p[0]), std::round(p[1]), std::round(p[2])));
        points.push_back(Vec3d(std::floor(p[0]) + 0.5, std::floor(p[1]) + 0.5, p[2]));
    }
    return points;
}

template <typename OursT, typename TheirsT>
void expectSameSamples(double tolerance) {
    const FloatPair p = valuesPair();
    const tree::ValueAccessor<const FloatTree> acc(p.ours->tree());
    const auto theirAcc = p.theirs->getConstAccessor();
    for (const Vec3d& xyz : samplePoints()) {
        float a = 0.0f, b = 0.0f;
        const bool onA = OursT::sample(acc, xyz, a);
        const bool onB = TheirsT::sample(theirAcc, toOvdb(xyz), b);
        ASSERT_EQ(onA, onB) << xyz;
        const float c = OursT::sample(acc, xyz);
        const float d = TheirsT::sample(theirAcc, toOvdb(xyz));
        if (tolerance == 0.0) {
            ASSERT_EQ(a, b) << xyz;
            ASSERT_EQ(c, d) << xyz;
        } else {
            ASSERT_NEAR(a, b, tolerance) << xyz;
            ASSERT_NEAR(c, d, tolerance) << xyz;
        }
    }
}

TEST(SamplingCompat, PointSamplerIsBitIdentical) {
    expectSameSamples<tools::PointSampler, openvdb::tools::PointSampler>(0.0);
}

TEST(SamplingCompat, BoxSamplerIsBitIdentical) {
    expectSameSamples<tools::BoxSampler, openvdb::tools::BoxSampler>(0.0);
}

TEST(SamplingCompat, QuadraticSamplerMatches) {
    expectSameSamples<tools::QuadraticSampler, openvdb::tools::QuadraticSampler>(1e-6);
}

TEST(SamplingCompat, StaggeredSamplersAndGridSamplersMatch) {
    const auto field = [](const Vec3d& p) {
        return Vec3s(float(std::sin(0.5 * p[0])), float(p[1] * 0.1 - p[2] * 0.05),
                     float(std::cos(0.3 * p[2] + p[0] * 0.2)));
    };
    const Vec3SPair p =
        test::sampledPair<Vec3SPair>(CoordBBox(Coord(-8), Coord(8)), Vec3d(0.5, 0.25, 0.4),
                                     Vec3d(1, -2, 0.5), field, Vec3s(0.0f));
    const tree::ValueAccessor<const Vec3STree> acc(p.ours->tree());
    const auto theirAcc = p.theirs->getConstAccessor();
    std::mt19937 rng(33);
    std::uniform_real_distribution<double> u(-9.0, 9.0);
    const tools::GridSampler<Vec3SGrid, tools::BoxSampler> ws(*p.ours);
    const openvdb::tools::GridSampler<openvdb::Vec3SGrid, openvdb::tools::BoxSampler> theirWs(
        *p.theirs);
    for (int n = 0; n < 2000; ++n) {
        const Vec3d xyz(u(rng), u(rng), u(rng));
        Vec3s a;
        openvdb::Vec3s b;
        EXPECT_EQ(tools::StaggeredPointSampler::sample(acc, xyz, a),
                  openvdb::tools::StaggeredPointSampler::sample(theirAcc, toOvdb(xyz), b));
        ASSERT_EQ(a, fromOvdb(b)) << xyz;
        EXPECT_EQ(tools::StaggeredBoxSampler::sample(acc, xyz, a),
                  openvdb::tools::StaggeredBoxSampler::sample(theirAcc, toOvdb(xyz), b));
        ASSERT_EQ(a, fromOvdb(b)) << xyz;
        EXPECT_EQ(tools::StaggeredQuadraticSampler::sample(acc, xyz, a),
                  openvdb::tools::StaggeredQuadraticSampler::sample(theirAcc, toOvdb(xyz), b));
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(a[c], b[c], 1e-6) << xyz;
        // World space through each library's transform of the same map.
        const Vec3d world = xyz * 0.3;
        const Vec3s w = ws.wsSample(world);
        const openvdb::Vec3s tw = theirWs.wsSample(toOvdb(world));
        for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(w[c], tw[c], 1e-6) << world;
    }
}

// The same index-space map in both libraries.
openvdb::Mat4R toOvdb(const Mat4R& m) {
    openvdb::Mat4R r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            r(i, j) = m(i, j);
    return r;
}

template <typename OursT, typename TheirsT>
void expectSameTransformGrid(const FloatPair& p, const Mat4R& m, double tolerance) {
    auto ours = FloatGrid::create();
    auto theirs = openvdb::FloatGrid::create();
    tools::GridTransformer(m).transformGrid<OursT>(*p.ours, *ours);
    openvdb::tools::GridTransformer(toOvdb(m)).transformGrid<TheirsT>(*p.theirs, *theirs);
    EXPECT_TRUE(test::sameActiveValues(*ours, *theirs, tolerance));
    EXPECT_GT(ours->activeVoxelCount(), 0u);
}

// Without tiles: OpenVDB 10's resampler reads a tile's value directly for sample points
// within the tile grown (not shrunk: BBox::expand takes the absolute value) by the sampler's
// radius, so near an active tile its values are wrong by up to the tile's contrast with its
// surroundings. Resampling across tiles is checked against brute force in
// tests/tools/GridTransformerTest.cpp.
TEST(SamplingCompat, TransformGridGivesTheSameVoxels) {
    const FloatPair p = valuesPair(false);
    Mat4R rotated = Mat4R::scale(Vec3d(1.2, 0.9, 1.05));
    rotated.postRotate(math::Axis::Y, 0.35);
    rotated.postRotate(math::Axis::Z, -0.25);
    rotated.postTranslate(Vec3d(0.3, -0.6, 1.1));
    expectSameTransformGrid<tools::BoxSampler, openvdb::tools::BoxSampler>(p, rotated, 1e-4);
    expectSameTransformGrid<tools::QuadraticSampler, openvdb::tools::QuadraticSampler>(p, rotated,
                                                                                       1e-4);
    expectSameTransformGrid<tools::BoxSampler, openvdb::tools::BoxSampler>(
        p, Mat4R::scale(Vec3d(0.5)), 1e-4);
    expectSameTransformGrid<tools::BoxSampler, openvdb::tools::BoxSampler>(
        p, Mat4R::scale(Vec3d(2.0)), 1e-4);
}

TEST(SamplingCompat, ResampleToMatchGivesTheSameVoxels) {
    const FloatPair p = valuesPair(false);
    // No sample point on a lattice point (see TransformGridGivesTheSameVoxels).
    const Vec3d scale(0.7, 0.7, 0.7), translation(0.13, -0.41, 0.27);
    auto ours = FloatGrid::create();
    auto theirs = openvdb::FloatGrid::create();
    ours->setTransform(test::ourTransform(scale, translation));
    theirs->setTransform(test::ovdbTransform(scale, translation));
    tools::resampleToMatch<tools::BoxSampler>(*p.ours, *ours);
    openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*p.theirs, *theirs);
    EXPECT_TRUE(test::sameActiveValues(*ours, *theirs, 1e-4));
    EXPECT_EQ(ours->background(), theirs->background());
}

// The largest |value - analytic distance| / edge over the voxels within one voxel of the
// surface, where the edge is the smallest voxel edge; either library's grid.
template <typename GridT>
double nearSurfaceError(const GridT& grid, const Vec3d& center, double radius) {
    const auto vs = grid.voxelSize();
    const double edge = std::min({double(vs[0]), double(vs[1]), double(vs[2])});
    double worst = 0.0;
    for (auto it = grid.cbeginValueOn(); it; ++it) {
        const auto w = grid.transform().indexToWorld(it.getCoord());
        const double exact = (Vec3d(w[0], w[1], w[2]) - center).length() - radius;
        if (std::abs(exact) <= edge)
            worst = std::max(worst, std::abs(double(*it) - exact) / edge);
    }
    return worst;
}

TEST(SamplingCompat, ResampledLevelSetsAreAsCloseToTheDistanceAsOpenVdbs) {
    const Vec3f center(0.1f, -0.2f, 0.3f);
    const FloatPair p = test::spheres(1.0f, center, 0.05f);
    struct Target {
        const char* name;
        Mat4R matrix;
    };
    Mat4R rotated = Mat4R::scale(Vec3d(0.06, 0.08, 0.1));
    rotated.postRotate(math::Axis::X, 0.3);
    rotated.postRotate(math::Axis::Z, 0.7);
    for (const Target& t : {Target{"half resolution", Mat4R::scale(Vec3d(0.1))},
                            Target{"double resolution", Mat4R::scale(Vec3d(0.025))},
                            Target{"rotated, non-uniform", rotated}}) {
        auto ours = FloatGrid::create();
        auto theirs = openvdb::FloatGrid::create();
        ours->setTransform(math::Transform::createLinearTransform(t.matrix));
        theirs->setTransform(openvdb::math::Transform::createLinearTransform(toOvdb(t.matrix)));
        tools::resampleToMatch<tools::BoxSampler>(*p.ours, *ours);
        openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*p.theirs, *theirs);
        const double ourError = nearSurfaceError(*ours, Vec3d(center), 1.0);
        const double theirError = nearSurfaceError(*theirs, Vec3d(center), 1.0);
        EXPECT_LE(ourError, theirError + 0.05) << t.name;
        std::cout << t.name << ": near-surface error " << ourError << " voxel (OpenVDB "
                  << theirError << ")\n";
    }
}

// A level set resampled to a rotated transform with unequal scales, into an output that is a
// level set (its background sets the band) and into one that is not (the input's band width):
// both libraries rebuild it in the output's index space, so the active voxels agree to a few
// percent (the voxels at the band's edge, where the meshes' few hundredths of a voxel decide),
// the backgrounds are equal, and the values near the surface agree.
TEST(SamplingCompat, LevelSetResampledToANonUniformRotatedTransformMatchesOpenVdb) {
    const Vec3f center(0.3f, -0.7f, 0.4f);
    const FloatPair p = test::spheres(5.0f, center, 0.2f);
    Mat4R m = Mat4R::scale(Vec3d(0.4, 0.65, 0.55));
    m.postRotate(math::Axis::X, 0.5);
    m.postRotate(math::Axis::Z, 0.9);
    m.postTranslate(Vec3d(0.11, -0.07, 0.23));
    for (const bool levelSet : {true, false}) {
        auto ours = FloatGrid::create(levelSet ? 1.0f : 0.0f);
        auto theirs = openvdb::FloatGrid::create(levelSet ? 1.0f : 0.0f);
        if (levelSet) {
            ours->setGridClass(GRID_LEVEL_SET);
            theirs->setGridClass(openvdb::GRID_LEVEL_SET);
        }
        ours->setTransform(math::Transform::createLinearTransform(m));
        theirs->setTransform(openvdb::math::Transform::createLinearTransform(toOvdb(m)));
        tools::resampleToMatch<tools::BoxSampler>(*p.ours, *ours);
        openvdb::tools::resampleToMatch<openvdb::tools::BoxSampler>(*p.theirs, *theirs);
        SCOPED_TRACE(levelSet ? "level set output" : "plain output");
        EXPECT_EQ(ours->background(), theirs->background());
        const double a = double(ours->activeVoxelCount()), b = double(theirs->activeVoxelCount());
        EXPECT_GT(b, 5000.0);
        EXPECT_NEAR(a / b, 1.0, 0.03) << a << " active voxels, OpenVDB " << b;
        // Values within one voxel (of the first size) of the surface, in both grids.
        const double vs0 = ours->voxelSize()[0];
        const auto acc = ours->getConstAccessor();
        double worst = 0.0;
        Index64 compared = 0, missing = 0;
        for (auto it = theirs->cbeginValueOn(); it; ++it) {
            if (std::abs(*it) > vs0)
                continue;
            const Coord ijk = test::fromOvdb(it.getCoord());
            if (!acc.isValueOn(ijk)) {
                ++missing;
                continue;
            }
            worst = std::max(worst, std::abs(double(acc.getValue(ijk)) - double(*it)) / vs0);
            ++compared;
        }
        EXPECT_EQ(missing, 0u);
        EXPECT_GT(compared, 1000u);
        EXPECT_LT(worst, 0.05) << "voxel";
        std::cout << (levelSet ? "level set" : "plain") << " output: " << a << " active voxels ("
                  << "OpenVDB " << b << "), background " << ours->background() << ", largest "
                  << "difference near the surface " << worst << " voxel\n";
    }
}

}  // namespace
}  // namespace vdb
