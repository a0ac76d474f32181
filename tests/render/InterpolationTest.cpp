// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic fields written into the voxels; trilinear reconstruction is exact for fields
// linear in each coordinate, triquadratic for fields quadratic in each coordinate, and the
// nearest-voxel sampler returns the field at the rounded point.

#include <vdb/tools/Interpolation.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace vdb::tools {
namespace {

// Writes field(i, j, k) into every voxel of [lo, hi]^3.
template <typename TreeT, typename FieldT>
void writeField(TreeT& tree, int lo, int hi, const FieldT& field) {
    typename TreeT::Accessor acc(tree);
    for (int i = lo; i <= hi; ++i)
        for (int j = lo; j <= hi; ++j)
            for (int k = lo; k <= hi; ++k)
                acc.setValue(Coord(i, j, k), field(double(i), double(j), double(k)));
}

TEST(Interpolation, BoxSamplerIsExactForTrilinearFields) {
    // Linear in each coordinate, with the mixed terms trilinear interpolation reproduces.
    auto field = [](double x, double y, double z) {
        return 0.5 + 2.0 * x - 3.0 * y + 0.25 * z + 0.1 * x * y - 0.05 * y * z + 0.01 * x * y * z;
    };
    DoubleTree tree(0.0);
    writeField(tree, -12, 12, field);
    tree::ValueAccessor<const DoubleTree> acc(tree);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    for (int n = 0; n < test::scaledBatchCount(2000); ++n) {
        const Vec3d p(u(rng), u(rng), u(rng));
        ASSERT_NEAR(BoxSampler::sample(acc, p), field(p[0], p[1], p[2]), 1e-9) << p;
    }
    // Voxel centres give the voxel's value exactly.
    EXPECT_EQ(BoxSampler::sample(acc, Vec3d(3, -4, 5)), tree.getValue(Coord(3, -4, 5)));
}

TEST(Interpolation, BoxSamplerGradientOfALinearFieldIsItsSlope) {
    auto field = [](double x, double y, double z) { return 1.0 - 0.5 * x + 2.0 * y + 4.0 * z; };
    DoubleTree tree(0.0);
    writeField(tree, -6, 6, field);
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> u(-5.0, 5.0);
    for (int n = 0; n < 200; ++n) {
        const Vec3d g = BoxSampler::gradient(tree, Vec3d(u(rng), u(rng), u(rng)));
        EXPECT_TRUE(math::isApproxEqual(g, Vec3d(-0.5, 2.0, 4.0), 1e-9)) << g;
    }
}

TEST(Interpolation, QuadraticSamplerIsExactForTriquadraticFields) {
    auto field = [](double x, double y, double z) {
        return 1.0 + x - 2.0 * y + 0.5 * z + 0.3 * x * x - 0.2 * y * y + 0.1 * z * z +
               0.05 * x * y * z - 0.01 * x * x * y * z * z;
    };
    DoubleTree tree(0.0);
    writeField(tree, -10, 10, field);
    tree::ValueAccessor<const DoubleTree> acc(tree);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-8.0, 8.0);
    for (int n = 0; n < test::scaledBatchCount(2000); ++n) {
        const Vec3d p(u(rng), u(rng), u(rng));
        ASSERT_NEAR(QuadraticSampler::sample(acc, p), field(p[0], p[1], p[2]), 1e-8) << p;
    }
    // The box sampler is not exact here: the oracle can tell them apart.
    EXPECT_GT(std::abs(BoxSampler::sample(acc, Vec3d(0.5, 0.5, 0.5)) - field(0.5, 0.5, 0.5)), 1e-3);
}

TEST(Interpolation, PointSamplerReturnsTheNearestVoxel) {
    FloatTree tree(-1.0f);
    tree.setValue(Coord(2, -3, 0), 7.0f);
    tree.setValue(Coord(3, -3, 0), 8.0f);
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.4, -3.4, 0.2)), 7.0f);
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.5, -2.6, -0.4)), 8.0f);  // halves round up
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.0, -3.6, 0.0)), -1.0f);
}

TEST(Interpolation, VectorValuesInterpolateComponentwise) {
    Vec3DTree tree(Vec3d(0.0));
    writeField(tree, -3, 3,
               [](double x, double y, double z) { return Vec3d(x + y, 2.0 * z, x * y * z); });
    const Vec3d p(0.25, -1.5, 1.75);
    const Vec3d v = BoxSampler::sample(tree, p);
    EXPECT_TRUE(math::isApproxEqual(v, Vec3d(p[0] + p[1], 2.0 * p[2], p[0] * p[1] * p[2]), 1e-12))
        << v;
}

}  // namespace
}  // namespace vdb::tools
