// SPDX-License-Identifier: Apache-2.0
// Oracles: the exact volume of the Enright sphere (4/3 pi 0.15^3) and of other shapes for the
// volume measure; the run's bookkeeping (sample times, counts, step totals) against the
// settings; and a short low-resolution Enright run whose volume stays within a loose bound.
// The full-period comparison with OpenVDB at 128^3 is in tests/compat (LevelSetAdvectCompatTest
// and LevelSetAdvectCompatSlowTest).

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetSphere.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace vdb {
namespace {

TEST(EnrightTest, LevelSetVolumeMeasuresSpheres) {
    for (int res : {64, 128}) {
        auto grid = tools::createEnrightSphere<FloatGrid>(res, 5.0f);
        const double exact = 4.0 / 3.0 * std::numbers::pi * std::pow(0.15, 3);
        // The smearing bias falls with the square of the voxel size over the radius.
        EXPECT_NEAR(tools::smearedHeavisideVolume(*grid), exact,
                    (res == 64 ? 0.015 : 0.005) * exact)
            << res;
    }
    // A sphere big enough for inside tiles above the leaves.
    auto big = tools::createLevelSetSphere<FloatGrid>(1.0f, Vec3f(0.0f), 0.01f, 3.0f);
    EXPECT_GT(big->tree().leafCount(), 0u);
    const double exact = 4.0 / 3.0 * std::numbers::pi;
    EXPECT_NEAR(tools::smearedHeavisideVolume(*big), exact, 1e-3 * exact);
    EXPECT_EQ(tools::smearedHeavisideVolume(*big, 1.5, false),
              tools::smearedHeavisideVolume(*big, 1.5, true));
}

TEST(EnrightTest, ShortRunReportsEveryFrame) {
    tools::EnrightTestOptions options;
    options.resolution = 32;
    options.endTime = 0.3;
    options.frames = 3;
    std::vector<tools::EnrightSample> samples;
    const auto result = tools::runEnrightTest<FloatGrid>(
        options, [&](const tools::EnrightSample& s, const FloatGrid& grid) {
            EXPECT_EQ(s.activeVoxels, grid.activeVoxelCount());
            samples.push_back(s);
        });
    ASSERT_EQ(samples.size(), 4u);
    for (int f = 0; f <= 3; ++f)
        EXPECT_NEAR(samples[size_t(f)].time, 0.1 * f, 1e-12);
    EXPECT_EQ(samples.front().steps, 0u);
    for (size_t f = 1; f < samples.size(); ++f)
        EXPECT_GT(samples[f].steps, samples[f - 1].steps);
    EXPECT_EQ(result.final.steps, samples.back().steps);
    EXPECT_EQ(result.initial.volume, samples.front().volume);
    // The field is divergence-free: over a tenth of the period the volume barely changes.
    EXPECT_LT(std::abs(result.volumeLoss()), 0.05);
}

TEST(EnrightTest, EveryFrameAdvancesEvenWhenTheFieldVanishesAtItsStart) {
    // Frames of 0.5 up to t = 2: the fourth starts at t = 1.5, where the field vanishes. Its
    // speed |c(t)| on [1.5, 2] mirrors that on [1, 1.5], so it needs as many steps as the
    // third frame, and cutting the run into frames must not change the result.
    tools::EnrightTestOptions options;
    options.resolution = 32;
    options.endTime = 2.0;
    options.frames = 4;
    std::vector<tools::EnrightSample> samples;
    const auto framed = tools::runEnrightTest<FloatGrid>(
        options, [&](const tools::EnrightSample& s, const FloatGrid&) { samples.push_back(s); });
    ASSERT_EQ(samples.size(), 5u);
    const double third = double(samples[3].steps - samples[2].steps);
    const double fourth = double(samples[4].steps - samples[3].steps);
    EXPECT_GT(third, 10.0);
    EXPECT_NEAR(fourth, third, 2.0);
    options.frames = 1;
    const auto whole = tools::runEnrightTest<FloatGrid>(options);
    EXPECT_NEAR(double(framed.final.steps), double(whole.final.steps), 4.0);
    EXPECT_NEAR(framed.final.volume, whole.final.volume, 0.01 * whole.initial.volume);
    EXPECT_NEAR(double(framed.final.activeVoxels), double(whole.final.activeVoxels),
                0.03 * double(whole.final.activeVoxels));
}

TEST(EnrightTest, RejectsBadOptions) {
    tools::EnrightTestOptions options;
    options.resolution = 4;
    EXPECT_THROW(tools::runEnrightTest<FloatGrid>(options), ValueError);
    options.resolution = 32;
    options.frames = 0;
    EXPECT_THROW(tools::runEnrightTest<FloatGrid>(options), ValueError);
}

}  // namespace
}  // namespace vdb
