// SPDX-License-Identifier: Apache-2.0
// Oracles: a snapshot of every voxel and tile of the tree taken before pruning, read back at
// each voxel and at two opposite corners of each tile; and the definitions of the prune rules
// (constant within tolerance, no active value) evaluated by plain loops over the values of the
// unpruned tree's leaves, which fix how many leaves survive.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/tools/Prune.h>
#include <vdb/tree/TreeConfigs.h>

#include "LevelSetTestUtil.h"
#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <unordered_set>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

constexpr float kBackground = 2.0f;

/// Calls `fn(ijk)` at the voxel, or at the two extreme corners of the tile, of a stored value.
template <typename ItemT, typename FnT>
void forEachProbe(const ItemT& item, const FnT& fn) {
    fn(item.min);
    if (item.dim > 1)
        fn(item.min.offsetBy(item.dim - 1, item.dim - 1, item.dim - 1));
}

/// A node region: its level and origin.
struct NodeKey {
    Index level;
    Coord origin;
    bool operator==(const NodeKey& o) const { return level == o.level && origin == o.origin; }
};
struct NodeKeyHash {
    size_t operator()(const NodeKey& k) const { return test::CoordHash()(k.origin) ^ k.level; }
};
using NodeKeySet = std::unordered_set<NodeKey, NodeKeyHash>;

template <typename C>
class Prune : public ::testing::Test {
protected:
    using TreeT = typename C::TreeType;
    using TopT = typename TreeT::TopNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    static constexpr Index TOP = TopT::LEVEL;
    static constexpr Int32 LEAF_DIM = Int32(LeafT::DIM);
    static constexpr Int32 NODE1_DIM = Int32(tree::NodeAtLevelT<TopT, 1>::DIM);

