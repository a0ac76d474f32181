// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic fields written into the voxels. The point sampler returns the field at the
// voxel nearest the sample point (halves away from zero), the box sampler reproduces any
// linear field and the quadratic sampler any quadratic field exactly, at arbitrary points, in
// index and in world space, across tiles; the background reads outside, inactive.

#include <vdb/tools/Interpolation.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <thread>
#include <vector>

namespace vdb::tools {
namespace {

// Writes field(i, j, k) into every voxel of [lo, hi]^3, active.
template <typename TreeT, typename FieldT>
void writeField(TreeT& tree, int lo, int hi, const FieldT& field) {
    typename TreeT::Accessor acc(tree);
    for (int i = lo; i <= hi; ++i)
        for (int j = lo; j <= hi; ++j)
            for (int k = lo; k <= hi; ++k)
                acc.setValue(Coord(i, j, k), field(Vec3d(i, j, k)));
}

// A random polynomial field of degree 1 (linear) or 2 (quadratic, with all mixed terms).
struct Polynomial {
    double c0;
    Vec3d c1, c2, cross;  // x^2 y^2 z^2 terms; xy yz zx terms
    int degree;
    Polynomial(std::mt19937& rng, int d) : degree(d) {
        std::uniform_real_distribution<double> u(-1.0, 1.0);
        c0 = u(rng);
        c1 = Vec3d(u(rng), u(rng), u(rng));
        c2 = d == 2 ? Vec3d(u(rng), u(rng), u(rng)) * 0.1 : Vec3d(0.0);
        cross = d == 2 ? Vec3d(u(rng), u(rng), u(rng)) * 0.1 : Vec3d(0.0);
    }
    double operator()(const Vec3d& p) const {
        return c0 + c1.dot(p) + c2[0] * p[0] * p[0] + c2[1] * p[1] * p[1] + c2[2] * p[2] * p[2] +
               cross[0] * p[0] * p[1] + cross[1] * p[1] * p[2] + cross[2] * p[2] * p[0];
    }
};

Vec3d randomPoint(std::mt19937& rng, double lo, double hi) {
    std::uniform_real_distribution<double> u(lo, hi);
    return Vec3d(u(rng), u(rng), u(rng));
}

TEST(Interpolation, PointSamplerIsExactAtVoxelCentresAndRoundsHalvesAwayFromZero) {
    std::mt19937 rng(101);
    const Polynomial field(rng, 2);
    DoubleTree tree(0.0);
    writeField(tree, -6, 6, field);
    for (int n = 0; n < 500; ++n) {
        const Vec3d p = randomPoint(rng, -5.4, 5.4);
        const Vec3d nearest(std::round(p[0]), std::round(p[1]), std::round(p[2]));
        double v = 0.0;
        EXPECT_TRUE(PointSampler::sample(tree, p, v));
        ASSERT_EQ(v, field(nearest)) << p;
        ASSERT_EQ(PointSampler::sample(tree, p), field(nearest)) << p;
    }
    // Ties: 2.5 reads voxel 3 and -2.5 voxel -3 (std::round), unlike floor(x + 0.5).
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.5, 0, 0)), field(Vec3d(3, 0, 0)));
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(-2.5, 0, 0)), field(Vec3d(-3, 0, 0)));
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(0, -0.5, 1.5)), field(Vec3d(0, -1, 2)));
}

TEST(Interpolation, BoxSamplerReproducesAnyLinearField) {
    std::mt19937 rng(102);
    for (int trial = 0; trial < 4; ++trial) {
        const Polynomial field(rng, 1);
        DoubleTree tree(0.0);
        writeField(tree, -9, 9, field);
        const tree::ValueAccessor<const DoubleTree> acc(tree);
        for (int n = 0; n < test::scaledBatchCount(1000); ++n) {
            const Vec3d p = randomPoint(rng, -8.0, 8.0);
            double v = 0.0;
            EXPECT_TRUE(BoxSampler::sample(acc, p, v));
            ASSERT_NEAR(v, field(p), 1e-12) << p;
            ASSERT_EQ(BoxSampler::sample(acc, p), v) << p;
        }
    }
}

