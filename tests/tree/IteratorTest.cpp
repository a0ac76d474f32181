// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels, filled by the same
// seeded workload as the tree; tile sizes come from the configuration's hand-written shape.

#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <tuple>
#include <unordered_set>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class TreeIterator : public ::testing::Test {
protected:
    using TreeT = typename C::TreeType;
    static constexpr float kBackground = -0.5f;

    // Fills `tree` and `model` with a small seeded workload that leaves voxels, active and
    // inactive tiles, and inactive non-background values, in all octants.
    static void populate(TreeT& tree, test::SparseVolumeModel<float>& model, uint32_t seed) {
        test::WorkloadOptions options;
        options.seed = seed;
        options.batches = 2;
        options.opsPerBatch = 6000;
        options.checkInactiveValues = false;
        options.checkCopy = false;
        options.pruneOrClearRate = 1e-4;
        test::TreeModelDriver<TreeT, tree::ValueAccessor<TreeT>, tree::ValueAccessor<const TreeT>>
            driver(tree, C::shape(), options, {kBackground, 0.0f, 1.0f, 2.0f, 3.0f});
        ASSERT_TRUE(driver.run());
        model = driver.model();
    }
};
using Configs =
    ::testing::Types<HashTree543, MapTree432, FixedTree643, FixedTree6542, FixedTree3333>;
TYPED_TEST_SUITE(TreeIterator, Configs, test::ConfigName);

TYPED_TEST(TreeIterator, EmptyTreeHasNoActiveValuesAndNoLeaves) {
    using TreeT = typename TestFixture::TreeT;
    const TreeT tree(TestFixture::kBackground);
    EXPECT_FALSE(tree.cbeginValueOn());
    EXPECT_FALSE(tree.cbeginLeaf());
    const test::SparseVolumeModel<float> model(TestFixture::kBackground);
    // Unbounded: nothing at all. Bounded: the top node's background tiles tile the domain.
    EXPECT_EQ(bool(tree.cbeginValueOff()), TreeT::BOUNDED);
    EXPECT_EQ(bool(tree.cbeginValueAll()), TreeT::BOUNDED);
    EXPECT_TRUE(test::compareInactiveValues(tree, model, TypeParam::shape()));
    if constexpr (TreeT::BOUNDED) {
        Index64 items = 0;
        for (auto it = tree.cbeginValueAll(); it; ++it, ++items) {
            ASSERT_EQ(it.getLevel(), TypeParam::shape().topLevel()) << it.getCoord();
            ASSERT_EQ(*it, TestFixture::kBackground) << it.getCoord();
        }
        EXPECT_EQ(items, tree.topNode().NUM_VALUES);
    }
}

TYPED_TEST(TreeIterator, ValueIteratorsVisitModelSetExactlyOnce) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(TestFixture::kBackground);
    test::SparseVolumeModel<float> model(TestFixture::kBackground);
    TestFixture::populate(tree, model, 7);
    ASSERT_GT(tree.activeTileCount(), 0u) << "the workload should leave active tiles";
    EXPECT_TRUE(test::compareActiveValues(tree, model, TypeParam::shape()));
    EXPECT_TRUE(test::compareInactiveValues(tree, model, TypeParam::shape()));
    EXPECT_TRUE(test::compareLeaves(tree, TypeParam::shape()));
}

// The non-const iterators visit the same items, in the same order, as the const ones.
TYPED_TEST(TreeIterator, NonConstIteratorsVisitSameSequenceAsConstIterators) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(TestFixture::kBackground);
    test::SparseVolumeModel<float> model(TestFixture::kBackground);
    TestFixture::populate(tree, model, 11);
    using Item = std::tuple<Coord, Index, float, bool>;
    auto collect = [](auto it) {
        std::vector<Item> items;
        for (; it; ++it)
            items.emplace_back(it.getCoord(), it.getLevel(), *it, it.isValueOn());
        return items;
    };
    const TreeT& constTree = tree;
    EXPECT_EQ(collect(tree.beginValueOn()), collect(constTree.cbeginValueOn()));
    EXPECT_EQ(collect(tree.beginValueOn()), collect(constTree.beginValueOn()));
    EXPECT_EQ(collect(tree.beginValueOff()), collect(constTree.cbeginValueOff()));
    EXPECT_EQ(collect(tree.beginValueAll()), collect(constTree.cbeginValueAll()));
    std::vector<Coord> leaves, constLeaves;
    for (auto it = tree.beginLeaf(); it; ++it)
        leaves.push_back(it->origin());
    for (const auto& leaf : constTree.leaves())
        constLeaves.push_back(leaf.origin());
    EXPECT_EQ(leaves, constLeaves);
    EXPECT_EQ(leaves.size(), tree.leafCount());
}

