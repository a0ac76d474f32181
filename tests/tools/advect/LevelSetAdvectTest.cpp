// SPDX-License-Identifier: Apache-2.0
// Oracles: the analytic translation of a sphere in a constant velocity field (centre and
// radius measured by brute force over a dense box, and the values near the interface against
// the translated distance), time reversal, and bitwise equality of results computed with one
// thread, serially and with many threads.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetAdvect.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/VelocityFields.h>

#include "AdvectTestUtil.h"
#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <numbers>
#include <string>

namespace vdb {
namespace {

constexpr float kRadius = 0.3f;
constexpr float kVoxel = 0.02f;
const Vec3f kCenter(0.1f, -0.05f, 0.2f);
const Vec3f kVelocity(1.0f, 0.5f, -0.25f);

using ConstantAdvection = tools::LevelSetAdvection<FloatGrid, tools::ConstantVelocityField<float>>;

CoordBBox boxAround(const Vec3d& center, double radius) {
    const Int32 lo[3] = {Int32(std::floor((center[0] - radius) / kVoxel)),
                         Int32(std::floor((center[1] - radius) / kVoxel)),
                         Int32(std::floor((center[2] - radius) / kVoxel))};
    const Int32 n = Int32(std::ceil(2 * radius / kVoxel)) + 2;
    return CoordBBox(Coord(lo[0], lo[1], lo[2]), Coord(lo[0] + n, lo[1] + n, lo[2] + n));
}

struct TranslationCase {
    math::BiasedGradientScheme spatial;
    math::TemporalIntegrationScheme temporal;
    double centerTol;  // voxels
    double radiusTol;  // voxels
    double valueTol;   // voxels, at voxels within one voxel of the interface
};

TEST(LevelSetAdvection, ConstantVelocityTranslatesTheSphere) {
    const double time = 0.2;  // displacement (10, 5, -2.5) voxels
    for (const TranslationCase& c :
         {TranslationCase{math::HJWENO5_BIAS, math::TVD_RK3, 0.1, 0.1, 0.1},
          TranslationCase{math::HJWENO5_BIAS, math::TVD_RK2, 0.1, 0.1, 0.1},
          TranslationCase{math::FIRST_BIAS, math::TVD_RK1, 0.25, 0.5, 0.5}}) {
        SCOPED_TRACE(std::string(math::biasedGradientSchemeToString(c.spatial)) + ", " +
                     std::string(math::temporalIntegrationSchemeToString(c.temporal)));
        auto grid = tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, 3.0f);
        const Vec3d c0(kCenter);
        const auto m0 = test::insideMoments(*grid, boxAround(c0, kRadius + 0.1));

        tools::ConstantVelocityField<float> field(kVelocity);
        ConstantAdvection advection(*grid, field);
        advection.setSpatialScheme(c.spatial);
        advection.setTemporalScheme(c.temporal);
        const size_t steps = advection.advect(0.0, time);
        // CFL 0.5: dt = 0.5 dx / |V|.
        const double dt = 0.5 * kVoxel / double(Vec3d(kVelocity).length());
        EXPECT_EQ(steps, size_t(std::ceil(time / dt - 1e-9)));

        const Vec3d c1 = c0 + Vec3d(kVelocity) * time;
        const auto m1 = test::insideMoments(*grid, boxAround(c1, kRadius + 0.1));
        // The measured centre moved by the analytic displacement.
        const Vec3d moved = m1.centroid - m0.centroid;
        EXPECT_LT((moved - Vec3d(kVelocity) * time).length() / kVoxel, c.centerTol) << moved;
        // Radius preserved (measured the same way before and after).
        const double r0 = std::cbrt(3.0 * m0.volume / (4.0 * std::numbers::pi));
        const double r1 = std::cbrt(3.0 * m1.volume / (4.0 * std::numbers::pi));
        EXPECT_NEAR(r0, kRadius, 0.1 * kVoxel);
        EXPECT_NEAR(r1, r0, c.radiusTol * kVoxel);
        // Values near the interface match the translated distance.
        double worst = 0.0;
        int n = 0;
        for (auto it = grid->cbeginValueOn(); it; ++it) {
            const double d =
                test::sphereDistance(grid->indexToWorld(Vec3d(it.getCoord())), c1, kRadius);
            if (std::abs(d) < kVoxel) {
                worst = std::max(worst, std::abs(double(*it) - d) / kVoxel);
                ++n;
            }
        }
        EXPECT_GT(n, 1000);
        EXPECT_LT(worst, c.valueTol);
        // The band is rebuilt around the new position: nothing active beyond the half width.
        for (auto it = grid->cbeginValueOn(); it; ++it)
            ASSERT_LT(std::abs(*it), grid->background());
    }
}

TEST(LevelSetAdvection, BackwardAdvectionUndoesForward) {
    auto grid = tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, 3.0f);
    const auto m0 = test::insideMoments(*grid, boxAround(Vec3d(kCenter), kRadius + 0.15));
    tools::ConstantVelocityField<float> field(kVelocity);
    ConstantAdvection advection(*grid, field);
    advection.setTemporalScheme(math::TVD_RK3);
    const size_t forward = advection.advect(0.0, 0.05);
    const size_t backward = advection.advect(0.05, 0.0);
    EXPECT_EQ(forward, backward);
    const auto m1 = test::insideMoments(*grid, boxAround(Vec3d(kCenter), kRadius + 0.15));
    EXPECT_LT((m1.centroid - m0.centroid).length(), 0.05 * kVoxel);
}