TEST(Interpolation, QuadraticSamplerReproducesAnyQuadraticField) {
    std::mt19937 rng(103);
    for (int trial = 0; trial < 4; ++trial) {
        const Polynomial field(rng, 2);
        DoubleTree tree(0.0);
        writeField(tree, -9, 9, field);
        const tree::ValueAccessor<const DoubleTree> acc(tree);
        for (int n = 0; n < test::scaledBatchCount(1000); ++n) {
            const Vec3d p = randomPoint(rng, -7.9, 7.9);
            double v = 0.0;
            EXPECT_TRUE(QuadraticSampler::sample(acc, p, v));
            ASSERT_NEAR(v, field(p), 1e-11) << p;
            ASSERT_EQ(QuadraticSampler::sample(acc, p), v) << p;
        }
        // The box sampler is not exact on a quadratic field: the oracle tells them apart.
        EXPECT_GT(
            std::abs(BoxSampler::sample(acc, Vec3d(0.5, 0.5, 0.5)) - field(Vec3d(0.5, 0.5, 0.5))),
            1e-4);
    }
}

TEST(Interpolation, QuadraticStencilStartsOneBelowTheFloor) {
    // One voxel of 1 at x = 2 in a zero field: the parabola through floor - 1, floor and
    // floor + 1. At x = 1.5 (floor 1) the stencil is voxels 0, 1, 2, reading (0, 0, 1):
    // 0.5 t^2 + 0.5 t = 0.375 at t = 0.5; a stencil centred on the nearest voxel (2) would
    // read (0, 1, 0) at t = -0.5: 1 - t^2 = 0.75.
    DoubleTree tree(0.0);
    tree.setValue(Coord(2, 0, 0), 1.0);
    EXPECT_DOUBLE_EQ(QuadraticSampler::sample(tree, Vec3d(1.5, 0, 0)), 0.375);
    // At x = 2.25 (floor 2): (0, 1, 0) at t = 0.25, 1 - t^2.
    EXPECT_DOUBLE_EQ(QuadraticSampler::sample(tree, Vec3d(2.25, 0, 0)), 1.0 - 0.25 * 0.25);
}

TEST(Interpolation, TilesAreReadAsTheirValueAndBackgroundIsInactive) {
    // A linear field along x over voxels; a constant active tile next to it with the field's
    // value on its face; the background far away.
    FloatTree tree(-7.0f);
    const float tile = 4.0f;
    tree.fill(CoordBBox(Coord(8, 0, 0), Coord(15, 7, 7)), tile, true);  // one 8^3 tile
    EXPECT_EQ(tree.activeTileCount(), 1u);
    for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j)
            for (int k = 0; k < 8; ++k)
                tree.setValue(Coord(i, j, k), float(i) * 0.5f);
    // Inside the tile (all stencils in it): the tile's value, active.
    for (const Vec3d p : {Vec3d(10.3, 3.7, 2.2), Vec3d(13.9, 1.1, 5.5)}) {
        float v = 0.0f;
        EXPECT_TRUE(BoxSampler::sample(tree, p, v));
        EXPECT_EQ(v, tile);
        EXPECT_TRUE(QuadraticSampler::sample(tree, p, v));
        EXPECT_EQ(v, tile);
        EXPECT_TRUE(PointSampler::sample(tree, p, v));
        EXPECT_EQ(v, tile);
    }
    // Across the voxel-tile boundary: the linear blend of voxel 7 (3.5) and the tile (4).
    EXPECT_FLOAT_EQ(BoxSampler::sample(tree, Vec3d(7.25, 2.5, 3.5)), 3.5f + 0.25f * 0.5f);
    // Far outside: the background, inactive, for every sampler.
    float v = 0.0f;
    EXPECT_FALSE(PointSampler::sample(tree, Vec3d(100.2, -50.7, 3.3), v));
    EXPECT_EQ(v, -7.0f);
    EXPECT_FALSE(BoxSampler::sample(tree, Vec3d(100.2, -50.7, 3.3), v));
    EXPECT_EQ(v, -7.0f);
    EXPECT_FALSE(QuadraticSampler::sample(tree, Vec3d(100.2, -50.7, 3.3), v));
    EXPECT_EQ(v, -7.0f);
    // One active voxel in the stencil is enough to report the sample active.
    FloatTree single(0.0f);
    single.setValue(Coord(1, 1, 1), 2.0f);
    EXPECT_TRUE(BoxSampler::sample(single, Vec3d(0.9, 0.1, 0.2), v));
    EXPECT_FALSE(BoxSampler::sample(single, Vec3d(-0.1, 0.1, 0.2), v));
    // The quadratic stencil starts one voxel lower: x = 2.5 reads voxels 1 to 3.
    EXPECT_FALSE(BoxSampler::sample(single, Vec3d(2.5, 1.2, 1.3), v));
    EXPECT_TRUE(QuadraticSampler::sample(single, Vec3d(2.5, 1.2, 1.3), v));
    EXPECT_FALSE(PointSampler::sample(single, Vec3d(0.9, 0.1, 0.2), v));
}

