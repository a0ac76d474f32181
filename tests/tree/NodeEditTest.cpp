// SPDX-License-Identifier: Apache-2.0
// The node-editing primitives of tree/NodeEdit.h and the read operations of tree/AccessOps.h,
// on a root-topped and on bounded trees. Oracle: SparseVolumeModel (a hash map of voxels) for
// what the edits leave in the tree, and the list of tiles written for what forEachTile visits.

#include <vdb/tree/AccessOps.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/RootTable.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <VoxelChecks.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <tuple>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class NodeEdit : public ::testing::Test {};
using Configs = ::testing::Types<HashTree543, MapTree432, FixedTree6543, FixedTree643>;
TYPED_TEST_SUITE(NodeEdit, Configs, test::ConfigName);

/// Every voxel of `box` reads as the model says.
template <typename TreeT>
void expectBox(const TreeT& tree, const test::SparseVolumeModel<float>& model,
               const CoordBBox& box) {
    test::expectVoxels(tree, box, [&](const Coord& ijk) {
        return std::pair(model.getValue(ijk), model.isValueOn(ijk));
    });
}

using TileKey = std::tuple<Coord, float, bool>;

/// The tiles of the top node as forEachTile<F> reports them, sorted.
template <tree::TileFilter F, typename NodeT>
std::vector<TileKey> visited(const NodeT& node) {
    std::vector<TileKey> out;
    tree::forEachTile<F>(
        node, [&](const auto& tile) { out.emplace_back(tile.origin, tile.value, tile.active); });
    std::sort(out.begin(), out.end());
    return out;
}

TYPED_TEST(NodeEdit, ForEachTileVisitsExactlyTheTopTilesOfEachState) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    constexpr Int32 dim = Int32(TopT::ChildNodeType::DIM);
    TreeT tree(-1.0f);
    // Top-level tiles at four regions, two on and two off, a child in a fifth.
    const std::vector<TileKey> written = {{Coord(0, 0, 0), 1.0f, true},
                                          {Coord(dim, 0, 0), 2.0f, false},
                                          {Coord(0, -dim, 0), 3.0f, true},
                                          {Coord(-dim, 0, dim), 4.0f, false}};
    for (const auto& [origin, value, on] : written)
        tree.addTile(TopT::LEVEL, origin, value, on);
    tree.setValue(Coord(-dim, -dim, -dim), 5.0f);

    std::vector<TileKey> on, off;
    for (const auto& t : written)
        (std::get<2>(t) ? on : off).push_back(t);
    std::sort(on.begin(), on.end());
    std::sort(off.begin(), off.end());
    EXPECT_EQ(visited<tree::TileFilter::Active>(tree.topNode()), on);
    const auto inactive = visited<tree::TileFilter::Inactive>(tree.topNode());
    const auto all = visited<tree::TileFilter::All>(tree.topNode());
    if constexpr (TreeT::BOUNDED) {
        // Every other slot of a bounded top is an inactive background tile.
        const size_t slots = TopT::NUM_VALUES - 1;  // one slot holds the child
        EXPECT_EQ(all.size(), slots);
        EXPECT_EQ(inactive.size(), slots - on.size());
        for (const auto& t : off)
            EXPECT_TRUE(std::binary_search(inactive.begin(), inactive.end(), t));
        for (const auto& t : inactive) {
            const bool written_ = std::binary_search(off.begin(), off.end(), t);
            EXPECT_TRUE(written_ || (std::get<1>(t) == -1.0f && !std::get<2>(t)));
        }
    } else {
        EXPECT_EQ(inactive, off);
        std::vector<TileKey> both = written;
        std::sort(both.begin(), both.end());
        EXPECT_EQ(all, both);
    }
    size_t children = 0;
    tree::forEachChild(tree.topNode(), [&](const auto& child) {
        ++children;
        EXPECT_EQ(child.origin(), Coord(-dim, -dim, -dim));
    });
    EXPECT_EQ(children, 1u);
    EXPECT_EQ(tree::childCount(tree.topNode()), 1u);
}

TYPED_TEST(NodeEdit, ForEachTileStoresChangedValuesAndStates) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    constexpr Int32 dim = Int32(TopT::ChildNodeType::DIM);
    TreeT tree(0.0f);
    tree.addTile(TopT::LEVEL, Coord(0), 1.0f, true);
    tree.addTile(TopT::LEVEL, Coord(dim, 0, 0), 2.0f, false);
    tree.setValue(Coord(3 * dim, 1, 2), 7.0f);
    tree::forEachTile<tree::TileFilter::Active>(tree.topNode(), [](auto& tile) {
        tile.value += 10.0f;
        tile.active = false;
    });
    tree::forEachTile(tree.topNode(), [&](auto& tile) {
        if (tile.origin == Coord(dim, 0, 0)) {
            tile.value = 20.0f;
            tile.active = true;
        }
    });
    EXPECT_EQ(tree.getValue(Coord(5, 6, 7)), 11.0f);
    EXPECT_FALSE(tree.isValueOn(Coord(5, 6, 7)));
    EXPECT_EQ(tree.getValue(Coord(dim + 5, 6, 7)), 20.0f);
    EXPECT_TRUE(tree.isValueOn(Coord(dim + 5, 6, 7)));
    EXPECT_EQ(tree.getValue(Coord(3 * dim, 1, 2)), 7.0f);  // the child is untouched
    EXPECT_EQ(tree.activeVoxelCount(), Index64(dim) * dim * dim + 1);
}