TEST(LevelSetAdvection, ZeroVelocityAdvancesTimeAndChangesNothing) {
    auto grid = tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, 3.0f);
    auto copy = grid->deepCopy();
    tools::ConstantVelocityField<float> field(Vec3s(0.0f));
    ConstantAdvection advection(*grid, field);
    EXPECT_EQ(advection.advect(0.0, 1.0), 1u);
    EXPECT_EQ(advection.step(1.0, -0.5), 0.5);
    EXPECT_TRUE(test::bitIdenticalTrees(grid->tree(), copy->tree()));
}

/// A uniform velocity along x growing linearly from zero at t = 0 (time-dependent: it does
/// not declare TIME_DEPENDENT). From t = 0 to T a point moves by RATE T^2 / 2.
struct RampField {
    static constexpr float RATE = 2.0f;
    Vec3s operator()(const Vec3d&, double time) const { return Vec3s(RATE * float(time), 0, 0); }
};

TEST(LevelSetAdvection, FieldVanishingAtTheStartStillMovesTheSurface) {
    // The velocity is zero at the start of the interval: the steps must come from the speed
    // reached within them, not from a vanishing start speed (which allows any step).
    constexpr double kTime = 0.3;  // displacement RATE T^2 / 2 = 0.09, 4.5 voxels
    auto grid = tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, 3.0f);
    const Vec3d c0(kCenter);
    const auto m0 = test::insideMoments(*grid, boxAround(c0, kRadius + 0.1));
    RampField field;
    tools::LevelSetAdvection<FloatGrid, RampField> advection(*grid, field);
    advection.setTemporalScheme(math::TVD_RK3);
    const size_t steps = advection.advect(0.0, kTime);
    // Each step moves the surface by at most 0.5 dx: at least RATE T^2 / 2 / (0.5 dx) = 9.
    EXPECT_GE(steps, 9u);
    const Vec3d shift(0.5 * RampField::RATE * kTime * kTime, 0.0, 0.0);
    const auto m1 = test::insideMoments(*grid, boxAround(c0 + shift, kRadius + 0.1));
    // Velocity sampled at the middle of each step: exact for a linear ramp in time.
    EXPECT_LT((m1.centroid - m0.centroid - shift).length() / kVoxel, 0.1)
        << m1.centroid - m0.centroid;

    // Backwards from T to 0 (the ramp vanishes at the end): back where it started.
    advection.advect(kTime, 0.0);
    const auto m2 = test::insideMoments(*grid, boxAround(c0, kRadius + 0.1));
    EXPECT_LT((m2.centroid - m0.centroid).length() / kVoxel, 0.1) << m2.centroid - m0.centroid;
}

TEST(LevelSetAdvection, OneStepSpanningAZeroOfTheFieldIsShortened) {
    // Enright's field vanishes at t = 1.5 and reverses: a step from 1.5 asked to reach 4.5 (a
    // zero again) must still be limited by the speed in between.
    auto grid = tools::createEnrightSphere<FloatGrid>(32, 3.0f);
    tools::EnrightField<float> field;
    tools::LevelSetAdvection<FloatGrid, tools::EnrightField<float>> advection(*grid, field);
    const double dt = advection.step(1.5, 3.0);
    EXPECT_GT(dt, 0.0);
    // Band speeds stay below 2 (|u| <= 2, |v|, |w| <= 1 and not all at once), so a step
    // of 0.5 dx / 2 is always allowed; anything near the whole interval is not.
    EXPECT_GE(dt, 0.5 / 32 / 2.5);
    EXPECT_LT(dt, 0.1);
}