TEST(Interpolation, GridSamplerReadsWorldSpaceThroughTheTransform) {
    std::mt19937 rng(104);
    const Polynomial field(rng, 1);
    // A rotated, non-uniformly scaled, translated transform.
    Mat4d m = Mat4d::scale(Vec3d(0.5, 0.25, 0.75));
    m.postRotate(math::Axis::Y, 0.4);
    m.postRotate(math::Axis::Z, -0.3);
    m.postTranslate(Vec3d(1.5, -2.0, 0.25));
    auto grid = FloatGrid::create(0.0f);
    grid->setTransform(math::Transform::createLinearTransform(m));
    // The field lives in index space; written per voxel.
    writeField(grid->tree(), -8, 8, [&](const Vec3d& p) { return float(field(p)); });

    const GridSampler<FloatGrid, BoxSampler> sampler(*grid);
    const tree::ValueAccessor<const FloatTree> acc(grid->tree());
    const GridSampler<tree::ValueAccessor<const FloatTree>, QuadraticSampler> accSampler(
        acc, grid->transform());
    for (int n = 0; n < 300; ++n) {
        const Vec3d ijk = randomPoint(rng, -7.0, 7.0);
        const Vec3d xyz = grid->transform().indexToWorld(ijk);
        ASSERT_NEAR(sampler.wsSample(xyz), field(ijk), 2e-5) << ijk;
        ASSERT_NEAR(sampler.isSample(ijk), field(ijk), 2e-5) << ijk;
        ASSERT_NEAR(accSampler.wsSample(xyz), field(ijk), 2e-5) << ijk;
    }
    EXPECT_EQ(sampler.isSample(Coord(3, -2, 1)), grid->tree().getValue(Coord(3, -2, 1)));
    EXPECT_EQ(&sampler.transform(), &grid->transform());
}

TEST(Interpolation, StaggeredSamplersReadEachComponentAtItsFace) {
    // Component c of voxel ijk holds the field's component c at the face ijk - e_c / 2.
    std::mt19937 rng(105);
    const Polynomial fx(rng, 2), fy(rng, 2), fz(rng, 2);
    const Polynomial* f[3] = {&fx, &fy, &fz};
    Vec3DTree tree(Vec3d(0.0));
    writeField(tree, -8, 8, [&](const Vec3d& p) {
        Vec3d v;
        for (int c = 0; c < 3; ++c) {
            Vec3d face = p;
            face[c] -= 0.5;
            v[c] = (*f[c])(face);
        }
        return v;
    });
    for (int n = 0; n < 300; ++n) {
        const Vec3d p = randomPoint(rng, -6.0, 6.0);
        Vec3d q, b;
        EXPECT_TRUE(StaggeredQuadraticSampler::sample(tree, p, q));
        EXPECT_TRUE(StaggeredBoxSampler::sample(tree, p, b));
        const Vec3d r = StaggeredQuadraticSampler::sample(tree, p);
        for (int c = 0; c < 3; ++c) {
            ASSERT_NEAR(q[c], (*f[c])(p), 1e-10) << p;
            ASSERT_EQ(r[c], q[c]);
        }
        // The box form is the trilinear blend of the same face values.
        Vec3d shifted = p;
        shifted[0] += 0.5;
        ASSERT_EQ(b[0], BoxSampler::sample(tree, shifted)[0]);
    }
    // Point: at a voxel centre, component c reads the voxel rounded from ijk + e_c / 2.
    const Vec3d s = StaggeredPointSampler::sample(tree, Vec3d(1, 2, 3));
    EXPECT_EQ(s[0], tree.getValue(Coord(2, 2, 3))[0]);
    EXPECT_EQ(s[1], tree.getValue(Coord(1, 3, 3))[1]);
    EXPECT_EQ(s[2], tree.getValue(Coord(1, 2, 4))[2]);
}

