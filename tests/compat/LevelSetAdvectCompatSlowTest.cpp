// SPDX-License-Identifier: Apache-2.0
// Oracle: OpenVDB 10 on the same Enright sphere with the same schemes. The full Enright period
// at 128^3 (a few minutes on two cores): this library's volume loss at most OpenVDB's plus 0.2
// percentage points.

#include "LevelSetAdvectCompat.h"
#include <gtest/gtest.h>

namespace vdb {
namespace {

TEST(LevelSetAdvectCompatSlow, EnrightFullPeriodVolumeLossIsNoWorseThanOpenVdb) {
    test::expectEnrightVolumeLossNoWorseThanOpenVdb(128, tools::EnrightField<float>::PERIOD);
}

}  // namespace
}  // namespace vdb
