// SPDX-License-Identifier: Apache-2.0
// Oracles: per-component arithmetic on plain arrays, vector identities (Lagrange's identity,
// orthogonality of the cross product), and std::floor / std::min.

#include <vdb/math/Vec3.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <type_traits>

namespace vdb::math {
namespace {

static_assert(std::is_trivially_copyable_v<Vec3f> && std::is_standard_layout_v<Vec3f>);
static_assert(std::is_same_v<Vec3s, Vec3f> && std::is_same_v<Vec3I::ValueType, uint32_t>);
static_assert(Vec3i(1, 2, 3) + Vec3i(1) == Vec3i(2, 3, 4), "arithmetic is constexpr");
static_assert(Vec3i(1, 0, 0).cross(Vec3i(0, 1, 0)) == Vec3i(0, 0, 1));

TEST(Vec3, DefaultConstructedIsZeroAndAccessorsAgree) {
    EXPECT_EQ(Vec3d(), Vec3d(0, 0, 0));
    EXPECT_EQ(Vec3I(), Vec3I::zero());
    Vec3f v(1.5f, -2.f, 3.f);
    EXPECT_EQ(v.x(), 1.5f);
    EXPECT_EQ(v.y(), -2.f);
    EXPECT_EQ(v.z(), 3.f);
    v.y() = 7.f;
    v[2] = 8.f;
    EXPECT_EQ(v, Vec3f(1.5f, 7.f, 8.f));
    EXPECT_EQ(v.data()[1], 7.f);
    EXPECT_EQ(Vec3d::ones(), Vec3d(1.0));
}

TEST(Vec3, BytesArePackedComponentsInOrder) {
    const Vec3d v(1.0, -2.0, 0.5);
    const double expected[3] = {1.0, -2.0, 0.5};
    static_assert(sizeof(v) == sizeof(expected));
    EXPECT_EQ(std::memcmp(&v, expected, sizeof(v)), 0);

    Vec3I tri;
    const uint32_t indices[3] = {7, 8, 4000000000u};
    std::memcpy(&tri, indices, sizeof(tri));
    EXPECT_EQ(tri, Vec3I(7, 8, 4000000000u));

    Vec4I quad;
    const uint32_t corners[4] = {1, 2, 3, 4};
    std::memcpy(&quad, corners, sizeof(quad));
    EXPECT_EQ(quad, Vec4I(1, 2, 3, 4));
    EXPECT_EQ(quad.w(), 4u);
}

TEST(Vec3, ArithmeticMatchesPerComponentOracle) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> value(-100.0, 100.0);
    for (int n = 0; n < 1000; ++n) {
        const std::array<double, 3> a{value(rng), value(rng), value(rng)};
        std::array<double, 3> b{value(rng), value(rng), value(rng)};
        for (double& c : b) {
            if (c == 0)
                c = 1;
        }
        const double s = value(rng) + 200.0;  // never zero
        const Vec3d va(a[0], a[1], a[2]), vb(b[0], b[1], b[2]);
        for (size_t i = 0; i < 3; ++i) {
            ASSERT_EQ((va + vb)[i], a[i] + b[i]);
            ASSERT_EQ((va - vb)[i], a[i] - b[i]);
            ASSERT_EQ((va * vb)[i], a[i] * b[i]);
            ASSERT_EQ((va / vb)[i], a[i] / b[i]);
            ASSERT_EQ((va + s)[i], a[i] + s);
            ASSERT_EQ((va - s)[i], a[i] - s);
            ASSERT_EQ((va * s)[i], a[i] * s);
            ASSERT_EQ((s * va)[i], s * a[i]);
            ASSERT_EQ((va / s)[i], a[i] / s);
            ASSERT_EQ((s + va)[i], s + a[i]);
            ASSERT_EQ((s - va)[i], s - a[i]);
            ASSERT_EQ((s / vb)[i], s / b[i]);
            ASSERT_EQ((-va)[i], -a[i]);
        }
        Vec3d c = va;
        c += vb;
        ASSERT_EQ(c, va + vb);
        c = va;
        c -= vb;
        ASSERT_EQ(c, va - vb);
        c = va;
        c *= vb;
        ASSERT_EQ(c, va * vb);
        c = va;
        c /= vb;
        ASSERT_EQ(c, va / vb);
        c = va;
        c *= s;
        ASSERT_EQ(c, va * s);
        c = va;
        c /= s;
        ASSERT_EQ(c, va / s);
        ASSERT_EQ(va.sum(), a[0] + a[1] + a[2]);
        ASSERT_EQ(va.product(), a[0] * a[1] * a[2]);
    }
}

TEST(Vec3, DotAndCrossSatisfyLagrangeIdentityAndOrthogonality) {
    EXPECT_EQ(Vec3d(1, 0, 0).cross(Vec3d(0, 1, 0)), Vec3d(0, 0, 1));
    EXPECT_EQ(Vec3d(0, 1, 0).cross(Vec3d(0, 0, 1)), Vec3d(1, 0, 0));
    EXPECT_EQ(Vec3d(0, 0, 1).cross(Vec3d(1, 0, 0)), Vec3d(0, 1, 0));
    EXPECT_EQ(Vec3i(1, 2, 3).dot(Vec3i(-4, 5, 6)), -4 + 10 + 18);

    std::mt19937 rng(2);
    std::uniform_real_distribution<double> value(-10.0, 10.0);
    for (int n = 0; n < 1000; ++n) {
        const Vec3d a(value(rng), value(rng), value(rng)), b(value(rng), value(rng), value(rng));
        const Vec3d c = a.cross(b);
        const double scale = a.lengthSqr() * b.lengthSqr();
        ASSERT_NEAR(c.dot(a), 0.0, 1e-12 * scale);
        ASSERT_NEAR(c.dot(b), 0.0, 1e-12 * scale);
        ASSERT_NEAR(c.lengthSqr(), scale - a.dot(b) * a.dot(b), 1e-12 * scale);
        ASSERT_EQ(b.cross(a), -c);
        ASSERT_EQ(a.dot(b), b.dot(a));
    }
}

TEST(Vec3, NormalizeGivesUnitLengthAndRejectsZero) {
    Vec3d v(3, 4, 12);
    EXPECT_EQ(v.length(), 13.0);
    EXPECT_EQ(v.lengthSqr(), 169.0);
    EXPECT_TRUE(v.normalize());
    EXPECT_NEAR(v.length(), 1.0, 1e-15);
    EXPECT_TRUE(isApproxEqual(v, Vec3d(3, 4, 12) / 13.0, 1e-15));

    Vec3f zero;
    EXPECT_FALSE(zero.normalize());
    EXPECT_EQ(zero, Vec3f(0.f));
    EXPECT_THROW((void)zero.unit(), ValueError);
    EXPECT_EQ(zero.unitSafe(), Vec3f(0.f));
    EXPECT_NEAR(Vec3f(0, -2, 0).unit().y(), -1.f, 1e-7f);
    EXPECT_FALSE(Vec3d(1e-3, 0, 0).normalize(1e-2));  // shorter than eps counts as zero
}

TEST(Vec3, MinAndMaxComponentAreComponentwise) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<Int32> value(-50, 50);
    for (int n = 0; n < 500; ++n) {
        const Vec3i a(value(rng), value(rng), value(rng)), b(value(rng), value(rng), value(rng));
        const Vec3i lo = Vec3i::minComponent(a, b), hi = Vec3i::maxComponent(a, b);
        for (size_t i = 0; i < 3; ++i) {
            ASSERT_EQ(lo[i], std::min(a[i], b[i]));
            ASSERT_EQ(hi[i], std::max(a[i], b[i]));
        }
        ASSERT_EQ(a.minComponent(), std::min({a[0], a[1], a[2]}));
        ASSERT_EQ(a.maxComponent(), std::max({a[0], a[1], a[2]}));
    }
}