TEST(Interpolation, DualGridSamplerReadsTheSourceAtTheTargetsVoxelCentres) {
    std::mt19937 rng(106);
    const Polynomial field(rng, 1);
    auto source = DoubleGrid::create(0.0);
    source->setTransform(math::Transform::createLinearTransform(0.5));
    // A linear field of world position.
    writeField(source->tree(), -20, 20,
               [&](const Vec3d& p) { return field(source->transform().indexToWorld(p)); });
    auto target = math::Transform::createLinearTransform(0.3);
    target->postTranslate(Vec3d(0.05, -0.1, 0.2));
    const DualGridSampler<DoubleGrid, BoxSampler> dual(*source, *target);
    EXPECT_FALSE(dual.isAligned());
    for (int n = 0; n < 300; ++n) {
        const Coord ijk = floorToCoord(randomPoint(rng, -25.0, 25.0));
        ASSERT_NEAR(dual(ijk), field(target->indexToWorld(ijk)), 1e-12) << ijk;
    }
    const DualGridSampler<DoubleTree, QuadraticSampler> aligned(source->tree(), source->transform(),
                                                                source->transform());
    EXPECT_TRUE(aligned.isAligned());
    EXPECT_EQ(aligned(Coord(3, 4, -5)), source->tree().getValue(Coord(3, 4, -5)));
}

TEST(Interpolation, IntegerValuesInterpolateWithoutOverflow) {
    Int32Tree tree(0);
    tree.setValue(Coord(0, 0, 0), std::numeric_limits<Int32>::min());
    tree.setValue(Coord(0, 0, 1), std::numeric_limits<Int32>::max());
    const Int32 mid = BoxSampler::sample(tree, Vec3d(0, 0, 0.5));
    EXPECT_GE(mid, -1);
    EXPECT_LE(mid, 0);
    // Stencil (min, max, 0) along z at t = 0.5: the coefficient a = -min / 2 - max saturates
    // at min, b = -min / 2, and t (t a + b) + max = max.
    EXPECT_EQ(QuadraticSampler::sample(tree, Vec3d(0, 0, 1.5)), std::numeric_limits<Int32>::max());
}

TEST(Interpolation, BoxSamplerIsExactForTrilinearFields) {
    // Linear in each coordinate, with the mixed terms trilinear interpolation reproduces.
    auto field = [](const Vec3d& p) {
        const double x = p[0], y = p[1], z = p[2];
        return 0.5 + 2.0 * x - 3.0 * y + 0.25 * z + 0.1 * x * y - 0.05 * y * z + 0.01 * x * y * z;
    };
    DoubleTree tree(0.0);
    writeField(tree, -12, 12, field);
    tree::ValueAccessor<const DoubleTree> acc(tree);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-10.0, 10.0);
    for (int n = 0; n < test::scaledBatchCount(2000); ++n) {
        const Vec3d p(u(rng), u(rng), u(rng));
        ASSERT_NEAR(BoxSampler::sample(acc, p), field(p), 1e-9) << p;
    }
    // Voxel centres give the voxel's value exactly.
    EXPECT_EQ(BoxSampler::sample(acc, Vec3d(3, -4, 5)), tree.getValue(Coord(3, -4, 5)));
}

TEST(Interpolation, BoxSamplerGradientOfALinearFieldIsItsSlope) {
    auto field = [](const Vec3d& p) { return 1.0 - 0.5 * p[0] + 2.0 * p[1] + 4.0 * p[2]; };
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
    auto field = [](const Vec3d& p) {
        const double x = p[0], y = p[1], z = p[2];
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
        ASSERT_NEAR(QuadraticSampler::sample(acc, p), field(p), 1e-8) << p;
    }
    // The box sampler is not exact here: the oracle can tell them apart.
    EXPECT_GT(std::abs(BoxSampler::sample(acc, Vec3d(0.5, 0.5, 0.5)) - field(Vec3d(0.5))), 1e-3);
}

TEST(Interpolation, PointSamplerReturnsTheNearestVoxel) {
    FloatTree tree(-1.0f);
    tree.setValue(Coord(2, -3, 0), 7.0f);
    tree.setValue(Coord(3, -3, 0), 8.0f);
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.4, -3.4, 0.2)), 7.0f);
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.5, -2.6, -0.4)), 8.0f);  // 2.5 rounds to 3
    EXPECT_EQ(PointSampler::sample(tree, Vec3d(2.0, -3.6, 0.0)), -1.0f);
}