    /// A seeded tree around the origin with constant, jittered, nearly constant and inactive
    /// leaves; level-1 regions tiled by leaf-sized tiles with constant leaves among them;
    /// scattered voxels; level-1-sized tiles; and, under a root, root tiles of the background
    /// (inactive, one float step above it, and active).
    static void populate(TreeT& tree, uint32_t seed) {
        std::mt19937 rng(seed);
        const std::vector<float> palette = {0.0f, 0.25f, -1.0f, kBackground, -2.0f, 3.0f};
        auto pick = [&] { return palette[rng() % palette.size()]; };
        std::uniform_int_distribution<Int32> cell(-2 * NODE1_DIM / LEAF_DIM,
                                                  2 * NODE1_DIM / LEAF_DIM - 1);
        auto leafOrigin = [&] {
            return Coord(cell(rng) * LEAF_DIM, cell(rng) * LEAF_DIM, cell(rng) * LEAF_DIM);
        };
        for (int n = 0; n < 40; ++n)
            tree.touchLeaf(leafOrigin())->fill(pick(), rng() % 2 == 0);
        // Jittered leaves: values base + 0.01 k, k < 2, 3 or 5; one state.
        for (int n = 0; n < 24; ++n) {
            LeafT* leaf = tree.touchLeaf(leafOrigin());
            const float base = pick();
            const bool on = rng() % 2 == 0;
            const uint32_t spread = n % 3 == 0 ? 2 : n % 3 == 1 ? 3 : 5;
            for (Index i = 0; i < LeafT::NUM_VALUES; ++i) {
                const float v = base + 0.01f * float(rng() % spread);
                on ? leaf->setValueOn(i, v) : leaf->setValueOff(i, v);
            }
        }
        // Constant leaves but for one voxel's state or value.
        for (int n = 0; n < 12; ++n) {
            LeafT* leaf = tree.touchLeaf(leafOrigin());
            const bool on = rng() % 2 == 0;
            leaf->fill(pick(), on);
            const Index i = Index(rng() % LeafT::NUM_VALUES);
            if (n % 2) {
                leaf->setActiveState(i, !on);
            } else {
                leaf->setValueOnly(i, leaf->getValue(i) + 1.0f);
            }
        }
        // Level-1 regions of leaf-sized tiles, with constant leaves of the same value inside
        // (constant, inactive, jittered; fewer in a scaled-down run).
        const int regions = std::min(3, test::scaledBatchCount(3));
        for (int n = 0; n < regions; ++n) {
            const Coord origin = leafOrigin().alignedDown(tree::NodeAtLevelT<TopT, 1>::TOTAL);
            const float v = pick();
            const bool on = n != 1;
            for (Int32 i = 0; i < NODE1_DIM; i += LEAF_DIM)
                for (Int32 j = 0; j < NODE1_DIM; j += LEAF_DIM)
                    for (Int32 k = 0; k < NODE1_DIM; k += LEAF_DIM) {
                        const CoordBBox box =
                            CoordBBox::createCube(origin.offsetBy(i, j, k), LEAF_DIM);
                        const float w = n == 2 ? v + 0.01f * float(rng() % 2) : v;
                        if (rng() % 64 == 0) {
                            tree.touchLeaf(box.min())->fill(w, on);
                        } else {
                            tree.fill(box, w, on);
                        }
                    }
        }
        // Scattered voxels and level-1-sized tiles.
        for (int n = 0; n < 300; ++n) {
            const Coord ijk = leafOrigin().offsetBy(Int32(rng() % LEAF_DIM), 0, 0);
            rng() % 3 ? tree.setValueOn(ijk, pick()) : tree.setValueOff(ijk, pick());
        }
        for (int n = 0; n < 4; ++n) {
            const Coord origin = leafOrigin().alignedDown(tree::NodeAtLevelT<TopT, 1>::TOTAL);
            tree.fill(CoordBBox::createCube(origin.offsetBy(0, 0, 4 * NODE1_DIM), NODE1_DIM),
                      pick(), n % 2 == 0);
        }
        if constexpr (!TreeT::BOUNDED) {
            const Int32 dim = Int32(TopT::ChildNodeType::DIM);
            tree.fill(CoordBBox::createCube(Coord(0, 0, 4 * dim), dim), kBackground, false);
            tree.fill(CoordBBox::createCube(Coord(0, 0, 5 * dim), dim), kBackground + 2e-7f, false);
            tree.fill(CoordBBox::createCube(Coord(0, 0, 6 * dim), dim), kBackground + 1e-3f, false);
            tree.fill(CoordBBox::createCube(Coord(0, 0, 7 * dim), dim), kBackground, true);
        }
    }

    /// The node regions of a tree below its top, and those that hold an active value.
    struct Regions {
        NodeKeySet nodes, active;
        Index log2[TOP];

        Regions(const TreeT& tree, const std::vector<test::StoredValue<float>>& values) {
            test::forEachLevel<0, TOP>([&](auto level) {
                log2[decltype(level)::value] =
                    tree::NodeAtLevelT<TopT, decltype(level)::value>::TOTAL;
            });
            for (auto it = tree.cbeginNode(); it; ++it) {
                if (it.getLevel() < TOP)
                    nodes.insert({Index(it.getLevel()), it.getCoord()});
            }
            for (const auto& item : values) {
                if (!item.on)
                    continue;
                for (Index l = item.level; l < TOP; ++l)
                    active.insert({l, item.min.alignedDown(log2[l])});
            }
        }
        /// The origin of the highest node on the path to `ijk` that holds no active value,
        /// or false.
        bool highestInactiveNode(const Coord& ijk, Coord& origin) const {
            for (Index l = TOP; l-- > 0;) {
                const NodeKey key{l, ijk.alignedDown(log2[l])};
                if (nodes.count(key) && !active.count(key)) {
                    origin = key.origin;
                    return true;
                }
            }
            return false;
        }
    };

    /// Applies `check(ijk, item)` at every probe point of every stored value, up to the first
    /// failure.
    template <typename CheckT>
    static ::testing::AssertionResult checkProbes(
        const std::vector<test::StoredValue<float>>& values, const CheckT& check) {
        ::testing::AssertionResult result = ::testing::AssertionSuccess();
        for (const auto& item : values) {
            forEachProbe(item, [&](const Coord& ijk) {
                if (result)
                    result = check(ijk, item);
            });
            if (!result)
                break;
        }
        return result;
    }

