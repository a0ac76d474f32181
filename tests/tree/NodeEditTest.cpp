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
#include <random>
#include <set>
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
template <ValueFilter F, typename NodeT>
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
    EXPECT_EQ(visited<ValueFilter::On>(tree.topNode()), on);
    const auto inactive = visited<ValueFilter::Off>(tree.topNode());
    const auto all = visited<ValueFilter::All>(tree.topNode());
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
    tree::forEachTile<ValueFilter::On>(tree.topNode(), [](auto& tile) {
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

// ---- The block visit, the tiles in a box, the level-stopping descent and the node counters,
// on small trees whose every voxel a dense model holds: leaves of 4^3, nodes of 4^3 entries.

using SmallRoot = tree::Tree<
    tree::RootNode<tree::InternalNode<tree::InternalNode<tree::LeafNode<float, 2>, 2>, 2>>>;
using SmallMapRoot = tree::Tree<tree::RootNode<
    tree::InternalNode<tree::InternalNode<tree::LeafNode<float, 2>, 2>, 2>, tree::MapTable>>;
using SmallBounded =
    tree::Tree<tree::InternalNode<tree::InternalNode<tree::LeafNode<float, 2>, 2>, 3>>;

template <typename TreeT>
class BlockVisit : public ::testing::Test {};
using SmallTrees = ::testing::Types<SmallRoot, SmallMapRoot, SmallBounded>;
TYPED_TEST_SUITE(BlockVisit, SmallTrees);

/// Every voxel of a window (a bounded tree's whole domain) as a value and a state.
struct DenseModel {
    CoordBBox window;
    float background;
    std::vector<float> values;
    std::vector<uint8_t> states;

    DenseModel(const CoordBBox& box, float bg)
        : window(box),
          background(bg),
          values(size_t(box.volume()), bg),
          states(size_t(box.volume()), 0) {}
    size_t index(const Coord& p) const {
        const Coord d = p - window.min();
        const Int64 n = window.dim()[1], m = window.dim()[2];
        return size_t((Int64(d[0]) * n + d[1]) * m + d[2]);
    }
    void fill(const CoordBBox& box, float value, bool on) {
        for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
            for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                    values[index(Coord(i, j, k))] = value;
                    states[index(Coord(i, j, k))] = on;
                }
    }
};

/// The edge in voxels of a tile of `level` of TreeT, and its log2.
template <typename TreeT>
Index tileLog2(Index level) {
    Index log2 = 0;
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        ((level == L + 1 ? (log2 = tree::NodeAtLevelT<typename TreeT::TopNodeType, L>::TOTAL, 0)
                         : 0),
         ...);
    }
    (std::make_integer_sequence<Index, TreeT::TopNodeType::LEVEL>{});
    return log2;
}

/// The same random writes to a tree and its model: tiles at every level (some of the
/// background value), boxes that leave tiles and partial leaves, single voxels.
template <typename TreeT>
DenseModel populateSmall(TreeT& tree, uint32_t seed) {
    constexpr Index TOP = TreeT::TopNodeType::LEVEL;
    const CoordBBox window = TreeT::BOUNDED ? TreeT::domain() : CoordBBox(Coord(-64), Coord(63));
    DenseModel model(window, tree.background());
    std::mt19937 rng(seed);
    const auto coord = [&] {
        std::uniform_int_distribution<Int32> c(window.min()[0], window.max()[0]);
        return Coord(c(rng), c(rng), c(rng));
    };
    const auto value = [&] { return rng() % 4 == 0 ? tree.background() : float(rng() % 7); };
    for (int n = 0; n < 40; ++n) {
        const Index level = 1 + Index(rng() % TOP);
        const Index log2 = tileLog2<TreeT>(level);
        const Coord origin = coord().alignedDown(log2);
        const float v = value();
        const bool on = rng() % 2 == 0;
        tree.addTile(level, origin, v, on);
        model.fill(CoordBBox::createCube(origin, Int32(1) << log2), v, on);
        CoordBBox box(coord(), coord());
        box =
            CoordBBox(Coord::minComponent(box.min(), box.max()),
                      Coord::minComponent(Coord::maxComponent(box.min(), box.max()),
                                          Coord::minComponent(box.min(), box.max()).offsetBy(20)));
        const float w = value();
        tree.fill(box, w, !on);
        model.fill(box, w, !on);
        for (int k = 0; k < 30; ++k) {
            const Coord ijk = coord();
            const float x = float(rng() % 5) - 2.0f;
            const bool xOn = rng() % 3 != 0;
            if (xOn)
                tree.setValueOn(ijk, x);
            else
                tree.setValueOff(ijk, x);
            model.fill(CoordBBox(ijk, ijk), x, xOn);
        }
    }
    return model;
}