TEST(Interpolation, VectorValuesInterpolateComponentwise) {
    Vec3DTree tree(Vec3d(0.0));
    writeField(tree, -3, 3,
               [](const Vec3d& q) { return Vec3d(q[0] + q[1], 2.0 * q[2], q[0] * q[1] * q[2]); });
    const Vec3d p(0.25, -1.5, 1.75);
    const Vec3d v = BoxSampler::sample(tree, p);
    EXPECT_TRUE(math::isApproxEqual(v, Vec3d(p[0] + p[1], 2.0 * p[2], p[0] * p[1] * p[2]), 1e-12))
        << v;
}

TEST(Interpolation, WorldSamplerReproducesALinearWorldFieldInEveryCopyAndThread) {
    // A vector field linear in world space is linear in index space under an affine transform,
    // so the box sampler must reproduce it at any world point inside the written voxels.
    Mat4d m = Mat4d::scale(Vec3d(0.5, 0.25, 0.75));
    m.postRotate(math::Axis::X, 0.7);
    m.postTranslate(Vec3d(-1.0, 2.5, 0.5));
    const auto xform = math::Transform::createLinearTransform(m);
    const auto field = [](const Vec3d& w) {
        return Vec3d(0.5 * w[0] - w[1] + 2.0, 0.25 * w[2] + 1.0, w[0] + w[1] + w[2]);
    };
    auto grid = Vec3SGrid::create(Vec3s(0.0f));
    grid->setTransform(xform);
    writeField(grid->tree(), -8, 8,
               [&](const Vec3d& ijk) { return Vec3s(field(xform->indexToWorld(ijk))); });

    const WorldSampler<Vec3SGrid> sampler(*grid);
    EXPECT_EQ(&sampler.grid(), grid.get());
    const auto check = [&](const WorldSampler<Vec3SGrid>& s, unsigned seed) {
        std::mt19937 rng(seed);
        int wrong = 0;
        for (int n = 0; n < 2000; ++n) {
            const Vec3d xyz = xform->indexToWorld(randomPoint(rng, -7.0, 7.0));
            const Vec3d got(s(xyz)), want = field(xyz);
            wrong += !math::isApproxEqual(got, want, 1e-4);
        }
        return wrong;
    };
    EXPECT_EQ(check(sampler, 1), 0);
    // Copies, one per thread, each with an accessor of its own (one copied after use).
    std::vector<int> wrong(4, -1);
    std::vector<std::thread> threads;
    for (unsigned t = 0; t < wrong.size(); ++t)
        threads.emplace_back([&, t, copy = sampler] { wrong[t] = check(copy, 10 + t); });
    for (auto& t : threads)
        t.join();
    EXPECT_EQ(wrong, std::vector<int>(4, 0));
    // Outside the written voxels it reads the background.
    EXPECT_EQ(sampler(xform->indexToWorld(Vec3d(100.5, -40.0, 3.0))), Vec3s(0.0f));
}

TEST(Interpolation, WorldSamplerWithAPointSamplerReadsTheNearestVoxel) {
    auto grid = DoubleGrid::create(-1.0);
    grid->setTransform(math::Transform::createLinearTransform(0.3));
    grid->transform().postTranslate(Vec3d(0.1, -0.2, 0.05));
    writeField(grid->tree(), -4, 4, [](const Vec3d& p) { return p[0] + 10 * p[1] + 100 * p[2]; });
    const WorldSampler<DoubleGrid, PointSampler> sampler(*grid);
    const GridSampler<DoubleGrid, PointSampler> gridSampler(*grid);
    std::mt19937 rng(7);
    for (int n = 0; n < 500; ++n) {
        const Vec3d xyz = grid->transform().indexToWorld(randomPoint(rng, -3.4, 3.4));
        const Vec3d ijk = grid->transform().worldToIndex(xyz);
        const Coord nearest(int(std::lround(ijk[0])), int(std::lround(ijk[1])),
                            int(std::lround(ijk[2])));
        ASSERT_EQ(sampler(xyz), grid->tree().getValue(nearest)) << xyz;
        ASSERT_EQ(sampler(xyz), gridSampler.wsSample(xyz));
    }
}

}  // namespace
}  // namespace vdb::tools