TEST(Vec3, ConvertsFromCoordAndOtherComponentTypesExactly) {
    const Int32 big = std::numeric_limits<Int32>::max(), small = std::numeric_limits<Int32>::min();
    EXPECT_EQ(Vec3d(Coord(big, small, -1)), Vec3d(2147483647.0, -2147483648.0, -1.0));
    EXPECT_EQ(Vec3i(Coord(big, small, 0)), Vec3i(big, small, 0));
    EXPECT_EQ(Vec3f(Vec3d(0.5, -1.25, 3.0)), Vec3f(0.5f, -1.25f, 3.f));
    EXPECT_EQ(Vec3i(Vec3d(1.9, -1.9, 0.0)), Vec3i(1, -1, 0));  // static_cast truncates
}

TEST(Vec3, FloorAndRoundToCoordHandleNegativesHalvesAndOverflow) {
    EXPECT_EQ(floorToCoord(Vec3d(-0.5, 0.5, -1.0)), Coord(-1, 0, -1));
    EXPECT_EQ(roundToCoord(Vec3d(-0.5, 0.5, -0.51)), Coord(0, 1, -1));  // halves round up
    EXPECT_EQ(roundToCoord(Vec3d(2.5, -2.5, 2.49)), Coord(3, -2, 2));
    constexpr Int32 kMax = std::numeric_limits<Int32>::max();
    constexpr Int32 kMin = std::numeric_limits<Int32>::min();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(floorToCoord(Vec3d(1e20, -1e20, nan)), Coord(kMax, kMin, 0));
    EXPECT_EQ(floorToCoord(Vec3d(2147483647.9, -2147483648.0, -2147483648.5)),
              Coord(kMax, kMin, kMin));
    // volatile: evaluated at run time, where an unchecked cast of 2^31 would overflow.
    volatile double twoTo31 = 2147483648.0;
    EXPECT_EQ(floorToCoord(Vec3d(twoTo31, twoTo31 - 1, -twoTo31 - 1)), Coord(kMax, kMax, kMin));
    volatile float twoTo31f = 2147483648.f;
    EXPECT_EQ(floorToCoord(Vec3f(twoTo31f, -twoTo31f, 1e30f)), Coord(kMax, kMin, kMax));
    EXPECT_EQ(floorToCoord(Vec3i(-3, 4, 5)), Coord(-3, 4, 5));

    std::mt19937 rng(4);
    std::uniform_real_distribution<double> value(-1e6, 1e6);
    for (int n = 0; n < 1000; ++n) {
        const Vec3d v(value(rng), value(rng), value(rng));
        const Coord f = floorToCoord(v), r = roundToCoord(v);
        for (size_t i = 0; i < 3; ++i) {
            ASSERT_EQ(f[i], Int32(std::floor(v[i])));
            ASSERT_EQ(r[i], Int32(std::floor(v[i] + 0.5)));
        }
    }
}