    /// The voxels and tiles of `tree` before an operation.
    static auto snapshot(const TreeT& tree) { return test::listStoredValues(tree); }

    /// True when `leaf`'s states agree and its values lie within `tolerance` (by definition:
    /// largest minus smallest).
    static bool leafIsConstant(const LeafT& leaf, float tolerance) {
        const bool state = leaf.isValueOn(Index(0));
        float lo = leaf.getValue(Index(0)), hi = lo;
        for (Index i = 0; i < LeafT::NUM_VALUES; ++i) {
            if (leaf.isValueOn(i) != state)
                return false;
            lo = std::min(lo, leaf.getValue(i));
            hi = std::max(hi, leaf.getValue(i));
        }
        return hi - lo <= tolerance;
    }

    /// Fails if some node below the top could still be replaced by a tile under prune(tolerance).
    static ::testing::AssertionResult noConstantNodeLeft(const TreeT& tree, float tolerance) {
        for (const auto& leaf : tree.leaves()) {
            if (leafIsConstant(leaf, tolerance))
                return ::testing::AssertionFailure() << "leaf " << leaf.origin() << " is constant";
        }
        ::testing::AssertionResult result = ::testing::AssertionSuccess();
        test::forEachLevel<1, TOP>([&](auto level) {
            test::forEachNodeAtLevel<decltype(level)::value>(tree, [&](const auto& node) {
                if (!node.getChildMask().isOff())
                    return;
                const auto& mask = node.getValueMask();
                if (!mask.isOn() && !mask.isOff())
                    return;
                float lo = node.getTileValue(0), hi = lo;
                for (Index n = 0; n < node.NUM_VALUES; ++n) {
                    lo = std::min(lo, node.getTileValue(n));
                    hi = std::max(hi, node.getTileValue(n));
                }
                if (hi - lo <= tolerance && result) {
                    result = ::testing::AssertionFailure()
                             << "level-" << decltype(level)::value << " node " << node.origin()
                             << " is constant";
                }
            });
        });
        return result;
    }
};

using PruneConfigs = ::testing::Types<HashTree543, MapTree432, FixedTree6543, FixedTree6542>;
TYPED_TEST_SUITE(Prune, PruneConfigs, test::ConfigName);

TYPED_TEST(Prune, ExactPruneKeepsEveryValueAndLeavesNoConstantNode) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(kBackground);
    TestFixture::populate(tree, 101);
    const auto before = TestFixture::snapshot(tree);
    const Index64 activeBefore = tree.activeVoxelCount();
    Index32 survivors = 0;
    for (const auto& leaf : tree.leaves())
        survivors += TestFixture::leafIsConstant(leaf, 0.0f) ? 0 : 1;
    ASSERT_LT(survivors, tree.leafCount()) << "the workload makes no constant leaf";

    typename TreeT::Accessor acc(tree);
    acc.getValue(Coord(0));  // a cached path that pruning may free
    tools::prune(tree);

    EXPECT_EQ(tree.leafCount(), survivors);
    EXPECT_EQ(tree.activeVoxelCount(), activeBefore);
    EXPECT_TRUE(TestFixture::noConstantNodeLeft(tree, 0.0f));
    EXPECT_TRUE(TestFixture::checkProbes(before, [&](const Coord& ijk, const auto& item) {
        if (acc.getValue(ijk) == item.value && acc.isValueOn(ijk) == item.on)
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure()
               << ijk << " reads " << acc.getValue(ijk) << " instead of " << item.value;
    }));
    if constexpr (!TreeT::BOUNDED) {
        // Inactive root tiles of the background are gone; one float step above it, or active,
        // they stay.
        const auto& root = tree.topNode();
        for (auto c = root.cbegin(); root.valid(c); root.next(c)) {
            const auto& e = root.entry(c);
            EXPECT_FALSE(!e.child && !e.active && e.tile == kBackground) << root.key(c);
        }
        const Int32 dim = Int32(TreeT::TopNodeType::ChildNodeType::DIM);
        EXPECT_EQ(root.findEntry(Coord(0, 0, 4 * dim)), nullptr);
        EXPECT_NE(root.findEntry(Coord(0, 0, 5 * dim)), nullptr);
        EXPECT_NE(root.findEntry(Coord(0, 0, 7 * dim)), nullptr);
    }
}

