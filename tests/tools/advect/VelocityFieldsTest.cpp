// SPDX-License-Identifier: Apache-2.0
// Oracles: the closed form of the Enright field and its properties (zero divergence by
// central differences in double precision, time reversal at half the period, zero normal
// velocity on the unit box), and exact trilinear reproduction of a linear velocity field by
// the sampled field in both the collocated and the staggered (MAC) interpretation.

#include <vdb/Grid.h>
#include <vdb/math/Transform.h>
#include <vdb/tools/VelocityFields.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace vdb {
namespace {

TEST(VelocityFields, EnrightFieldMatchesItsClosedForm) {
    tools::EnrightField<double> field;
    const double pi = std::numbers::pi;
    for (const Vec3d p : {Vec3d(0.35, 0.35, 0.35), Vec3d(0.1, 0.7, 0.45), Vec3d(0.9, 0.2, 0.6)}) {
        for (double t : {0.0, 0.7, 2.2}) {
            const double c = std::cos(pi * t / 3.0);
            const double sx = std::sin(pi * p[0]), sy = std::sin(pi * p[1]),
                         sz = std::sin(pi * p[2]);
            const Vec3d v = field(p, t);
            EXPECT_NEAR(v[0], 2 * sx * sx * std::sin(2 * pi * p[1]) * std::sin(2 * pi * p[2]) * c,
                        1e-12);
            EXPECT_NEAR(v[1], -std::sin(2 * pi * p[0]) * sy * sy * std::sin(2 * pi * p[2]) * c,
                        1e-12);
            EXPECT_NEAR(v[2], -std::sin(2 * pi * p[0]) * std::sin(2 * pi * p[1]) * sz * sz * c,
                        1e-12);
        }
    }
}

TEST(VelocityFields, EnrightFieldIsDivergenceFreeAndReversesAtHalfPeriod) {
    tools::EnrightField<double> field;
    const double h = 1e-5;
    for (const Vec3d p : {Vec3d(0.35, 0.35, 0.35), Vec3d(0.12, 0.81, 0.44), Vec3d(0.6, 0.3, 0.9)}) {
        double div = 0.0;
        for (size_t a = 0; a < 3; ++a) {
            Vec3d q = p, r = p;
            q[a] += h;
            r[a] -= h;
            div += (field(q, 0.0)[a] - field(r, 0.0)[a]) / (2 * h);
        }
        EXPECT_NEAR(div, 0.0, 1e-6) << p;
        const Vec3d before = field(p, 0.4), after = field(p, 3.0 - 0.4);
        for (size_t a = 0; a < 3; ++a)
            EXPECT_NEAR(before[a], -after[a], 1e-12);
        EXPECT_NEAR(field(p, 1.5).length(), 0.0, 1e-12);
    }
    // No flow through the faces of the unit box.
    EXPECT_NEAR(field(Vec3d(0.0, 0.3, 0.6), 0.0)[0], 0.0, 1e-12);
    EXPECT_NEAR(field(Vec3d(0.3, 1.0, 0.6), 0.0)[1], 0.0, 1e-12);
    EXPECT_NEAR(field(Vec3d(0.3, 0.6, 0.0), 0.0)[2], 0.0, 1e-12);
}

TEST(VelocityFields, ConstantFieldIsConstant) {
    tools::ConstantVelocityField<float> field(Vec3s(1.0f, -2.0f, 0.5f));
    EXPECT_EQ(field(Vec3d(3.0, 4.0, 5.0), 1.0), Vec3s(1.0f, -2.0f, 0.5f));
    EXPECT_EQ(field(Vec3d(-3.0, 0.0, 5.0), -7.0), Vec3s(1.0f, -2.0f, 0.5f));
}

// A linear velocity field V(p) = A p + b in world space.
Vec3d linearVelocity(const Vec3d& p) {
    return Vec3d(0.5 + 0.25 * p[0] - 0.5 * p[1] + 0.125 * p[2], -1.0 + 0.75 * p[1] + 0.5 * p[2],
                 0.25 - 0.5 * p[0] + 0.375 * p[2]);
}

TEST(VelocityFields, DiscreteFieldInterpolatesCollocatedVelocities) {
    const double h = 0.5;
    auto grid = Vec3SGrid::create(Vec3s(0.0f));
    grid->setTransform(math::Transform::createLinearTransform(h));
    auto acc = grid->getAccessor();
    for (int i = -6; i <= 6; ++i)
        for (int j = -6; j <= 6; ++j)
            for (int k = -6; k <= 6; ++k)
                acc.setValue(Coord(i, j, k), Vec3s(linearVelocity(Vec3d(i, j, k) * h)));
    tools::DiscreteField<Vec3SGrid> field(*grid);
    EXPECT_FALSE(field.isStaggered());
    auto sampler = field.sampler();
    for (const Vec3d p :
         {Vec3d(0.3, -1.1, 2.05), Vec3d(-2.2, 0.0, 0.9), Vec3d(1.75, 1.75, -1.75)}) {
        const Vec3s v = field(p, 0.0), w = sampler(p, 0.0);
        const Vec3d exact = linearVelocity(p);
        for (size_t a = 0; a < 3; ++a) {
            EXPECT_NEAR(v[a], exact[a], 1e-5) << p;
            EXPECT_EQ(v[a], w[a]);
        }
    }
}

TEST(VelocityFields, DiscreteFieldInterpolatesStaggeredVelocities) {
    // MAC layout: component a of voxel ijk is the velocity at ijk - 0.5 e_a (index space).
    const double h = 0.25;
    auto grid = Vec3SGrid::create(Vec3s(0.0f));
    grid->setTransform(math::Transform::createLinearTransform(h));
    grid->setGridClass(GRID_STAGGERED);
    auto acc = grid->getAccessor();
    for (int i = -8; i <= 8; ++i) {
        for (int j = -8; j <= 8; ++j) {
            for (int k = -8; k <= 8; ++k) {
                Vec3s v;
                for (size_t a = 0; a < 3; ++a) {
                    Vec3d face(i, j, k);
                    face[a] -= 0.5;
                    v[a] = float(linearVelocity(face * h)[a]);
                }
                acc.setValue(Coord(i, j, k), v);
            }
        }
    }
    tools::DiscreteField<Vec3SGrid> field(*grid);
    EXPECT_TRUE(field.isStaggered());
    for (const Vec3d p : {Vec3d(0.3, -1.1, 1.05), Vec3d(-1.2, 0.0, 0.9), Vec3d(0.6, 0.6, -0.6)}) {
        const Vec3s v = field(p, 0.0);
        const Vec3d exact = linearVelocity(p);
        for (size_t a = 0; a < 3; ++a)
            EXPECT_NEAR(v[a], exact[a], 1e-5) << p;
    }
    // Read as collocated, the same grid is off by half a voxel: the interpretations differ.
    tools::DiscreteField<Vec3SGrid> collocated(*grid, false);
    EXPECT_GT(std::abs(collocated(Vec3d(0.3, -1.1, 1.05), 0.0)[0] -
                       field(Vec3d(0.3, -1.1, 1.05), 0.0)[0]),
              1e-3);
}

}  // namespace
}  // namespace vdb
