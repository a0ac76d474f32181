// SPDX-License-Identifier: Apache-2.0
// Oracle: analytic derivatives of smooth functions. The one-sided schemes must converge at
// their design order on refinement (first order ~1, second ~2, third ~3, HJ-WENO5 ~5 where
// the function is smooth and monotone); Godunov's norm must pick the upwind sides.

#include <vdb/math/FiniteDifference.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace vdb::math {
namespace {

// A smooth function with no critical point near x0 = 0.4, and its derivative.
double f(double x) {
    return std::sin(x) + 0.5 * std::exp(0.5 * x);
}
double df(double x) {
    return std::cos(x) + 0.25 * std::exp(0.5 * x);
}

template <BiasedGradientScheme Scheme>
std::array<double, 2> errorsAt(double h) {
    const double x0 = 0.4;
    std::array<double, 7> line;
    for (int d = -3; d <= 3; ++d)
        line[size_t(d + 3)] = f(x0 + d * h);
    double dm, dp;
    biasedDifferences<Scheme>(line.data(), dm, dp);
    return {std::abs(dm / h - df(x0)), std::abs(dp / h - df(x0))};
}

// Observed order from errors at h, h/2, h/4 (the mean of the two ratios).
template <BiasedGradientScheme Scheme>
std::array<double, 2> observedOrder(double h) {
    const auto e1 = errorsAt<Scheme>(h), e2 = errorsAt<Scheme>(h / 2), e3 = errorsAt<Scheme>(h / 4);
    std::array<double, 2> order;
    for (size_t s = 0; s < 2; ++s)
        order[s] = 0.5 * (std::log2(e1[s] / e2[s]) + std::log2(e2[s] / e3[s]));
    return order;
}

template <BiasedGradientScheme Scheme>
void expectOrder(double expected, double tolerance) {
    const auto order = observedOrder<Scheme>(0.05);
    EXPECT_NEAR(order[0], expected, tolerance) << "D-";
    EXPECT_NEAR(order[1], expected, tolerance) << "D+";
}

TEST(FiniteDifference, OneSidedSchemesConvergeAtTheirOrder) {
    expectOrder<FIRST_BIAS>(1.0, 0.15);
    expectOrder<SECOND_BIAS>(2.0, 0.2);
    expectOrder<THIRD_BIAS>(3.0, 0.3);
}

TEST(FiniteDifference, HjWeno5ConvergesAtFifthOrderInSmoothRegions) {
    const auto order = observedOrder<HJWENO5_BIAS>(0.1);
    EXPECT_GT(order[0], 4.4);
    EXPECT_GT(order[1], 4.4);
    EXPECT_LT(order[0], 6.0);
    EXPECT_LT(order[1], 6.0);
    // And it is far more accurate than first order at the same spacing.
    EXPECT_LT(errorsAt<HJWENO5_BIAS>(0.05)[0], 1e-4 * errorsAt<FIRST_BIAS>(0.05)[0]);
}

TEST(FiniteDifference, HjWeno5ChoosesTheSmoothSideOfAKink) {
    // |x| sampled around x = 0.5 h to the right of the kink at 0: D+ sees only the linear
    // branch x (slope 1) and must be exact to round-off; first-order D+ is exact too.
    const double h = 0.1;
    std::array<double, 7> line;
    for (int d = -3; d <= 3; ++d)
        line[size_t(d + 3)] = std::abs((d + 1.5) * h);
    double dm, dp;
    biasedDifferences<HJWENO5_BIAS>(line.data(), dm, dp);
    EXPECT_NEAR(dp / h, 1.0, 1e-6);
    // D- straddles the kink; WENO weights the stencils away from it, so it stays in [-1, 1]
    // rather than overshooting as a fixed fifth-order stencil would.
    EXPECT_LE(dm / h, 1.0 + 1e-9);
    EXPECT_GE(dm / h, -1.0 - 1e-9);
}

TEST(FiniteDifference, LinearFunctionsAreExactForEveryScheme) {
    std::array<double, 7> line;
    for (int d = 0; d < 7; ++d)
        line[size_t(d)] = 3.0 - 2.5 * d;
    double dm, dp;
    biasedDifferences<FIRST_BIAS>(line.data(), dm, dp);
    EXPECT_DOUBLE_EQ(dm, -2.5);
    EXPECT_DOUBLE_EQ(dp, -2.5);
    biasedDifferences<SECOND_BIAS>(line.data(), dm, dp);
    EXPECT_DOUBLE_EQ(dm, -2.5);
    EXPECT_DOUBLE_EQ(dp, -2.5);
    biasedDifferences<THIRD_BIAS>(line.data(), dm, dp);
    EXPECT_NEAR(dm, -2.5, 1e-12);
    EXPECT_NEAR(dp, -2.5, 1e-12);
    biasedDifferences<HJWENO5_BIAS>(line.data(), dm, dp);
    EXPECT_NEAR(dm, -2.5, 1e-12);
    EXPECT_NEAR(dp, -2.5, 1e-12);
}

TEST(FiniteDifference, GodunovTakesTheUpwindSides) {
    // Outside (phi > 0) on the x axis of a distance field: D- = 1 flows outward and counts; a
    // D+ of 1 (positive, so not an inflow) does not add to it.
    EXPECT_DOUBLE_EQ(godunovNormSqrd(true, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0), 1.0);
    // At a local minimum of phi outside (D- < 0 < D+) nothing flows in: zero.
    EXPECT_DOUBLE_EQ(godunovNormSqrd(true, -0.5, 0.5, 0.0, 0.0, 0.0, 0.0), 0.0);
    // At a local maximum outside, both sides flow in: the larger square wins.
    EXPECT_DOUBLE_EQ(godunovNormSqrd(true, 0.5, -0.75, 0.0, 0.0, 0.0, 0.0), 0.5625);
    // Inside the roles swap: at a local minimum both count, at a maximum neither.
    EXPECT_DOUBLE_EQ(godunovNormSqrd(false, -0.5, 0.25, 0.0, 0.0, 0.0, 0.0), 0.25);
    EXPECT_DOUBLE_EQ(godunovNormSqrd(false, 0.5, -0.75, 0.0, 0.0, 0.0, 0.0), 0.0);
    // The axes add up.
    EXPECT_DOUBLE_EQ(godunovNormSqrd(true, 0.6, 0.6, 0.8, 0.8, 0.0, 0.0), 1.0);
}

TEST(FiniteDifference, UpwindFollowsTheVelocitySign) {
    EXPECT_EQ(upwind(1.0, 2.0, 3.0), 2.0);
    EXPECT_EQ(upwind(-1.0, 2.0, 3.0), 3.0);
    EXPECT_EQ(upwind(0.0, 2.0, 3.0), 3.0);
}

TEST(FiniteDifference, SchemeTablesMatchTheSchemes) {
    EXPECT_EQ(stencilRadius(FIRST_BIAS), 1);
    EXPECT_EQ(stencilRadius(HJWENO5_BIAS), 3);
    EXPECT_EQ(auxBufferCount(TVD_RK1), 1);
    EXPECT_EQ(auxBufferCount(TVD_RK2), 1);
    EXPECT_EQ(auxBufferCount(TVD_RK3), 2);
    EXPECT_FALSE(isSupported(WENO5_BIAS));
    EXPECT_FALSE(isSupported(UNKNOWN_TIS));
}

}  // namespace
}  // namespace vdb::math