TYPED_TEST(Prune, TolerancePruneStaysWithinToleranceAndKeepsStates) {
    using TreeT = typename TestFixture::TreeT;
    for (const float tolerance : {0.015f, 0.05f}) {
        SCOPED_TRACE(::testing::Message() << "tolerance " << tolerance);
        TreeT tree(kBackground);
        TestFixture::populate(tree, 202);
        const auto before = TestFixture::snapshot(tree);
        Index32 survivors = 0;
        for (const auto& leaf : tree.leaves())
            survivors += TestFixture::leafIsConstant(leaf, tolerance) ? 0 : 1;
        tools::prune(tree, tolerance);

        EXPECT_EQ(tree.leafCount(), survivors);
        EXPECT_TRUE(TestFixture::noConstantNodeLeft(tree, tolerance));
        // Each level that collapses moves a value by at most the tolerance.
        const float bound = float(TestFixture::TOP) * tolerance * 1.0001f;
        typename TreeT::ConstAccessor acc(tree);
        EXPECT_TRUE(TestFixture::checkProbes(before, [&](const Coord& ijk, const auto& item) {
            if (std::abs(acc.getValue(ijk) - item.value) <= bound &&
                acc.isValueOn(ijk) == item.on) {
                return ::testing::AssertionSuccess();
            }
            return ::testing::AssertionFailure()
                   << ijk << " reads " << acc.getValue(ijk) << " instead of " << item.value;
        }));
    }
}

TYPED_TEST(Prune, PruneInactiveReplacesNodesWithoutActiveValues) {
    using TreeT = typename TestFixture::TreeT;
    constexpr Index TOP = TestFixture::TOP;
    for (const bool withValue : {false, true}) {
        SCOPED_TRACE(::testing::Message() << "with value " << withValue);
        TreeT tree(kBackground);
        TestFixture::populate(tree, 303);
        const TreeT original(tree);
        const auto before = TestFixture::snapshot(tree);

        const typename TestFixture::Regions regions(tree, before);
        Index32 survivors = 0;
        for (const auto& leaf : tree.leaves())
            survivors += leaf.isEmpty() ? 0 : 1;

        const float fill = withValue ? -5.0f : kBackground;
        if (withValue) {
            tools::pruneInactiveWithValue(tree, fill);
        } else {
            tools::pruneInactive(tree);
        }
        EXPECT_EQ(tree.leafCount(), survivors);
        typename TreeT::ConstAccessor acc(tree), orig(original);
        // The highest node on each path with no active value became a tile of `fill`.
        EXPECT_TRUE(TestFixture::checkProbes(before, [&](const Coord& ijk, const auto&) {
            Coord origin;
            const float expected =
                regions.highestInactiveNode(ijk, origin) ? fill : orig.getValue(ijk);
            if (acc.getValue(ijk) == expected && acc.isValueOn(ijk) == orig.isValueOn(ijk))
                return ::testing::AssertionSuccess();
            return ::testing::AssertionFailure()
                   << ijk << " reads " << acc.getValue(ijk) << " instead of " << expected;
        }));
        test::forEachLevel<1, TOP>([&](auto level) {
            test::forEachNodeAtLevel<decltype(level)::value>(tree, [&](const auto& node) {
                EXPECT_FALSE(node.getChildMask().isOff() && node.getValueMask().isOff())
                    << "inactive node " << node.origin() << " left";
            });
        });
    }
}

