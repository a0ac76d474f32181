// SPDX-License-Identifier: Apache-2.0
// Oracle: analytic fields sampled into grids (double precision): gradients, laplacians and
// mean curvature of a sphere's signed distance and of smooth functions, exact trilinear
// interpolation of linear fields, and convergence order of the WENO5 stencil on refinement.

#include <vdb/Grid.h>
#include <vdb/math/Stencils.h>
#include <vdb/math/Transform.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace vdb::math {
namespace {

using Field = std::function<double(double, double, double)>;

/// A DoubleGrid of voxel size `h` holding `f` at every voxel of the cube [-n, n]^3 (active).
DoubleGrid::Ptr sampleGrid(const Field& f, double h, int n, const Vec3d& offset = Vec3d(0.0)) {
    auto grid = DoubleGrid::create(0.0);
    grid->setTransform(Transform::createLinearTransform(h));
    auto acc = grid->getAccessor();
    for (int i = -n; i <= n; ++i)
        for (int j = -n; j <= n; ++j)
            for (int k = -n; k <= n; ++k)
                acc.setValue(Coord(i, j, k),
                             f(offset[0] + i * h, offset[1] + j * h, offset[2] + k * h));
    return grid;
}

double sphereSdf(double x, double y, double z) {
    const double cx = x - 0.031, cy = y + 0.017, cz = z - 0.009;
    return std::sqrt(cx * cx + cy * cy + cz * cz) - 0.5;
}

TEST(Stencils, SevenPointGradientAndLaplacianOfAQuadratic) {
    // Central differences are exact on quadratics.
    const Field f = [](double x, double y, double z) {
        return 1.0 + 2.0 * x - 3.0 * y + 0.5 * z + x * x + 2.0 * y * y - z * z + x * y;
    };
    const double h = 0.125;
    auto grid = sampleGrid(f, h, 3);
    SevenPointStencil<DoubleGrid> s(*grid);
    s.moveTo(Coord(1, -1, 2));
    const double x = h, y = -h, z = 2 * h;
    const Vec3d g = s.gradient();
    EXPECT_NEAR(g[0], 2.0 + 2.0 * x + y, 1e-12);
    EXPECT_NEAR(g[1], -3.0 + 4.0 * y + x, 1e-12);
    EXPECT_NEAR(g[2], 0.5 - 2.0 * z, 1e-12);
    EXPECT_NEAR(s.laplacian(), 2.0 + 4.0 - 2.0, 1e-10);
    EXPECT_NEAR(s.normal().length(), 1.0, 1e-12);
}

TEST(Stencils, SequentialMoveReadsTheCentreFromTheIterator) {
    auto grid = sampleGrid(sphereSdf, 0.1, 4);
    SevenPointStencil<DoubleGrid> a(*grid), b(*grid);
    for (auto it = grid->cbeginValueOn(); it; ++it) {
        a.moveTo(it);
        b.moveTo(it.getCoord());
        ASSERT_EQ(a.getValue(), b.getValue());
        ASSERT_EQ(a.getValue(1, 0, 0), b.getValue(1, 0, 0));
        ASSERT_EQ(a.getValue(0, 0, -1), b.getValue(0, 0, -1));
    }
}

TEST(Stencils, ZeroCrossingFindsTheInterfaceVoxels) {
    const double h = 0.1;
    auto grid = sampleGrid(sphereSdf, h, 8);
    SevenPointStencil<DoubleGrid> s(*grid);
    int crossings = 0;
    for (int i = -6; i <= 6; ++i) {
        s.moveTo(Coord(i, 0, 0));
        const bool expected = (sphereSdf((i - 1) * h, 0, 0) < 0) != (sphereSdf(i * h, 0, 0) < 0) ||
                              (sphereSdf((i + 1) * h, 0, 0) < 0) != (sphereSdf(i * h, 0, 0) < 0) ||
                              (sphereSdf(i * h, h, 0) < 0) != (sphereSdf(i * h, 0, 0) < 0) ||
                              (sphereSdf(i * h, -h, 0) < 0) != (sphereSdf(i * h, 0, 0) < 0) ||
                              (sphereSdf(i * h, 0, h) < 0) != (sphereSdf(i * h, 0, 0) < 0) ||
                              (sphereSdf(i * h, 0, -h) < 0) != (sphereSdf(i * h, 0, 0) < 0);
        EXPECT_EQ(s.zeroCrossing(), expected) << i;
        crossings += expected;
    }
    EXPECT_EQ(crossings, 4);
}

TEST(Stencils, WenoGradientOfASmoothFieldConvergesAtFifthOrder) {
    const Field f = [](double x, double y, double z) {
        return std::sin(x + 0.4) + 0.5 * std::exp(0.5 * y) + std::cos(0.7 * z + 0.3);
    };
    const Vec3d exact(std::cos(0.4), 0.25, -0.7 * std::sin(0.3));
    double errors[3][2];
    for (int r = 0; r < 3; ++r) {
        const double h = 0.1 / (1 << r);
        auto grid = sampleGrid(f, h, 4);
        WenoStencil<DoubleGrid> s(*grid);
        s.moveTo(Coord(0));
        const Vec3d gm = s.gradient(Vec3d(1.0)), gp = s.gradient(Vec3d(-1.0));
        errors[r][0] = (gm - exact).length();
        errors[r][1] = (gp - exact).length();
    }
    for (int side = 0; side < 2; ++side) {
        const double order = 0.5 * (std::log2(errors[0][side] / errors[1][side]) +
                                    std::log2(errors[1][side] / errors[2][side]));
        EXPECT_GT(order, 4.4) << "side " << side;
        EXPECT_LT(order, 6.0) << "side " << side;
    }
}

TEST(Stencils, FirstOrderGradientConvergesAtFirstOrder) {
    const Field f = [](double x, double y, double z) {
        return std::sin(x + 0.4) + 0.5 * std::exp(0.5 * y) + std::cos(0.7 * z + 0.3);
    };
    const Vec3d exact(std::cos(0.4), 0.25, -0.7 * std::sin(0.3));
    double errors[3];
    for (int r = 0; r < 3; ++r) {
        const double h = 0.05 / (1 << r);
        auto grid = sampleGrid(f, h, 4);
        WenoStencil<DoubleGrid> s(*grid);
        s.moveTo(Coord(0));
        errors[r] = (s.gradient<FIRST_BIAS>(Vec3d(1.0)) - exact).length();
    }
    const double order =
        0.5 * (std::log2(errors[0] / errors[1]) + std::log2(errors[1] / errors[2]));
    EXPECT_NEAR(order, 1.0, 0.15);
}

TEST(Stencils, GodunovNormOfADistanceFieldIsOne) {
    const double h = 0.05;
    auto grid = sampleGrid(sphereSdf, h, 14);
    WenoStencil<DoubleGrid> s(*grid);
    for (int i = -10; i <= 10; i += 2) {
        for (int j = -10; j <= 10; j += 5) {
            s.moveTo(Coord(i, j, 3));
            // Where the level sets are curved no more than 1 / (6 h), i.e. 0.3 from the centre.
            if (std::abs(sphereSdf(i * h, j * h, 3 * h)) > 0.2)
                continue;
            EXPECT_NEAR(s.normSqGrad(), 1.0, 2e-3) << Coord(i, j, 3);
            EXPECT_NEAR(s.normSqGrad<FIRST_BIAS>(), 1.0, 0.2) << Coord(i, j, 3);
        }
    }
}

TEST(Stencils, LaplacianAndMeanCurvatureOfASphereDistance) {
    // For the distance to a sphere, at distance r from its centre: laplacian 2 / r, and the
    // level set through the point is a sphere of radius r, mean curvature 1 / r.
    const double h = 0.02;
    auto grid = sampleGrid(sphereSdf, h, 30);
    CurvatureStencil<DoubleGrid> c(*grid);
    WenoStencil<DoubleGrid> w(*grid);
    for (const Coord ijk :
         {Coord(25, 0, 0), Coord(0, -20, 5), Coord(12, 12, 12), Coord(-17, 8, -3)}) {
        const double x = ijk[0] * h - 0.031, y = ijk[1] * h + 0.017, z = ijk[2] * h - 0.009;
        const double r = std::sqrt(x * x + y * y + z * z);
        c.moveTo(ijk);
        w.moveTo(ijk);
        EXPECT_NEAR(c.meanCurvature(), 1.0 / r, 0.01 / r) << ijk;
        EXPECT_NEAR(c.laplacian(), 2.0 / r, 0.01 / r) << ijk;
        EXPECT_NEAR(w.laplacian(), 2.0 / r, 0.001 / r) << ijk;
        const Vec3d g = c.gradient();
        EXPECT_NEAR(g[0], x / r, 1e-3) << ijk;
        EXPECT_NEAR(g[1], y / r, 1e-3) << ijk;
        EXPECT_NEAR(g[2], z / r, 1e-3) << ijk;
    }
}

TEST(Stencils, BoxStencilInterpolatesLinearFieldsExactly) {
    const Field f = [](double x, double y, double z) {
        return 0.25 + 1.5 * x - 2.0 * y + 0.75 * z;
    };
    auto grid = sampleGrid(f, 1.0, 4);
    BoxStencil<DoubleGrid> box(*grid);
    for (const Vec3d p : {Vec3d(0.25, 0.5, 0.75), Vec3d(-1.3, 2.9, -0.01), Vec3d(3.0, -3.0, 0.0),
                          Vec3d(-2.5, -2.5, 2.5)}) {
        EXPECT_NEAR(box.interpolation(p), f(p[0], p[1], p[2]), 1e-12) << p;
    }
    // A bilinear term is reproduced too (trilinear interpolation is exact on xyz products).
    const Field g = [](double x, double y, double z) { return x * y * z + x * y; };
    auto grid2 = sampleGrid(g, 1.0, 4);
    BoxStencil<DoubleGrid> box2(*grid2);
    EXPECT_NEAR(box2.interpolation(Vec3d(0.3, -1.6, 2.2)), g(0.3, -1.6, 2.2), 1e-12);
}

TEST(Stencils, BoxStencilInterpolatesVectorGrids) {
    auto grid = Vec3SGrid::create(Vec3s(0.0f));
    auto acc = grid->getAccessor();
    for (int i = 0; i <= 1; ++i)
        for (int j = 0; j <= 1; ++j)
            for (int k = 0; k <= 1; ++k)
                acc.setValue(Coord(i, j, k), Vec3s(float(i), float(j), float(k)) * 2.0f);
    BoxStencil<Vec3SGrid> box(*grid);
    const Vec3s v = box.interpolation(Vec3d(0.25, 0.5, 0.75));
    EXPECT_NEAR(v[0], 0.5f, 1e-6f);
    EXPECT_NEAR(v[1], 1.0f, 1e-6f);
    EXPECT_NEAR(v[2], 1.5f, 1e-6f);
}

}  // namespace
}  // namespace vdb::math