TYPED_TEST(TreeIterator, SetValueThroughValueOnIteratorChangesEveryActiveVoxelAndTile) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(TestFixture::kBackground);
    test::SparseVolumeModel<float> model(TestFixture::kBackground);
    TestFixture::populate(tree, model, 13);
    const Index64 before = tree.activeVoxelCount();
    for (auto it = tree.beginValueOn(); it; ++it) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        const float value = *it + 10.0f * float(it.getLevel() + 1);
        it.setValue(value);
        model.fill(bbox, value, true);
    }
    EXPECT_EQ(tree.activeVoxelCount(), before);
    EXPECT_TRUE(test::compareActiveValues(tree, model, TypeParam::shape()));
    EXPECT_TRUE(test::compareStoredValues(tree, model));
    EXPECT_TRUE(test::compareInactiveValues(tree, model, TypeParam::shape()));
}

// Inactive voxels in leaves, and inactive tiles that do not hold the background, are changed
// through the ValueOff and ValueAll iterators; active values are untouched.
TYPED_TEST(TreeIterator, SetValueThroughValueOffAndValueAllIteratorsKeepsStates) {
    using TreeT = typename TestFixture::TreeT;
    const float bg = TestFixture::kBackground;
    TreeT tree(bg);
    test::SparseVolumeModel<float> model(bg);
    TestFixture::populate(tree, model, 17);
    for (auto it = tree.beginValueOff(); it; ++it) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        if (it.isTileValue() && *it == bg)
            continue;  // background regions stay background
        it.setValue(*it + 100.0f);
        model.fill(bbox, *it, false);
    }
    for (auto it = tree.beginValueAll(); it; ++it) {
        if (!it.isVoxelValue())
            continue;
        const float value = *it * 2.0f;
        it.setValue(value);
        if (it.isValueOn()) {
            model.setValue(it.getCoord(), value);
        } else {
            model.setValueOff(it.getCoord(), value);
        }
    }
    EXPECT_TRUE(test::compareActiveValues(tree, model, TypeParam::shape()));
    EXPECT_TRUE(test::compareStoredValues(tree, model));
    EXPECT_TRUE(test::compareInactiveValues(tree, model, TypeParam::shape()));
}

// Hand-made tiles at every level below the top, around the origin (negative coordinates
// included), each reported once with its level and its whole region.
TYPED_TEST(TreeIterator, TilesAreReportedWithTheirLevelAndRegion) {
    using TreeT = typename TestFixture::TreeT;
    const test::TreeShape shape = TypeParam::shape();
    TreeT tree(TestFixture::kBackground);
    std::set<std::tuple<Index, Coord, Coord>> expected;  // level, bbox min, bbox max
    for (Index level = 1; level <= shape.topLevel(); ++level) {
        const Index log2 = shape.tileLog2(level);
        if (log2 > 20)
            break;  // keeps the regions disjoint and the expected counts small
        const Int32 dim = Int32(1) << log2;
        // One tile per level, each in its own octant-straddling corner.
        const Coord origin = level % 2 ? Coord(-dim, -dim, dim * 2) : Coord(dim * 4, -dim, -dim);
        const CoordBBox box = CoordBBox::createCube(origin, dim);
        if (!shape.domain().isInside(box))
            continue;
        tree.fill(box, float(level), level % 3 != 0);
        expected.emplace(level, box.min(), box.max());
    }
    // And one voxel next to the origin, in the negative octant.
    tree.setValueOff(Coord(-1, -1, -1), 42.0f);
    std::set<std::tuple<Index, Coord, Coord>> visited;
    for (auto it = tree.cbeginValueAll(); it; ++it) {
        if (*it == TestFixture::kBackground)
            continue;
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        EXPECT_TRUE(visited.emplace(it.getLevel(), bbox.min(), bbox.max()).second)
            << "visited twice: " << bbox;
        if (it.isVoxelValue()) {
            EXPECT_EQ(it.getCoord(), Coord(-1, -1, -1));
            EXPECT_EQ(*it, 42.0f);
            EXPECT_FALSE(it.isValueOn());
        } else {
            EXPECT_EQ(*it, float(it.getLevel())) << bbox;
            EXPECT_EQ(it.isValueOn(), it.getLevel() % 3 != 0) << bbox;
            EXPECT_EQ(it.getCoord(), bbox.min());
        }
    }
    expected.emplace(0, Coord(-1, -1, -1), Coord(-1, -1, -1));
    EXPECT_EQ(visited, expected);
}

