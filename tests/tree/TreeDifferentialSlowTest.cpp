// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels that knows nothing
// of nodes or tiles. The larger variant of TreeDifferentialTest.cpp: more seeds, longer
// batches, wider clusters and more isolated points, for every configuration of Table II.

#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

// Every configuration of Table II with float values: the tree type, whether an InternalNode
// stands on top, and the log2 edges of its nodes below any root, top first.
struct HashTree543 : test::TreeConfig<tree::HashTree543<float>, false, 5, 4, 3> {
    static constexpr const char* NAME = "HashTree543";
};
struct MapTree543 : test::TreeConfig<tree::MapTree543<float>, false, 5, 4, 3> {
    static constexpr const char* NAME = "MapTree543";
};
struct HashTree432 : test::TreeConfig<tree::HashTree432<float>, false, 4, 3, 2> {
    static constexpr const char* NAME = "HashTree432";
};
struct MapTree432 : test::TreeConfig<tree::MapTree432<float>, false, 4, 3, 2> {
    static constexpr const char* NAME = "MapTree432";
};
struct FixedTree76543 : test::TreeConfig<tree::FixedTree76543<float>, true, 7, 6, 5, 4, 3> {
    static constexpr const char* NAME = "FixedTree76543";
};
struct FixedTree6543 : test::TreeConfig<tree::FixedTree6543<float>, true, 6, 5, 4, 3> {
    static constexpr const char* NAME = "FixedTree6543";
};
struct FixedTree643 : test::TreeConfig<tree::FixedTree643<float>, true, 6, 4, 3> {
    static constexpr const char* NAME = "FixedTree643";
};
struct FixedTree103 : test::TreeConfig<tree::FixedTree103<float>, true, 10, 3> {
    static constexpr const char* NAME = "FixedTree103";
};
struct FixedTree6545 : test::TreeConfig<tree::FixedTree6545<float>, true, 6, 5, 4, 5> {
    static constexpr const char* NAME = "FixedTree6545";
};
struct FixedTree6544 : test::TreeConfig<tree::FixedTree6544<float>, true, 6, 5, 4, 4> {
    static constexpr const char* NAME = "FixedTree6544";
};
struct FixedTree6542 : test::TreeConfig<tree::FixedTree6542<float>, true, 6, 5, 4, 2> {
    static constexpr const char* NAME = "FixedTree6542";
};
struct FixedTree6666 : test::TreeConfig<tree::FixedTree6666<float>, true, 6, 6, 6, 6> {
    static constexpr const char* NAME = "FixedTree6666";
};
struct FixedTree5555 : test::TreeConfig<tree::FixedTree5555<float>, true, 5, 5, 5, 5> {
    static constexpr const char* NAME = "FixedTree5555";
};
struct FixedTree4444 : test::TreeConfig<tree::FixedTree4444<float>, true, 4, 4, 4, 4> {
    static constexpr const char* NAME = "FixedTree4444";
};
struct FixedTree3333 : test::TreeConfig<tree::FixedTree3333<float>, true, 3, 3, 3, 3> {
    static constexpr const char* NAME = "FixedTree3333";
};

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
