// SPDX-License-Identifier: Apache-2.0
// Dense copies against OpenVDB 10's tools/Dense.h on the same values: copyToDense gives the
// same array bit for bit, and copyFromDense into an empty tree the same active voxels, values
// and inactive values.

#include <vdb/Grid.h>
#include <vdb/tools/Dense.h>

#include "OpenVdbConvert.h"
#include <gtest/gtest.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <random>

namespace vdb {
namespace {

using test::fromOvdb;
using test::toOvdb;

/// The same random values, blocks of constant values and background in both libraries' grids.
void makeGrids(FloatTree& ours, openvdb::FloatTree& theirs, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-40, 60);
    std::uniform_real_distribution<float> v(-3.0f, 3.0f);
    for (int n = 0; n < 3000; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        const float x = v(rng);
        const bool on = rng() % 3 != 0;
        if (on) {
            ours.setValueOn(ijk, x);
            theirs.setValueOn(toOvdb(ijk), x);
        } else {
            ours.setValueOff(ijk, x);
            theirs.setValueOff(toOvdb(ijk), x);
        }
    }
    const CoordBBox tile(Coord(64, 0, 0), Coord(127, 63, 63));
    ours.fill(tile, 1.5f, true);
    theirs.fill(toOvdb(tile), 1.5f, true);
}

TEST(DenseCompat, CopyToDenseGivesOpenVdbsArrayBitForBit) {
    openvdb::initialize();
    FloatTree ours(0.25f);
    openvdb::FloatTree theirs(0.25f);
    makeGrids(ours, theirs, 5);
    const CoordBBox box(Coord(-45, -10, -3), Coord(100, 70, 66));
    tools::Dense<float> a(box);
    tools::copyToDense(ours, a);
    openvdb::tools::Dense<float> b(toOvdb(box));
    openvdb::tools::copyToDense(theirs, b);
    ASSERT_EQ(a.valueCount(), b.valueCount());
    for (Index64 n = 0; n < a.valueCount(); ++n)
        ASSERT_EQ(a.data()[n], b.data()[n]) << n;
}

TEST(DenseCompat, CopyFromDenseBuildsOpenVdbsTree) {
    openvdb::initialize();
    for (const float tolerance : {0.0f, 0.5f}) {
        const CoordBBox box(Coord(-21, -5, 3), Coord(70, 40, 61));
        tools::Dense<float> a(box);
        openvdb::tools::Dense<float> b(toOvdb(box));
        std::mt19937 rng(9);
        std::uniform_real_distribution<float> v(-2.0f, 2.0f);
        for (Index64 n = 0; n < a.valueCount(); ++n) {
            const float x = rng() % 4 == 0 ? v(rng) : (rng() % 2 ? 0.0f : 1.25f);
            a.data()[n] = x;
            b.data()[n] = x;
        }
        FloatTree ours(0.0f);
        openvdb::FloatTree theirs(0.0f);
        tools::copyFromDense(a, ours, tolerance);
        openvdb::tools::copyFromDense(b, theirs, tolerance);
        EXPECT_EQ(ours.activeVoxelCount(), theirs.activeVoxelCount()) << tolerance;
        EXPECT_EQ(ours.leafCount(), theirs.leafCount()) << tolerance;
        for (auto it = theirs.cbeginValueOn(); it; ++it) {
            const Coord ijk = fromOvdb(it.getCoord());
            ASSERT_TRUE(ours.isValueOn(ijk)) << ijk;
            ASSERT_EQ(ours.getValue(ijk), *it) << ijk;
        }
        for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
            for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                    ASSERT_EQ(ours.getValue(Coord(i, j, k)),
                              theirs.getValue(openvdb::Coord(i, j, k)));
    }
}

}  // namespace
}  // namespace vdb