/// One block as the visit reported it.
template <typename TreeT>
struct Seen {
    Coord origin;
    Index level;
    float value;
    bool active;
    const typename TreeT::LeafNodeType* leaf;
    bool operator==(const Seen&) const = default;
};

template <typename TreeT, ValueFilter F>
std::vector<Seen<TreeT>> visitAll(const TreeT& tree, bool withLeaves) {
    std::vector<Seen<TreeT>> out;
    const auto onTile = [&](const auto& t) {
        EXPECT_EQ(t.dim, Index(1) << tileLog2<TreeT>(t.level));
        out.push_back({t.origin, t.level, t.value, t.active, nullptr});
    };
    if (withLeaves) {
        tree::visitBlocks<F>(tree.topNode(), onTile, [&](const auto& leaf) {
            out.push_back({leaf.origin(), 0, 0, false, &leaf});
        });
    } else {
        tree::visitTiles<F>(tree.topNode(), onTile);
    }
    return out;
}

/// The position of the block at `p` in OpenVDB's iteration order: the root key (x, y, z), or
/// the wrapped slot of a bounded top, then the slot in each internal node below.
template <typename TreeT>
std::vector<Int64> orderKey(const Coord& p) {
    using TopT = typename TreeT::TopNodeType;
    std::vector<Int64> key;
    const auto slot = [&](Index total, Index childTotal) {
        for (int a = 0; a < 3; ++a)
            key.push_back(Int64((uint32_t(p[a]) & ((uint32_t(1) << total) - 1)) >> childTotal));
    };
    if constexpr (TreeT::BOUNDED) {
        slot(TopT::TOTAL, TopT::ChildNodeType::TOTAL);
    } else {
        for (int a = 0; a < 3; ++a)
            key.push_back(Int64(p[a]) >> TopT::ChildNodeType::TOTAL);
    }
    for (Index level = TopT::LEVEL - 1; level >= 1; --level)
        slot(tileLog2<TreeT>(level + 1), tileLog2<TreeT>(level));
    return key;
}

