// SPDX-License-Identifier: Apache-2.0
// Oracles: naive triple-loop products on plain arrays, the Leibniz permutation expansion of
// the determinant, inverse(M) * M = I, and the rotation matrix the .vdb format example shows.

#include <vdb/math/Mat4.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

namespace vdb::math {
namespace {

using Plain = std::array<std::array<double, 4>, 4>;

Plain toPlain(const Mat4d& m) {
    Plain p{};
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c)
            p[size_t(r)][size_t(c)] = m.data()[4 * r + c];
    }
    return p;
}

Mat4d randomMatrix(std::mt19937& rng, bool affine) {
    std::uniform_real_distribution<double> value(-2.0, 2.0);
    Mat4d m;
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c)
            m(r, c) = value(rng);
    }
    if (affine) {
        m(0, 3) = m(1, 3) = m(2, 3) = 0;
        m(3, 3) = 1;
    }
    return m;
}

// Leibniz formula: the sum over all 24 permutations of signed products.
double leibnizDeterminant(const Plain& a) {
    std::array<int, 4> perm{0, 1, 2, 3};
    double det = 0;
    do {
        int inversions = 0;
        for (int i = 0; i < 4; ++i) {
            for (int j = i + 1; j < 4; ++j)
                inversions += perm[size_t(i)] > perm[size_t(j)];
        }
        double term = (inversions % 2) ? -1.0 : 1.0;
        for (size_t r = 0; r < 4; ++r)
            term *= a[r][size_t(perm[r])];
        det += term;
    } while (std::next_permutation(perm.begin(), perm.end()));
    return det;
}

double maxAbsDifference(const Mat4d& a, const Mat4d& b) {
    double d = 0;
    for (int i = 0; i < 16; ++i)
        d = std::max(d, std::abs(a.data()[i] - b.data()[i]));
    return d;
}