TYPED_TEST(Prune, PruneLevelSetGivesTilesTheSignOfTheFirstValue) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(kBackground);
    TestFixture::populate(tree, 404);
    const TreeT original(tree);
    const auto before = TestFixture::snapshot(tree);
    const typename TestFixture::Regions regions(tree, before);

    tools::pruneLevelSet(tree);
    typename TreeT::ConstAccessor acc(tree), orig(original);
    // A pruned node's first value is the original value at its origin.
    EXPECT_TRUE(TestFixture::checkProbes(before, [&](const Coord& ijk, const auto&) {
        Coord origin;
        float expected = orig.getValue(ijk);
        if (regions.highestInactiveNode(ijk, origin))
            expected = orig.getValue(origin) < 0.0f ? -kBackground : kBackground;
        if (acc.getValue(ijk) == expected && acc.isValueOn(ijk) == orig.isValueOn(ijk))
            return ::testing::AssertionSuccess();
        return ::testing::AssertionFailure()
               << ijk << " reads " << acc.getValue(ijk) << " instead of " << expected;
    }));
    for (const auto& leaf : tree.leaves())
        EXPECT_FALSE(leaf.isEmpty()) << leaf.origin();
}

TYPED_TEST(Prune, ThreadedMatchesSingleThreadedBitForBit) {
    using TreeT = typename TestFixture::TreeT;
    TreeT a(kBackground);
    TestFixture::populate(a, 505);
    const TreeT input(a);
    TreeT b(input), c(input), d(input), e(input), f(input);
    tools::prune(a, 0.0f, true);
    tools::prune(b, 0.0f, false);
    EXPECT_TRUE(test::identicalTrees(a, b));
    tools::prune(c, 0.05f, true);
    tools::prune(d, 0.05f, false);
    EXPECT_TRUE(test::identicalTrees(c, d));
    tools::pruneLevelSet(e, true);
    tools::pruneLevelSet(f, false);
    EXPECT_TRUE(test::identicalTrees(e, f));
}

// ---- Single rules, on the standard tree ----------------------------------------------------

TEST(PruneRules, ToleranceTileTakesTheLowerMedian) {
    FloatTree tree(0.0f);
    auto* leaf = tree.touchLeaf(Coord(8, -16, 24));
    // Values 0.001 * ((n * 37) % 512): a permutation of 0 .. 0.511, so the lower median is
    // element 255 of the sorted values.
    for (Index n = 0; n < 512; ++n)
        leaf->setValueOn(n, 0.001f * float((n * 37) % 512));
    tools::prune(tree, 0.5f);  // spread 0.511: not constant
    EXPECT_EQ(tree.leafCount(), 1u);
    tools::prune(tree, 0.52f);
    EXPECT_EQ(tree.leafCount(), 0u);
    EXPECT_EQ(tree.getValue(Coord(8, -16, 24)), 0.001f * 255.0f);
    EXPECT_TRUE(tree.isValueOn(Coord(15, -9, 31)));
}

TEST(PruneRules, VectorTilesCompareLexicographically) {
    Vec3STree tree(Vec3s(0.0f));
    auto* leaf = tree.touchLeaf(Coord(0));
    // First components 1.0 or 1.01 (spread 0.01); the second decides order among equals.
    for (Index n = 0; n < 512; ++n)
        leaf->setValueOn(n, Vec3s(n < 300 ? 1.0f : 1.01f, float(n % 7), 5.0f));
    Vec3STree copy(tree);
    tools::prune(copy, Vec3s(0.005f));
    EXPECT_EQ(copy.leafCount(), 1u);
    tools::prune(tree, Vec3s(0.02f));
    ASSERT_EQ(tree.leafCount(), 0u);
    // Sorted: 300 values (1.0, m, 5) with m = n % 7 over n < 300, then (1.01, ...). Element 255
    // is (1.0, m255, 5) where m255 is the 256th smallest of {n % 7 : n < 300}.
    std::vector<float> second;
    for (Index n = 0; n < 300; ++n)
        second.push_back(float(n % 7));
    std::sort(second.begin(), second.end());
    EXPECT_EQ(tree.getValue(Coord(3)), Vec3s(1.0f, second[255], 5.0f));
}

