// SPDX-License-Identifier: Apache-2.0
// Shared by the level set advection compatibility tests: the Enright sphere in both libraries,
// OpenVDB results measured by this library's code, and the Enright volume loss comparison.

#pragma once

#include <vdb/Grid.h>
#include <vdb/tools/EnrightTest.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/SignedFloodFill.h>

#include "OpenVdbConvert.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetAdvect.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace vdb::test {

struct Pair {
    FloatGrid::Ptr ours;
    openvdb::FloatGrid::Ptr theirs;
};

inline Pair enrightSpheres(int res) {
    openvdb::initialize();
    Pair p;
    p.ours = tools::createEnrightSphere<FloatGrid>(res, 5.0f);
    p.theirs = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(
        0.15f, openvdb::Vec3f(0.35f), 1.0f / float(res), 5.0f);
    return p;
}

/// Copies OpenVDB's active voxels into one of our grids (flood filled), to measure both
/// results with the same code.
inline FloatGrid::Ptr toVdbGrid(const openvdb::FloatGrid& in) {
    auto out = FloatGrid::create(in.background());
    out->setTransform(math::Transform::createLinearTransform(in.voxelSize()[0]));
    auto acc = out->getAccessor();
    for (auto it = in.cbeginValueOn(); it; ++it)
        acc.setValue(fromOvdb(it.getCoord()), *it);
    tools::signedFloodFill(out->tree());
    return out;
}

/// Runs the Enright test from t = 0 to `end` at `res`^3 in both libraries with the paper's
/// Table III schemes (advection HJ-WENO5 and TVD-RK3; renormalisation HJ-WENO5 and TVD-RK1,
/// three steps per rebuild) and the CFL number OpenVDB fixes for TVD-RK3, 1/sqrt(3) (so both
/// take about as many steps, hence as many rebuilds), and expects this library's relative
/// volume loss to be at most OpenVDB's plus 0.002 (0.2 percentage points). Both volumes are
/// measured by tools::smearedHeavisideVolume. With `intervals` > 1 both libraries are called once
/// per equal interval of [0, end] (as a caller writing that many frames would): OpenVDB sizes each
/// step by the speed at its start and keeps that velocity for the step, so in one call over a
/// reversal of the field (t = 1.5) it takes a few long steps that skip part of the flow.
inline void expectEnrightVolumeLossNoWorseThanOpenVdb(int res, double end, int intervals = 1) {
    auto p = enrightSpheres(res);
    const double v0 = tools::smearedHeavisideVolume(*p.ours);

    tools::EnrightTestOptions options;
    options.resolution = res;
    options.endTime = end;
    options.cfl = 1.0 / std::sqrt(3.0);
    options.frames = intervals;
    const auto ours = tools::runEnrightTest<FloatGrid>(options);
    EXPECT_DOUBLE_EQ(ours.initial.volume, v0);

    openvdb::tools::EnrightField<float> ofield;
    openvdb::tools::LevelSetAdvection<openvdb::FloatGrid, openvdb::tools::EnrightField<float>>
        theirs(*p.theirs, ofield);
    theirs.setSpatialScheme(openvdb::math::HJWENO5_BIAS);
    theirs.setTemporalScheme(openvdb::math::TVD_RK3);
    theirs.setTrackerSpatialScheme(openvdb::math::HJWENO5_BIAS);
    theirs.setTrackerTemporalScheme(openvdb::math::TVD_RK1);
    theirs.setNormCount(3);
    for (int f = 0; f < intervals; ++f)
        theirs.advect(end * f / intervals, end * (f + 1) / intervals);
    const double theirLoss = (v0 - tools::smearedHeavisideVolume(*toVdbGrid(*p.theirs))) / v0;
    ::testing::Test::RecordProperty("vdb_volume_loss", std::to_string(ours.volumeLoss()));
    ::testing::Test::RecordProperty("openvdb_volume_loss", std::to_string(theirLoss));
    EXPECT_LE(ours.volumeLoss(), theirLoss + 0.002)
        << "ours " << ours.volumeLoss() << ", OpenVDB " << theirLoss;
    std::printf(
        "Enright %d^3 to t = %g in %d interval(s): volume loss %.4f%% here, %.4f%% in "
        "OpenVDB\n",
        res, end, intervals, 100.0 * ours.volumeLoss(), 100.0 * theirLoss);
}

}  // namespace vdb::test