TYPED_TEST(NodeEdit, TouchChildSplitsATileWithoutChangingAVoxel) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    using ChildT = typename TopT::ChildNodeType;
    constexpr Int32 dim = Int32(ChildT::DIM);
    TreeT tree(-2.0f);
    test::SparseVolumeModel<float> model(-2.0f);
    tree.addTile(TopT::LEVEL, Coord(0), 4.0f, true);
    const CoordBBox tile = CoordBBox::createCube(Coord(0), dim);
    const CoordBBox window(Coord(-3), Coord(12));
    CoordBBox inside = tile;
    inside.intersect(window);
    model.fill(inside, 4.0f, true);

    ChildT& a = tree::touchChild(tree.topNode(), Coord(1, 2, 3));
    ChildT& b = tree::touchChild(tree.topNode(), Coord(dim - 1, 0, 5));
    EXPECT_EQ(&a, &b);
    EXPECT_EQ(a.origin(), Coord(0));
    EXPECT_EQ(tree::probeChild(tree.topNode(), Coord(4)), &a);
    expectBox(tree, model, window);
    EXPECT_EQ(tree.activeVoxelCount(), Index64(dim) * dim * dim);

    // Where no node stores anything, the new child holds the background, inactive.
    ChildT& c = tree::touchChild(tree.topNode(), Coord(-1, -1, -1));
    EXPECT_EQ(c.origin(), Coord(-dim));
    expectBox(tree, model, window);
    EXPECT_EQ(tree.activeVoxelCount(), Index64(dim) * dim * dim);
}

TYPED_TEST(NodeEdit, AddLeafSetTileAndClearRegionChangeOnlyTheirRegion) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    constexpr Int32 dim = Int32(TopT::ChildNodeType::DIM);
    constexpr Int32 leafDim = Int32(LeafT::DIM);
    TreeT tree(0.5f);
    test::SparseVolumeModel<float> model(0.5f);
    const CoordBBox window(Coord(-2 * leafDim), Coord(3 * leafDim));

    // A leaf under an active tile: the tile's other regions keep its value and state.
    tree.addTile(TopT::LEVEL, Coord(0), 3.0f, true);
    CoordBBox tileBox = CoordBBox::createCube(Coord(0), dim);
    tileBox.intersect(window);
    model.fill(tileBox, 3.0f, true);
    auto leaf = std::make_unique<LeafT>(Coord(leafDim, 0, 0), 9.0f, false);
    leaf->setValueOn(Index(5), 8.0f);
    bool replaced = true;
    LeafT& linked = tree::addLeaf(tree.topNode(), std::move(leaf), &replaced);
    EXPECT_FALSE(replaced);
    model.fill(CoordBBox::createCube(Coord(leafDim, 0, 0), leafDim), 9.0f, false);
    model.setValueOn(linked.offsetToGlobalCoord(5), 8.0f);
    tree.clearAllAccessors();
    expectBox(tree, model, window);

    // The same origin again replaces it.
    tree::addLeaf(tree.topNode(), std::make_unique<LeafT>(Coord(leafDim, 0, 0), 1.0f, true),
                  &replaced);
    EXPECT_TRUE(replaced);
    model.fill(CoordBBox::createCube(Coord(leafDim, 0, 0), leafDim), 1.0f, true);
    tree.clearAllAccessors();
    expectBox(tree, model, window);

    // A tile over the branch frees it.
    EXPECT_TRUE(tree::setTile(tree.topNode(), Coord(2), 6.0f, false));
    EXPECT_FALSE(tree::setTile(tree.topNode(), Coord(2), 6.5f, false));
    model.fill(tileBox, 6.5f, false);
    tree.clearAllAccessors();
    expectBox(tree, model, window);

    // Clearing a region leaves the background, inactive; a root keeps no entry for it.
    tree.setValue(Coord(-1), 2.0f);
    EXPECT_TRUE(tree::clearRegion(tree.topNode(), Coord(-1), tree.background()));
    EXPECT_FALSE(tree::clearRegion(tree.topNode(), Coord(0), tree.background()));
    tree.clearAllAccessors();
    model.fill(tileBox, 0.5f, false);
    model.setValueOff(Coord(-1), 0.5f);
    expectBox(tree, model, window);
    if constexpr (!TreeT::BOUNDED) {
        EXPECT_TRUE(tree.topNode().empty());
    }
    EXPECT_EQ(tree.leafCount(), 0u);
}