TYPED_TEST(TreeIterator, LeafIteratorVisitsEveryLeafHoldingAnActiveVoxelOnce) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(TestFixture::kBackground);
    test::SparseVolumeModel<float> model(TestFixture::kBackground);
    TestFixture::populate(tree, model, 19);
    std::unordered_set<Coord, test::CoordHash> origins;
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        ASSERT_TRUE(origins.insert(it->origin()).second) << "leaf " << it->origin() << " twice";
    }
    EXPECT_EQ(origins.size(), tree.leafCount());
    EXPECT_TRUE(test::compareLeaves(tree, TypeParam::shape()));
    // The active tiles, listed once (searching the tree per voxel is quadratic).
    std::vector<CoordBBox> activeTiles;
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        if (!it.isTileValue())
            continue;
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        activeTiles.push_back(bbox);
    }
    model.forEach([&](const Coord& ijk, float, bool active) {
        if (!active)
            return;
        const auto* leaf = tree.probeConstLeaf(ijk);
        if (leaf == nullptr) {
            // Then the voxel lies in a tile.
            for (const CoordBBox& bbox : activeTiles) {
                if (bbox.isInside(ijk))
                    return;
            }
            ADD_FAILURE() << "active voxel " << ijk << " is in neither a leaf nor a tile";
            return;
        }
        EXPECT_TRUE(origins.count(leaf->origin())) << "leaf of " << ijk << " not visited";
    });
}

TYPED_TEST(TreeIterator, WritingThroughLeafIteratorChangesTreeValues) {
    using TreeT = typename TestFixture::TreeT;
    TreeT tree(TestFixture::kBackground);
    test::SparseVolumeModel<float> model(TestFixture::kBackground);
    TestFixture::populate(tree, model, 23);
    for (auto& leaf : tree.leaves()) {
        for (auto it = leaf.beginValueOn(); it; ++it) {
            const float value = float(it.pos() % 7);
            it.setValue(value);
            model.setValue(it.getCoord(), value);
        }
    }
    EXPECT_TRUE(test::compareActiveValues(tree, model, TypeParam::shape()));
    EXPECT_TRUE(test::compareStoredValues(tree, model));
}

TEST(TreeIterator, SingleNegativeVoxelIsVisitedWithItsLeaf) {
    FloatTree tree(0.0f);
    tree.setValue(Coord(-1, -2, -3), 5.0f);
    int n = 0;
    for (auto it = tree.cbeginValueOn(); it; ++it, ++n) {
        EXPECT_EQ(it.getCoord(), Coord(-1, -2, -3));
        EXPECT_TRUE(it.isVoxelValue());
        EXPECT_EQ(*it, 5.0f);
    }
    EXPECT_EQ(n, 1);
    n = 0;
    for (const auto& leaf : tree.leaves()) {
        EXPECT_EQ(leaf.origin(), Coord(-8, -8, -8));
        ++n;
    }
    EXPECT_EQ(n, 1);
    // Off visits the other 511 voxels of the leaf and the inactive tiles of the two internal
    // nodes above it: 32^3 - 1 and 16^3 - 1.
    Index64 voxels = 0, tiles = 0;
    for (auto it = tree.cbeginValueOff(); it; ++it)
        (it.isVoxelValue() ? voxels : tiles) += 1;
    EXPECT_EQ(voxels, 511u);
    EXPECT_EQ(tiles, 32u * 32u * 32u - 1u + 16u * 16u * 16u - 1u);
}

}  // namespace
}  // namespace vdb