TEST(LevelSetAdvection, DiscreteFieldAdvectsLikeTheConstantField) {
    // A velocity grid holding the constant velocity everywhere near the sphere gives the same
    // trilinear samples, collocated or staggered, so the same result bit for bit.
    auto velocity = Vec3SGrid::create(Vec3s(0.0f));
    velocity->setTransform(math::Transform::createLinearTransform(kVoxel));
    velocity->tree().fill(CoordBBox(Coord(-40), Coord(40)), kVelocity, true);
    for (bool staggered : {false, true}) {
        auto a = tools::createLevelSetSphere<FloatGrid>(0.2f, Vec3f(0.0f), kVoxel, 3.0f);
        auto b = a->deepCopy();
        tools::DiscreteField<Vec3SGrid> sampled(*velocity, staggered);
        tools::LevelSetAdvection<FloatGrid, tools::DiscreteField<Vec3SGrid>> adv(*a, sampled);
        tools::ConstantVelocityField<float> constant(kVelocity);
        ConstantAdvection ref(*b, constant);
        EXPECT_EQ(adv.advect(0.0, 0.03), ref.advect(0.0, 0.03));
        EXPECT_TRUE(test::bitIdenticalTrees(a->tree(), b->tree()));
    }
}

TEST(LevelSetAdvection, ResultsDoNotDependOnTheThreadCount) {
    const auto run = [](bool threaded) {
        auto grid = tools::createEnrightSphere<FloatGrid>(64, 5.0f);
        tools::EnrightField<float> field;
        tools::LevelSetAdvection<FloatGrid, tools::EnrightField<float>> advection(*grid, field);
        advection.setTemporalScheme(math::TVD_RK3);
        advection.setThreaded(threaded);
        advection.advect(0.0, 0.05);
        return grid;
    };
    const auto serial = run(false);
    FloatGrid::Ptr one, many;
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
        one = run(true);
    }
    {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 8);
        tbb::task_arena arena(8);
        arena.execute([&] { many = run(true); });
    }
    EXPECT_GT(serial->activeVoxelCount(), 10000u);
    EXPECT_TRUE(test::bitIdenticalTrees(serial->tree(), one->tree()));
    EXPECT_TRUE(test::bitIdenticalTrees(serial->tree(), many->tree()));
}

TEST(LevelSetAdvection, WorksOnDoubleGrids) {
    auto grid = tools::createLevelSetSphere<DoubleGrid>(kRadius, kCenter, kVoxel, 3.0f);
    tools::ConstantVelocityField<double> field(Vec3d(0.0, 0.0, 1.0));
    tools::LevelSetAdvection<DoubleGrid, tools::ConstantVelocityField<double>> advection(*grid,
                                                                                         field);
    advection.setTemporalScheme(math::TVD_RK3);
    advection.advect(0.0, 0.1);  // 5 voxels along z
    const Vec3d c1 = Vec3d(kCenter) + Vec3d(0.0, 0.0, 0.1);
    const auto m = test::insideMoments(*grid, boxAround(c1, kRadius + 0.1));
    EXPECT_LT((m.centroid - c1).length(), 0.1 * kVoxel);
}

TEST(LevelSetAdvection, RejectsBadSettings) {
    auto grid = tools::createLevelSetSphere<FloatGrid>(kRadius, kCenter, kVoxel, 3.0f);
    tools::ConstantVelocityField<float> field(kVelocity);
    ConstantAdvection advection(*grid, field);
    EXPECT_THROW(advection.setCFL(1.5f), ValueError);
    EXPECT_THROW(advection.setSpatialScheme(math::UNKNOWN_BIAS), ValueError);
    EXPECT_THROW(advection.setTemporalScheme(math::UNKNOWN_TIS), ValueError);
    EXPECT_THROW(advection.setTrackerSpatialScheme(math::WENO5_BIAS), ValueError);
    EXPECT_EQ(advection.getSpatialScheme(), math::HJWENO5_BIAS);
    EXPECT_EQ(advection.getTemporalScheme(), math::TVD_RK2);
    EXPECT_EQ(advection.getTrackerSpatialScheme(), math::HJWENO5_BIAS);
    EXPECT_EQ(advection.getTrackerTemporalScheme(), math::TVD_RK1);
    EXPECT_EQ(advection.getNormCount(), 3);
    EXPECT_FLOAT_EQ(advection.getCFL(), 0.5f);
}

}  // namespace
}  // namespace vdb
