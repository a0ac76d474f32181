// SPDX-License-Identifier: Apache-2.0
// Oracles: serial loops over the tree's own leaf iterator; temporal buffers checked against
// the values written into each buffer before the swap.

#include <vdb/tree/LeafManager.h>
#include <vdb/tree/TreeConfigs.h>

#include <gtest/gtest.h>

#include <random>
#include <set>

namespace vdb::tree {
namespace {

FloatTree makeRandomTree(int n, unsigned seed) {
    FloatTree tree(0.0f);
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(-500, 500);
    for (int i = 0; i < n; ++i)
        tree.setValue(Coord(d(rng), d(rng), d(rng)), float(i % 97));
    return tree;
}

TEST(LeafManager, HoldsEveryLeafOnce) {
    FloatTree tree = makeRandomTree(20000, 1);
    LeafManager<FloatTree> leaves(tree);
    ASSERT_EQ(leaves.leafCount(), tree.leafCount());
    std::set<Coord> origins;
    for (size_t i = 0; i < leaves.leafCount(); ++i)
        origins.insert(leaves.leaf(i).origin());
    EXPECT_EQ(origins.size(), leaves.leafCount());
    for (auto it = tree.cbeginLeaf(); it; ++it)
        EXPECT_EQ(origins.count(it->origin()), 1u);
    EXPECT_EQ(leaves.activeLeafVoxelCount(), tree.activeVoxelCount());
}

TEST(LeafManager, ThreadedForeachEqualsSerialForeach) {
    FloatTree a = makeRandomTree(20000, 2), b = a;
    auto op = [](auto& leaf, size_t i) {
        for (auto it = leaf.beginValueOn(); it; ++it)
            it.setValue(*it * 2.0f + float(i % 3));
    };
    LeafManager<FloatTree>(a).foreach (op, /*threaded=*/true);
    LeafManager<FloatTree>(b).foreach (op, /*threaded=*/false);
    for (auto it = a.cbeginValueOn(); it; ++it) {
        ASSERT_EQ(*it, b.getValue(it.getCoord())) << it.getCoord();
    }
}

TEST(LeafManager, AuxBuffersStartAsCopiesAndSwapWithoutCopying) {
    FloatTree tree = makeRandomTree(5000, 3);
    const FloatTree before = tree;
    LeafManager<FloatTree> leaves(tree, 2);
    EXPECT_EQ(leaves.auxBufferCount(), 2u);
    leaves.foreach ([](auto& leaf, size_t) {
        ASSERT_EQ(leaf.bufferCount(), 3u);
        for (Index n = 0; n < leaf.NUM_VALUES; ++n) {
            ASSERT_EQ(leaf.buffer(1)[n], leaf.buffer(0)[n]);
            ASSERT_EQ(leaf.buffer(2)[n], leaf.buffer(0)[n]);
            leaf.buffer(1)[n] = 100.0f + leaf.buffer(0)[n];
        }
    });
    const float* oldData = leaves.leaf(0).buffer(1).data();
    leaves.swapLeafBuffers(0, 1);
    EXPECT_EQ(leaves.leaf(0).buffer(0).data(), oldData);  // swapped, not copied
    for (auto it = before.cbeginValueOn(); it; ++it) {
        ASSERT_EQ(tree.getValue(it.getCoord()), 100.0f + *it);
    }
    leaves.swapLeafBuffers(0, 1);
    for (auto it = before.cbeginValueOn(); it; ++it) {
        ASSERT_EQ(tree.getValue(it.getCoord()), *it);
    }
    leaves.setAuxBufferCount(0);
    EXPECT_EQ(leaves.leaf(0).bufferCount(), 1u);
    EXPECT_LT(tree.memUsage(), before.memUsage() + 1);
}

TEST(LeafManager, ConstTreeAllowsReadOnlyLoops) {
    const FloatTree tree = makeRandomTree(3000, 4);
    LeafManager<const FloatTree> leaves(tree);
    std::atomic<Index64> count{0};
    leaves.foreach ([&](const auto& leaf, size_t) { count += leaf.onVoxelCount(); });
    EXPECT_EQ(count.load(), tree.activeVoxelCount());
}

template <typename TreeT>
void checkBufferlessLeaves() {
    TreeT tree(false);
    tree.setValueOn(Coord(-9, 0, 3));
    tree.setValueOn(Coord(100, 200, -300));
    LeafManager<TreeT> leaves(tree);
    EXPECT_FALSE(LeafManager<TreeT>::HAS_BUFFERS);
    EXPECT_EQ(leaves.leafCount(), 2u);
    std::atomic<Index64> count{0};
    leaves.foreach ([&](const auto& leaf, size_t) { count += leaf.onVoxelCount(); });
    EXPECT_EQ(count.load(), 2u);
    tree.setValueOn(Coord(1000, 0, 0));
    leaves.rebuild();
    EXPECT_EQ(leaves.leafCount(), 3u);
    EXPECT_THROW(leaves.rebuild(1), ValueError);
    EXPECT_THROW(LeafManager<TreeT>(tree, 2), ValueError);
}

TEST(LeafManager, BoolAndMaskTreesHaveLeavesButNoTemporalBuffers) {
    EXPECT_TRUE(LeafManager<FloatTree>::HAS_BUFFERS);
    checkBufferlessLeaves<BoolTree>();
    checkBufferlessLeaves<MaskTree>();
}

}  // namespace
}  // namespace vdb::tree
