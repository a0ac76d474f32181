// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10 on the same Enright sphere with the same schemes. The full Enright period
// at 128^3 (about a minute on two cores), both libraries called once per 1/100 of the period:
// this library's volume loss at most OpenVDB's plus 0.2 percentage points.
//
// Why intervals: in one call over the whole period OpenVDB sizes each step by the speed at its
// start and keeps that velocity for the step, so around t = 1.5, where the field vanishes and
// reverses, it takes a few long steps that carry almost no motion (666 steps against 827 here
// at 128^3) and loses less volume by skipping part of the flow (measured 2026-11-23: 23.05%
// there, 24.08% here). Intervals bound every step of both alike: about 870 steps each, 24.65%
// there and 24.36% here (this test, 2026-11-23).

#include "LevelSetAdvectCompat.h"
#include <gtest/gtest.h>

namespace vdb {
namespace {

TEST(LevelSetAdvectCompatSlow, EnrightFullPeriodVolumeLossIsNoWorseThanOpenVdb) {
    test::expectEnrightVolumeLossNoWorseThanOpenVdb(128, tools::EnrightField<float>::PERIOD, 100);
}

}  // namespace
}  // namespace vdb