TYPED_TEST(BlockVisit, VisitsEveryBlockOnceInKeyOrderForEachFilter) {
    using TreeT = TypeParam;
    using LeafT = typename TreeT::LeafNodeType;
    for (uint32_t seed : {1u, 2u, 3u}) {
        TreeT tree(-1.0f);
        const DenseModel model = populateSmall(tree, seed);
        const auto all = visitAll<TreeT, ValueFilter::All>(tree, true);
        ASSERT_FALSE(all.empty());
        // Key order, each block once.
        for (size_t i = 1; i < all.size(); ++i)
            ASSERT_LT(orderKey<TreeT>(all[i - 1].origin), orderKey<TreeT>(all[i].origin))
                << all[i - 1].origin << " " << all[i].origin;
        // Together the blocks cover every voxel once, with the model's values and states;
        // under a root, what they leave is background in regions without an entry.
        std::vector<uint8_t> covered(model.values.size(), 0);
        size_t tiles = 0, leaves = 0;
        for (const auto& b : all) {
            const Int32 dim = b.leaf ? Int32(LeafT::DIM) : Int32(1) << tileLog2<TreeT>(b.level);
            ASSERT_EQ(b.origin,
                      b.origin.alignedDown(b.leaf ? LeafT::TOTAL : tileLog2<TreeT>(b.level)));
            const CoordBBox box = CoordBBox::createCube(b.origin, dim);
            ASSERT_TRUE(model.window.isInside(box)) << b.origin;
            (b.leaf ? leaves : tiles) += 1;
            for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
                for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                    for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                        const Coord ijk(i, j, k);
                        const size_t n = model.index(ijk);
                        ++covered[n];
                        const Index m = LeafT::coordToOffset(ijk);
                        const float v = b.leaf ? b.leaf->getValue(m) : b.value;
                        const bool on = b.leaf ? b.leaf->isValueOn(m) : b.active;
                        ASSERT_EQ(v, model.values[n]) << ijk;
                        ASSERT_EQ(on, bool(model.states[n])) << ijk;
                    }
        }
        for (Int32 i = model.window.min()[0]; i <= model.window.max()[0]; ++i)
            for (Int32 j = model.window.min()[1]; j <= model.window.max()[1]; ++j)
                for (Int32 k = model.window.min()[2]; k <= model.window.max()[2]; ++k) {
                    const Coord ijk(i, j, k);
                    const size_t n = model.index(ijk);
                    if (covered[n] == 1)
                        continue;
                    ASSERT_EQ(covered[n], 0) << ijk;
                    ASSERT_FALSE(TreeT::BOUNDED) << ijk;
                    ASSERT_EQ(model.values[n], -1.0f) << ijk;
                    ASSERT_FALSE(model.states[n]) << ijk;
                    if constexpr (!TreeT::BOUNDED) {
                        using TopT = typename TreeT::TopNodeType;
                        ASSERT_EQ(tree.topNode().findEntry(TopT::coordToKey(ijk)), nullptr);
                    }
                }
        EXPECT_GT(tiles, 0u);
        EXPECT_GT(leaves, 0u);
        // The filters select tiles by state and keep every leaf; without leaves, the tiles.
        const auto keep = [&](auto pred) {
            std::vector<Seen<TreeT>> out;
            for (const auto& b : all)
                if (pred(b))
                    out.push_back(b);
            return out;
        };
        const auto on = visitAll<TreeT, ValueFilter::On>(tree, true);
        const auto off = visitAll<TreeT, ValueFilter::Off>(tree, true);
        EXPECT_EQ(on, keep([](const auto& b) { return b.leaf || b.active; }));
        EXPECT_EQ(off, keep([](const auto& b) { return b.leaf || !b.active; }));
        EXPECT_EQ((visitAll<TreeT, ValueFilter::All>(tree, false)),
                  keep([](const auto& b) { return !b.leaf; }));
        EXPECT_EQ((visitAll<TreeT, ValueFilter::On>(tree, false)),
                  keep([](const auto& b) { return !b.leaf && b.active; }));
        EXPECT_EQ((visitAll<TreeT, ValueFilter::Off>(tree, false)),
                  keep([](const auto& b) { return !b.leaf && !b.active; }));

        // The node counters, from the blocks (checked above against the model).
        Index64 active = 0, leafActive = 0, leafInactive = 0, inactive = 0, activeTiles = 0;
        CoordBBox bbox;
        std::set<std::pair<Index, Coord>> nodes;
        for (const auto& b : all) {
            const Index64 volume =
                b.leaf ? LeafT::NUM_VALUES : Index64(1) << (3 * tileLog2<TreeT>(b.level));
            if (b.leaf) {
                leafActive += b.leaf->getValueMask().countOn();
                leafInactive += LeafT::NUM_VALUES - b.leaf->getValueMask().countOn();
            } else if (b.active) {
                active += volume;
                ++activeTiles;
            } else if (b.level < TreeT::TopNodeType::LEVEL || TreeT::BOUNDED ||
                       b.value != tree.background()) {
                inactive += volume;  // a root's background tiles count for nothing
            }
            for (Index l = std::max<Index>(b.level, 1); l < TreeT::TopNodeType::LEVEL; ++l)
                nodes.insert({l, b.origin.alignedDown(tileLog2<TreeT>(l + 1))});
        }
        for (size_t n = 0; n < model.values.size(); ++n) {
            if (model.states[n]) {
                const Int64 x = Int64(n) / (model.window.dim()[1] * model.window.dim()[2]);
                const Int64 y = (Int64(n) / model.window.dim()[2]) % model.window.dim()[1];
                const Int64 z = Int64(n) % model.window.dim()[2];
                bbox.expand(model.window.min().offsetBy(Int32(x), Int32(y), Int32(z)));
            }
        }
        const Index64 modelActive =
            Index64(std::count(model.states.begin(), model.states.end(), 1));
        EXPECT_EQ(tree.activeVoxelCount(), modelActive);
        EXPECT_EQ(active + leafActive, modelActive);
        EXPECT_EQ(tree.activeLeafVoxelCount(), leafActive);
        EXPECT_EQ(tree.inactiveLeafVoxelCount(), leafInactive);
        EXPECT_EQ(tree.inactiveVoxelCount(), inactive + leafInactive);
        EXPECT_EQ(tree.activeTileCount(), activeTiles);
        EXPECT_EQ(tree.leafCount(), leaves);
        EXPECT_EQ(tree.nonLeafCount(), nodes.size() + 1);
        CoordBBox evaluated;
        tree.evalActiveVoxelBoundingBox(evaluated);
        EXPECT_EQ(evaluated, bbox);
    }
}

