// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10's tools/LevelSetMeasure.h, math/Stats.h, tools/Count.h and
// tools/ChangeBackground.h. The same level sets go through both libraries' measures (area,
// volume, curvatures, Euler characteristic, genus; relative difference at most 1e-4), value
// statistics and histograms, min/max, and background changes (identical values everywhere).
// OpenVDB's tools::statistics() does not compile against oneTBB 2021 (its iterator range is
// no TBB range), so the statistics are OpenVDB's math::Stats, Extrema and Histogram fed by
// OpenVDB's value iterators, each tile weighted by its voxel count as tools::statistics()
// does.

#include <vdb/Grid.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Count.h>
#include <vdb/tools/LevelSetMeasure.h>
#include <vdb/tools/Statistics.h>

#include "ToolboxCompat.h"
#include <gtest/gtest.h>
#include <openvdb/math/Stats.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/ChangeBackground.h>
#include <openvdb/tools/Count.h>
#include <openvdb/tools/LevelSetMeasure.h>

#include <cmath>
#include <utility>
#include <vector>

namespace vdb {
namespace {

void expectRelNear(double ours, double theirs, double rel, const char* what) {
    EXPECT_NEAR(ours, theirs, rel * std::max(1.0, std::abs(theirs))) << what;
}

TEST(MeasureCompat, SphereMeasuresMatchOpenVdb) {
    for (const float dx : {0.05f, 0.02f}) {
        auto p = test::spheres(0.9f, Vec3f(0.13f, -0.21f, 0.05f), dx);
        tools::LevelSetMeasure<FloatGrid> ours(*p.ours);
        openvdb::tools::LevelSetMeasure<openvdb::FloatGrid> theirs(*p.theirs);
        expectRelNear(ours.area(), theirs.area(), 1e-4, "area");
        expectRelNear(ours.volume(), theirs.volume(), 1e-4, "volume");
        expectRelNear(ours.area(false), theirs.area(false), 1e-4, "area in voxels");
        expectRelNear(ours.volume(false), theirs.volume(false), 1e-4, "volume in voxels");
        expectRelNear(ours.totMeanCurvature(), theirs.totMeanCurvature(), 1e-4, "total H");
        expectRelNear(ours.avgMeanCurvature(), theirs.avgMeanCurvature(), 1e-4, "mean H");
        expectRelNear(ours.totGaussianCurvature(), theirs.totGaussianCurvature(), 1e-4, "total K");
        EXPECT_EQ(ours.eulerCharacteristic(), theirs.eulerCharacteristic());
        EXPECT_EQ(ours.genus(), theirs.genus());
        expectRelNear(tools::levelSetArea(*p.ours), openvdb::tools::levelSetArea(*p.theirs), 1e-4,
                      "levelSetArea");
        expectRelNear(tools::levelSetVolume(*p.ours), openvdb::tools::levelSetVolume(*p.theirs),
                      1e-4, "levelSetVolume");
        EXPECT_EQ(tools::levelSetGenus(*p.ours), openvdb::tools::levelSetGenus(*p.theirs));
        EXPECT_EQ(tools::levelSetEulerCharacteristic(*p.ours),
                  openvdb::tools::levelSetEulerCharacteristic(*p.theirs));
    }
}

TEST(MeasureCompat, TorusMeasuresMatchOpenVdb) {
    // The same torus written voxel by voxel into both.
    const double dx = 1.0 / 96;
    const auto sdf = [](const Vec3d& q) {
        const double a = std::sqrt(q[0] * q[0] + q[1] * q[1]) - 0.3;
        return float(std::sqrt(a * a + q[2] * q[2]) - 0.1);
    };
    const CoordBBox box(Coord(-44, -44, -16), Coord(44, 44, 16));
    auto p = test::sampledPair<test::FloatPair>(box, Vec3d(dx), Vec3d(0.0), sdf, float(3 * dx));
    // Keep only the band, as a level set holds it.
    std::vector<std::pair<Coord, float>> outside;
    for (auto it = p.ours->tree().cbeginValueOn(); it; ++it) {
        if (std::abs(*it) >= float(3 * dx))
            outside.emplace_back(it.getCoord(), *it > 0 ? float(3 * dx) : float(-3 * dx));
    }
    for (const auto& [ijk, v] : outside) {
        p.ours->tree().setValueOff(ijk, v);
        p.theirs->tree().setValueOff(test::toOvdb(ijk), v);
    }
    p.ours->setGridClass(GRID_LEVEL_SET);
    p.theirs->setGridClass(openvdb::GRID_LEVEL_SET);
    tools::LevelSetMeasure<FloatGrid> ours(*p.ours);
    openvdb::tools::LevelSetMeasure<openvdb::FloatGrid> theirs(*p.theirs);
    expectRelNear(ours.area(), theirs.area(), 1e-4, "area");
    expectRelNear(ours.volume(), theirs.volume(), 1e-4, "volume");
    expectRelNear(ours.totGaussianCurvature(), theirs.totGaussianCurvature(), 1e-4, "total K");
    expectRelNear(ours.totMeanCurvature(), theirs.totMeanCurvature(), 1e-4, "total H");
    EXPECT_EQ(ours.genus(), theirs.genus());
    EXPECT_EQ(ours.genus(), 1);
}

TEST(StatisticsCompat, StatisticsHistogramAndMinMaxMatchOpenVdb) {
    auto p = test::spheres(1.0f, Vec3f(0.0f), 0.05f);
    // An active tile too.
    p.ours->tree().fill(CoordBBox::createCube(Coord(512, 0, 0), 128), 0.7f, true);
    p.theirs->tree().fill(openvdb::CoordBBox::createCube(openvdb::Coord(512, 0, 0), 128), 0.7f,
                          true);
    // OpenVDB's accumulators over OpenVDB's iterators, tiles weighted by their voxel counts.
    openvdb::math::Stats b;
    openvdb::math::Histogram hb(-0.15, 0.15, 12);
    for (auto it = p.theirs->cbeginValueOn(); it; ++it) {
        b.add(*it, it.getVoxelCount());
        hb.add(*it, it.getVoxelCount());
    }
    openvdb::math::Extrema eb;
    for (auto it = p.theirs->cbeginValueAll(); it; ++it)
        eb.add(*it, it.getVoxelCount());
    const auto a = tools::statistics(p.ours->cbeginValueOn());
    EXPECT_EQ(a.size(), b.size());
    EXPECT_DOUBLE_EQ(a.min(), b.min());
    EXPECT_DOUBLE_EQ(a.max(), b.max());
    expectRelNear(a.mean(), b.mean(), 1e-9, "mean");
    expectRelNear(a.variance(), b.variance(), 1e-9, "variance");
    const auto ea = tools::extrema(p.ours->cbeginValueAll());
    EXPECT_EQ(ea.size(), eb.size());
    EXPECT_DOUBLE_EQ(ea.min(), eb.min());
    EXPECT_DOUBLE_EQ(ea.max(), eb.max());
    const auto ha = tools::histogram(p.ours->cbeginValueOn(), -0.15, 0.15, 12);
    EXPECT_EQ(ha.size(), hb.size());
    for (int i = 0; i < 12; ++i)
        EXPECT_EQ(ha.count(i), hb.count(i)) << "bin " << i;
    const auto ma = tools::minMax(p.ours->tree());
    const auto mb = openvdb::tools::minMax(p.theirs->tree());
    EXPECT_EQ(ma.min(), mb.min());
    EXPECT_EQ(ma.max(), mb.max());
}

TEST(ChangeBackgroundCompat, ValuesMatchOpenVdbEverywhere) {
    for (int variant = 0; variant < 3; ++variant) {
        auto p = test::spheres(1.0f, Vec3f(0.0f), 0.05f);
        if (variant == 0) {
            tools::changeBackground(p.ours->tree(), 0.4f);
            openvdb::tools::changeBackground(p.theirs->tree(), 0.4f);
        } else if (variant == 1) {
            tools::changeLevelSetBackground(p.ours->tree(), 0.25f);
            openvdb::tools::changeLevelSetBackground(p.theirs->tree(), 0.25f);
        } else {
            tools::changeAsymmetricLevelSetBackground(p.ours->tree(), 0.3f, -0.1f);
            openvdb::tools::changeAsymmetricLevelSetBackground(p.theirs->tree(), 0.3f, -0.1f);
        }
        EXPECT_EQ(p.ours->background(), p.theirs->background());
        auto acc = p.theirs->getConstAccessor();
        for (auto it = p.ours->cbeginValueAll(); it; ++it)
            ASSERT_EQ(*it, acc.getValue(test::toOvdb(it.getCoord()))) << it.getCoord();
        EXPECT_EQ(p.ours->tree().getValue(Coord(4000, 0, 0)),
                  acc.getValue(openvdb::Coord(4000, 0, 0)));
    }
}

}  // namespace
}  // namespace vdb