TEST(PruneRules, BoolAndMaskTreesPruneExactly) {
    BoolTree boolTree(false);
    boolTree.touchLeaf(Coord(0))->fill(true, true);
    boolTree.touchLeaf(Coord(8, 0, 0))->fill(true, false);
    boolTree.touchLeaf(Coord(16, 0, 0))->fill(false, false);
    auto* mixed = boolTree.touchLeaf(Coord(24, 0, 0));
    mixed->fill(true, true);
    mixed->setValueOnly(Index(7), false);
    tools::prune(boolTree);
    EXPECT_EQ(boolTree.leafCount(), 1u);
    EXPECT_TRUE(boolTree.getValue(Coord(3)) && boolTree.isValueOn(Coord(3)));
    EXPECT_TRUE(boolTree.getValue(Coord(9, 1, 1)) && !boolTree.isValueOn(Coord(9, 1, 1)));
    EXPECT_FALSE(boolTree.getValue(Coord(17, 1, 1)));
    EXPECT_FALSE(boolTree.getValue(Coord(24, 0, 7)));

    MaskTree mask;
    mask.touchLeaf(Coord(0))->fill(true, true);
    mask.touchLeaf(Coord(-8))->fill(false, false);
    mask.setValueOn(Coord(100, 100, 100));
    mask.touchLeaf(Coord(200));  // empty
    tools::prune(mask);
    EXPECT_EQ(mask.leafCount(), 1u);
    EXPECT_EQ(mask.activeVoxelCount(), 513u);
    EXPECT_EQ(mask.activeTileCount(), 1u);
    tools::pruneInactive(mask);
    EXPECT_EQ(mask.leafCount(), 1u);
    EXPECT_EQ(mask.activeVoxelCount(), 513u);
}

TEST(PruneRules, PruneInactiveDropsInactiveBranchesAndRootTiles) {
    FloatTree tree(1.0f);
    tree.setValueOff(Coord(5000, 5000, 5000), 7.0f);  // a branch without active values
    tree.setValueOn(Coord(1, 2, 3), 4.0f);
    tree.setValueOff(Coord(1, 2, 40), 9.0f);  // inactive leaf beside an active one
    tools::pruneInactive(tree);
    EXPECT_EQ(tree.leafCount(), 1u);
    EXPECT_EQ(tree.getValue(Coord(5000, 5000, 5000)), 1.0f);
    EXPECT_EQ(tree.getValue(Coord(1, 2, 40)), 1.0f);
    EXPECT_EQ(tree.getValue(Coord(1, 2, 3)), 4.0f);
    EXPECT_EQ(tree.topNode().entryCount(), 1u);
}

TEST(PruneRules, PruneLevelSetRejectsNegativeOutsideValues) {
    FloatTree tree(-1.0f);
    EXPECT_THROW(tools::pruneLevelSet(tree), ValueError);
    FloatTree ok(1.0f);
    EXPECT_THROW(tools::pruneLevelSet(ok, 1.0f, 0.0f), ValueError);
    EXPECT_THROW(tools::pruneLevelSet(ok, -1.0f, -2.0f), ValueError);
    EXPECT_NO_THROW(tools::pruneLevelSet(ok, 1.0f, -2.0f));
    FloatTree zero(0.0f);  // inside -0 is allowed for a zero background
    zero.setValueOff(Coord(0), -3.0f);
    EXPECT_NO_THROW(tools::pruneLevelSet(zero));
    EXPECT_EQ(zero.leafCount(), 0u);
}

TEST(PruneRules, PruneLevelSetOfIntegerTrees) {
    Int32Tree tree(3);
    tree.setValueOff(Coord(0), -3);
    tree.setValueOff(Coord(300), 3);
    tree.setValueOn(Coord(1000), -1);
    tools::pruneLevelSet(tree);
    EXPECT_EQ(tree.leafCount(), 1u);
    EXPECT_EQ(tree.getValue(Coord(1)), -3);
    EXPECT_EQ(tree.getValue(Coord(301)), 3);
}

}  // namespace
}  // namespace vdb