TYPED_TEST(BlockVisit, TilesInABoxCoverWhatNoLeafHolds) {
    using TreeT = TypeParam;
    TreeT tree(-1.0f);
    const DenseModel model = populateSmall(tree, 7);
    std::mt19937 rng(11);
    std::uniform_int_distribution<Int32> c(model.window.min()[0], model.window.max()[0] - 24);
    for (int n = 0; n < 60; ++n) {
        const Coord lo(c(rng), c(rng), c(rng));
        const CoordBBox box(lo,
                            lo.offsetBy(Int32(rng() % 24), Int32(rng() % 3), Int32(rng() % 24)));
        std::map<Coord, int> covered;
        tree::forEachTileIn(tree.topNode(), box, [&](const CoordBBox& part, float value) {
            ASSERT_TRUE(box.isInside(part));
            for (Int32 i = part.min()[0]; i <= part.max()[0]; ++i)
                for (Int32 j = part.min()[1]; j <= part.max()[1]; ++j)
                    for (Int32 k = part.min()[2]; k <= part.max()[2]; ++k) {
                        ++covered[Coord(i, j, k)];
                        ASSERT_EQ(value, model.values[model.index(Coord(i, j, k))]);
                    }
        });
        for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
            for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                    const Coord ijk(i, j, k);
                    const bool inLeaf = tree.probeConstLeaf(ijk) != nullptr;
                    const auto it = covered.find(ijk);
                    ASSERT_EQ(it == covered.end() ? 0 : it->second, inLeaf ? 0 : 1) << ijk;
                }
    }
}

TYPED_TEST(BlockVisit, DescentStopsAtTheLevelAskedFor) {
    using TreeT = TypeParam;
    using TopT = typename TreeT::TopNodeType;
    constexpr Index TOP = TopT::LEVEL;
    TreeT tree(-1.0f);
    const DenseModel model = populateSmall(tree, 5);
    // The level that stores each voxel, from the blocks (checked against the model above).
    std::vector<uint8_t> stored(model.values.size(), uint8_t(TOP));
    for (const auto& b : visitAll<TreeT, ValueFilter::All>(tree, true)) {
        const Int32 dim =
            b.leaf ? Int32(TreeT::LeafNodeType::DIM) : Int32(1) << tileLog2<TreeT>(b.level);
        const CoordBBox box = CoordBBox::createCube(b.origin, dim);
        for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
            for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                    stored[model.index(Coord(i, j, k))] = uint8_t(b.level);
    }
    tree::ValueAccessor<const TreeT> acc(tree);
    const auto check = [&]<Index L>(const Coord& ijk, Index level, float value) {
        using NodeT = tree::NodeAtLevelT<TopT, L>;
        using Op = tree::ops::ProbeNode<NodeT>;
        float v = 99.0f, w = 99.0f;
        const NodeT* a = tree.template get<Op>(ijk, v);
        const NodeT* b = acc.template get<Op>(ijk, w);
        ASSERT_EQ(a, b) << ijk << " level " << L;
        ASSERT_EQ(a == nullptr, L < level) << ijk << " level " << L;
        if (a) {
            if constexpr (L < TOP) {
                ASSERT_EQ(a->origin(), ijk.alignedDown(NodeT::TOTAL));
            }
            ASSERT_EQ(v, 99.0f);
        } else {
            ASSERT_EQ(v, value) << ijk;
            ASSERT_EQ(w, value) << ijk;
        }
        ASSERT_EQ(tree.template get<Op>(ijk), a);
    };
    for (Int32 i = model.window.min()[0]; i <= model.window.max()[0]; i += 3)
        for (Int32 j = model.window.min()[1]; j <= model.window.max()[1]; j += 2)
            for (Int32 k = model.window.min()[2]; k <= model.window.max()[2]; ++k) {
                const Coord ijk(i, j, k);
                const size_t n = model.index(ijk);
                [&]<Index... L>(std::integer_sequence<Index, L...>) {
                    (check.template operator()<L>(ijk, stored[n], model.values[n]), ...);
                }
                (std::make_integer_sequence<Index, TOP + 1>{});
            }
    ASSERT_EQ(
        tree.template get<tree::ops::ProbeNode<typename TreeT::LeafNodeType>>(Coord(-60, 5, 3)),
        tree.probeConstLeaf(Coord(-60, 5, 3)));
    if constexpr (TreeT::BOUNDED) {
        // Outside the domain: no node, the background.
        float v = 0.0f;
        const Coord outside = TreeT::domain().max().offsetBy(1);
        EXPECT_EQ(tree.template get<tree::ops::ProbeNode<TopT>>(outside, v), nullptr);
        EXPECT_EQ(v, -1.0f);
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