/// A user's read operation: one walk, the sign of the value.
struct IsNegative {
    template <typename LeafT>
    static bool leaf(const LeafT& leaf, Index n) {
        return leaf.getValue(n) < 0;
    }
    static bool tile(float value, bool) { return value < 0; }
};

/// A read operation with an argument: the value, or `fallback` where it is inactive.
struct ValueOr {
    template <typename LeafT>
    static float leaf(const LeafT& leaf, Index n, float fallback) {
        return leaf.isValueOn(n) ? leaf.getValue(n) : fallback;
    }
    static float tile(float value, bool active, float fallback) {
        return active ? value : fallback;
    }
};

TYPED_TEST(NodeEdit, UserReadOperationsAgreeWithTheModelThroughEveryPath) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    constexpr Int32 dim = Int32(TopT::ChildNodeType::DIM);
    TreeT tree(1.0f);
    test::SparseVolumeModel<float> model(1.0f);
    const CoordBBox window(Coord(-12), Coord(12));
    tree.addTile(TopT::LEVEL, Coord(0), -2.0f, true);
    CoordBBox tileBox = CoordBBox::createCube(Coord(0), dim);
    tileBox.intersect(window);
    model.fill(tileBox, -2.0f, true);
    for (Int32 i = -10; i <= 10; i += 3) {
        const float v = float(i) - 0.5f;
        tree.setValueOff(Coord(i, -i, i / 2), v);
        model.setValueOff(Coord(i, -i, i / 2), v);
        tree.setValue(Coord(-i, i / 3, 7), v + 100.0f);
        model.setValue(Coord(-i, i / 3, 7), v + 100.0f);
    }
    tree::ValueAccessor<const TreeT> acc(tree);
    for (Int32 i = window.min()[0]; i <= window.max()[0]; ++i)
        for (Int32 j = window.min()[1]; j <= window.max()[1]; ++j)
            for (Int32 k = window.min()[2]; k <= window.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                const float v = model.getValue(ijk);
                const bool on = model.isValueOn(ijk);
                ASSERT_EQ(tree.template get<IsNegative>(ijk), v < 0) << ijk;
                ASSERT_EQ(acc.template get<IsNegative>(ijk), v < 0) << ijk;
                ASSERT_EQ(tree.template get<ValueOr>(ijk, 42.0f), on ? v : 42.0f) << ijk;
                ASSERT_EQ(acc.template get<ValueOr>(ijk, 42.0f), on ? v : 42.0f) << ijk;
                float probed = 0;
                ASSERT_EQ(acc.template get<tree::ops::ProbeValue>(ijk, probed), on) << ijk;
                ASSERT_EQ(probed, v) << ijk;
                ASSERT_EQ(acc.probeConstLeaf(ijk), tree.probeConstLeaf(ijk)) << ijk;
            }
    // Outside a bounded tree's domain the operations see the background, inactive.
    if constexpr (TreeT::BOUNDED) {
        const Coord outside = TreeT::domain().max().offsetBy(1);
        EXPECT_EQ(tree.template get<ValueOr>(outside, 42.0f), 42.0f);
        EXPECT_EQ(acc.template get<ValueOr>(outside, 42.0f), 42.0f);
        EXPECT_FALSE(acc.template get<IsNegative>(outside));
        EXPECT_EQ(acc.probeConstLeaf(outside), nullptr);
    }
}

TEST(RootTable, InsertingAPresentKeyNeverGrowsTheTable) {
    // Pointers into the table and cursors stay valid while entries change in place, which
    // forEachTile's write-back and the tools rely on. 64 keys fill half of 128 slots, the
    // most the table holds before it grows.
    tree::detail::RootTable<int, 3, tree::HashTable> table;
    for (Int32 i = 0; i < 64; ++i)
        table.insert(Coord(i * 8, 0, 0)) = i;
    const Index64 bytes = table.memUsage();
    for (int round = 1; round <= 3; ++round) {
        std::map<Coord, int> seen;
        for (auto c = table.begin(); table.valid(c); table.next(c)) {
            const Coord key = table.key(c);
            table.insert(key) = key[0] / 8 + 100 * round;
            seen[key] = table.entry(c);
        }
        ASSERT_EQ(seen.size(), 64u);
        EXPECT_EQ(table.memUsage(), bytes);
        for (const auto& [key, value] : seen)
            EXPECT_EQ(value, key[0] / 8 + 100 * round);
    }
}

}  // namespace
}  // namespace vdb
