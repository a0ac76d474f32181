// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels that knows nothing
// of nodes or tiles. The larger variant of TreeDifferentialTest.cpp: more seeds, longer
// batches, wider clusters and more isolated points, for every configuration of Table II.

#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class TreeDifferentialSlow : public ::testing::Test {};
using AllConfigs =
    ::testing::Types<HashTree543, MapTree543, HashTree432, MapTree432, FixedTree76543,
                     FixedTree6543, FixedTree643, FixedTree103, FixedTree6545, FixedTree6544,
                     FixedTree6542, FixedTree6666, FixedTree5555, FixedTree4444, FixedTree3333>;
TYPED_TEST_SUITE(TreeDifferentialSlow, AllConfigs, test::ConfigName);

TYPED_TEST(TreeDifferentialSlow, LongRandomOperationsMatchSparseVolumeModel) {
    using TreeT = typename TypeParam::TreeType;
    constexpr bool is103 = std::is_same_v<TreeT, tree::FixedTree103<float>>;
    // The [10,3] tree's 2^30-entry top table is only cheap when the background is zero bits.
    const float background = is103 ? 0.0f : -4.0f;
    for (const uint32_t seed : {19700101u, 31415926u}) {
        SCOPED_TRACE(::testing::Message() << "seed " << seed);
        test::WorkloadOptions options;
        options.seed = seed;
        options.batches = 25;
        options.opsPerBatch = 100000;
        options.clusterRadius = 24;
        options.denseClusters = 10;
        options.sparsePoints = 64;
        options.maxSmallFillVolume = 8192;
        options.alignedFillVoxelsPerBatch = 65536;
        options.maxModelSize = 400000;
        options.storedValuesCheckedPerBatch = 100000;
        if constexpr (is103) {
            // Every whole-tree pass scans 2^24 mask words; see TreeDifferentialTest.cpp.
            options.batches = 10;
            options.pruneOrClearRate = 1e-5;
            options.checkInactiveValues = false;
            options.checkCopy = false;
        }
        if constexpr (std::is_same_v<TreeT, tree::FixedTree76543<float>> ||
                      std::is_same_v<TreeT, tree::FixedTree6666<float>>) {
            options.sparsePoints = 24;  // each isolated point costs megabytes of nodes
        }
        TreeT tree(background);
        test::TreeModelDriver<TreeT, tree::ValueAccessor<TreeT>, tree::ValueAccessor<const TreeT>>
            driver(tree, TypeParam::shape(), options,
                   {background, 0.0f, -1.0f, 1.0f, 2.0f, 0.5f, 8.0f, -3.75f, 1e6f});
        EXPECT_TRUE(driver.run());
    }
}

}  // namespace
}  // namespace vdb