TEST(Mat4, ElementsAreRowMajorLikeTheFileFormat) {
    double values[16];
    for (int i = 0; i < 16; ++i)
        values[i] = i;
    const Mat4d m = Mat4d::fromRowMajor(values);
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c) {
            EXPECT_EQ(m(r, c), 4 * r + c);
            EXPECT_EQ(m[r][c], 4 * r + c);
        }
    }
    EXPECT_EQ(m, Mat4d(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
    // The translation lives in elements 12, 13 and 14.
    Mat4d t = Mat4d::identity();
    t.setTranslation(Vec3d(7, 8, 9));
    EXPECT_EQ(t.data()[12], 7);
    EXPECT_EQ(t.data()[13], 8);
    EXPECT_EQ(t.data()[14], 9);
    EXPECT_EQ(t.getTranslation(), Vec3d(7, 8, 9));
    EXPECT_EQ(Mat4d(), Mat4d::zero());
    EXPECT_TRUE(Mat4d::identity().isIdentity());
    EXPECT_TRUE(t.isAffine());
    EXPECT_FALSE(m.isAffine());
}

TEST(Mat4, ProductMatchesTripleLoopOracle) {
    std::mt19937 rng(1);
    for (int n = 0; n < 200; ++n) {
        const Mat4d a = randomMatrix(rng, false), b = randomMatrix(rng, false);
        const Plain pa = toPlain(a), pb = toPlain(b);
        const Mat4d ab = a * b;
        for (size_t r = 0; r < 4; ++r) {
            for (size_t c = 0; c < 4; ++c) {
                double sum = 0;
                for (size_t k = 0; k < 4; ++k)
                    sum += pa[r][k] * pb[k][c];
                ASSERT_NEAR(ab(int(r), int(c)), sum, 1e-14);
            }
        }
        Mat4d c = a;
        c *= b;
        ASSERT_EQ(c, ab);
        ASSERT_EQ(a * Mat4d::identity(), a);
        ASSERT_EQ(Mat4d::identity() * a, a);
    }
}

TEST(Mat4, PointsAreRowVectorsAndProductsApplyLeftFactorFirst) {
    // [x y z 1] * M, written out by hand.
    const Mat4d m(1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 10, 0, -1, -2, -3, 1);
    const Vec3d p(1, -1, 2);
    EXPECT_EQ(m.transformPoint(p), Vec3d(1 - 4 + 14 - 1, 2 - 5 + 16 - 2, 3 - 6 + 20 - 3));
    EXPECT_EQ(m.transformDirection(p), Vec3d(1 - 4 + 14, 2 - 5 + 16, 3 - 6 + 20));

    std::mt19937 rng(2);
    std::uniform_real_distribution<double> value(-5.0, 5.0);
    for (int n = 0; n < 200; ++n) {
        const Mat4d a = randomMatrix(rng, true), b = randomMatrix(rng, true);
        const Vec3d q(value(rng), value(rng), value(rng));
        ASSERT_TRUE(
            isApproxEqual((a * b).transformPoint(q), b.transformPoint(a.transformPoint(q)), 1e-12));
        ASSERT_TRUE(isApproxEqual((a * b).transformDirection(q),
                                  b.transformDirection(a.transformDirection(q)), 1e-12));
    }
}

TEST(Mat4, DeterminantMatchesLeibnizExpansionAndIsMultiplicative) {
    EXPECT_EQ(Mat4d::identity().determinant(), 1.0);
    EXPECT_EQ(Mat4d::scale(Vec3d(2, 3, 4)).determinant(), 24.0);
    EXPECT_EQ(Mat4d(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16).determinant(), 0.0);

    std::mt19937 rng(3);
    for (int n = 0; n < 500; ++n) {
        const Mat4d a = randomMatrix(rng, false), b = randomMatrix(rng, false);
        ASSERT_NEAR(a.determinant(), leibnizDeterminant(toPlain(a)), 1e-12);
        ASSERT_NEAR((a * b).determinant(), a.determinant() * b.determinant(), 1e-10);
        ASSERT_NEAR(a.transpose().determinant(), a.determinant(), 1e-12);
        const Mat4d c = randomMatrix(rng, true);
        ASSERT_NEAR(c.determinant3(), c.determinant(), 1e-12);  // affine: det = det of 3x3
    }
}

TEST(Mat4, TransposeSwapsRowsAndColumns) {
    std::mt19937 rng(4);
    const Mat4d a = randomMatrix(rng, false);
    const Mat4d t = a.transpose();
    for (int r = 0; r < 4; ++r) {
        for (int c = 0; c < 4; ++c)
            EXPECT_EQ(t(c, r), a(r, c));
    }
    EXPECT_EQ(t.transpose(), a);
}

TEST(Mat4, InverseTimesMatrixIsIdentityForRandomMatrices) {
    std::mt19937 rng(5);
    for (bool affine : {false, true}) {
        for (int n = 0; n < 1000; ++n) {
            const Mat4d a = randomMatrix(rng, affine);
            if (std::abs(a.determinant()) < 1e-3)
                continue;  // keep the check well conditioned
            const Mat4d inv = a.inverse();
            ASSERT_LT(maxAbsDifference(inv * a, Mat4d::identity()), 1e-9) << a;
            ASSERT_LT(maxAbsDifference(a * inv, Mat4d::identity()), 1e-9) << a;
            ASSERT_EQ(inv.isAffine(), affine);
        }
    }
}

TEST(Mat4, AffineInverseStaysAccurateWhenTranslationDwarfsScale) {
    Mat4d m = Mat4d::scale(Vec3d(1e-6, 2e-6, 3e-6));
    m.preRotate(Axis::Z, 0.3);
    m.setTranslation(Vec3d(1e9, -2e9, 3e9));
    const Mat4d inv = m.inverse();
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> value(-1e3, 1e3);
    for (int n = 0; n < 100; ++n) {
        const Vec3d p(value(rng), value(rng), value(rng));
        // World coordinates near 1e9 carry about 1e-7 of rounding; in index units (1e-6 per
        // voxel) that is about 0.1.
        ASSERT_TRUE(isApproxEqual(inv.transformPoint(m.transformPoint(p)), p, 0.5)) << p;
    }
    EXPECT_TRUE(isApproxEqual(inv.transformPoint(Vec3d(1e9, -2e9, 3e9)), Vec3d(0.0), 1e-6));
}

TEST(Mat4, InverseOfSingularMatrixThrowsValueError) {
    // Exactly dependent rows, affine and general.
    const Mat4d dependent3(1, 2, 3, 0, 4, 5, 6, 0, 7, 8, 9, 0, 1, 1, 1, 1);
    EXPECT_THROW((void)dependent3.inverse(), ValueError);
    const Mat4d dependent4(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16);
    EXPECT_THROW((void)dependent4.inverse(), ValueError);
    EXPECT_THROW((void)Mat4d::zero().inverse(), ValueError);
    EXPECT_THROW((void)Mat4d::scale(Vec3d(1, 0, 1)).inverse(), ValueError);
    Mat4d nan = Mat4d::identity();
    nan(1, 1) = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW((void)nan.inverse(), ValueError);
    // Rows that are dependent in exact arithmetic but whose rounded determinant is not zero.
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> value(-1.0, 1.0);
    int nonzeroDeterminants = 0;
    for (int n = 0; n < 100; ++n) {
        Mat4d m = Mat4d::identity();
        for (int c = 0; c < 3; ++c) {
            m(0, c) = value(rng);
            m(1, c) = value(rng);
            m(2, c) = 0.1 * m(0, c) + 0.7 * m(1, c);
        }
        nonzeroDeterminants += m.determinant3() != 0;
        EXPECT_THROW((void)m.inverse(), ValueError) << m;
        m(0, 3) = 0.5;  // the same rows in a general (non-affine) matrix
        EXPECT_THROW((void)m.inverse(), ValueError) << m;
    }
    EXPECT_GT(nonzeroDeterminants, 10);
    // Tiny but well-conditioned scales are not singular.
    EXPECT_NO_THROW((void)Mat4d::scale(Vec3d(1e-12)).inverse());
    EXPECT_NO_THROW((void)Mat4s::scale(Vec3s(1e-6f)).inverse());
}

TEST(Mat4, RotationMatchesTheFileFormatExample) {
    // FORMAT.md: a Z rotation of 0.5 rad plus translation (1, 0, 0) is stored as the rows
    // [cos sin 0 0], [-sin cos 0 0], [0 0 1 0], [1 0 0 1].
    Mat4d m = Mat4d::rotation(Axis::Z, 0.5);
    m.postTranslate(Vec3d(1, 0, 0));
    const double c = std::cos(0.5), s = std::sin(0.5);
    EXPECT_EQ(m, Mat4d(c, s, 0, 0, -s, c, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1));
}

TEST(Mat4, RotationsTurnAxesCounterclockwiseAndAreOrthonormal) {
    const double half = std::numbers::pi / 2;
    EXPECT_TRUE(isApproxEqual(Mat4d::rotation(Axis::Z, half).transformPoint(Vec3d(1, 0, 0)),
                              Vec3d(0, 1, 0), 1e-15));
    EXPECT_TRUE(isApproxEqual(Mat4d::rotation(Axis::X, half).transformPoint(Vec3d(0, 1, 0)),
                              Vec3d(0, 0, 1), 1e-15));
    EXPECT_TRUE(isApproxEqual(Mat4d::rotation(Axis::Y, half).transformPoint(Vec3d(0, 0, 1)),
                              Vec3d(1, 0, 0), 1e-15));

    std::mt19937 rng(7);
    std::uniform_real_distribution<double> value(-3.0, 3.0);
    for (int n = 0; n < 100; ++n) {
        const Vec3d axis(value(rng), value(rng), value(rng));
        const double angle = value(rng);
        const Mat4d r = Mat4d::rotation(axis, angle);
        ASSERT_LT(maxAbsDifference(r * r.transpose(), Mat4d::identity()), 1e-14);
        ASSERT_NEAR(r.determinant(), 1.0, 1e-14);
        // The axis is fixed; a perpendicular vector turns by `angle` around it.
        ASSERT_TRUE(isApproxEqual(r.transformDirection(axis), axis, 1e-13));
        const Vec3d perp = axis.cross(Vec3d(1, 2, 3)).unit();
        const Vec3d turned = r.transformDirection(perp);
        ASSERT_NEAR(perp.dot(turned), std::cos(angle), 1e-13);
        ASSERT_NEAR(perp.cross(turned).dot(axis.unit()), std::sin(angle), 1e-13);
    }
    for (Axis a : {Axis::X, Axis::Y, Axis::Z}) {
        Vec3d axis(0.0);
        axis[size_t(a)] = 1;
        EXPECT_LT(maxAbsDifference(Mat4d::rotation(a, 0.7), Mat4d::rotation(axis, 0.7)), 1e-15);
    }
    EXPECT_THROW((void)Mat4d::rotation(Vec3d(0.0), 1.0), ValueError);
}

TEST(Mat4, PreOperationsActBeforeAndPostOperationsAfter) {
    const Mat4d base = Mat4d::scale(Vec3d(2, 3, 4));
    const Vec3d p(1, 1, 1), t(10, 20, 30);
    Mat4d pre = base, post = base;
    pre.preTranslate(t);
    post.postTranslate(t);
    EXPECT_EQ(pre.transformPoint(p), base.transformPoint(p + t));
    EXPECT_EQ(post.transformPoint(p), base.transformPoint(p) + t);
    pre = post = base;
    pre.preScale(Vec3d(2));
    post.postScale(Vec3d(-1, 1, 1));
    EXPECT_EQ(pre.transformPoint(p), base.transformPoint(p * 2.0));
    EXPECT_EQ(post.transformPoint(p), base.transformPoint(p) * Vec3d(-1, 1, 1));
}

TEST(Mat4, StreamsRowsInBrackets) {
    std::ostringstream os;
    os << Mat4d::identity();
    EXPECT_EQ(os.str(), "[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]");
    EXPECT_TRUE(isApproxEqual(Mat4d::identity(), Mat4d(Mat4s::identity()), 0.0));
}

}  // namespace
}  // namespace vdb::math