TEST(Vec3, ApproxEqualUsesAbsoluteTolerancePerComponent) {
    EXPECT_TRUE(isApproxEqual(Vec3d(1, 2, 3), Vec3d(1 + 1e-10, 2, 3 - 1e-10), 1e-9));
    EXPECT_FALSE(isApproxEqual(Vec3d(1, 2, 3), Vec3d(1, 2, 3 + 1e-8), 1e-9));
    EXPECT_TRUE(isApproxEqual(Vec3d(1, 2, 3), Vec3d(1.5, 2, 3), Vec3d(0.5, 0, 0)));
    EXPECT_FALSE(isApproxEqual(Vec3d(1, 2, 3), Vec3d(1.5, 2, 3), Vec3d(0.4, 1, 1)));
    EXPECT_TRUE(isApproxEqual(Vec3i(1, 2, 3), Vec3i(1, 2, 3)));
    EXPECT_EQ(Abs(Vec3d(-1, 2, -0.5)), Vec3d(1, 2, 0.5));
}

TEST(Vec3, StreamsAsBracketedComponents) {
    std::ostringstream os;
    os << Vec3d(1.5, -2, 0) << ' ' << Vec3<uint8_t>(65, 0, 255) << ' ' << Vec4I(1, 2, 3, 4);
    EXPECT_EQ(os.str(), "[1.5, -2, 0] [65, 0, 255] [1, 2, 3, 4]");
}

}  // namespace
}  // namespace vdb::math
