// SPDX-License-Identifier: Apache-2.0
// Oracles: nested-index arithmetic for internal-node offsets, std::map for the root tables,
// SparseVolumeModel (tests/support/Oracles.h) for trees, and counts of distinct node regions
// (computed from the hand-written node sizes) for the tree statistics.

#include <vdb/tree/InternalNode.h>
#include <vdb/tree/LeafNode.h>
#include <vdb/tree/RootNode.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

using Leaf8 = tree::LeafNode<float, 3>;
using Node16 = tree::InternalNode<Leaf8, 4>;  // 16^3 children of 8^3 voxels: 128^3 voxels

// ---- InternalNode -----------------------------------------------------------------------------

TEST(InternalNode, OffsetsFollowNestedArrayOrderAndInvert) {
    const Coord origin(-128, 256, 0);
    const Node16 node(origin.offsetBy(5, 6, 7), 1.0f);
    EXPECT_EQ(node.origin(), origin);
    EXPECT_EQ(Node16::DIM, 128u);
    EXPECT_EQ(Node16::NUM_VALUES, 4096u);
    EXPECT_EQ(Node16::LEVEL, 1u);
    for (Int32 i = 0; i < 16; ++i) {
        for (Int32 j = 0; j < 16; ++j) {
            for (Int32 k = 0; k < 16; ++k) {
                const Coord child = origin.offsetBy(8 * i, 8 * j, 8 * k);
                const Index n = Index((i * 16 + j) * 16 + k);
                ASSERT_EQ(Node16::coordToOffset(child), n) << child;
                ASSERT_EQ(Node16::coordToOffset(child.offsetBy(7, 3, 1)), n) << child;
                ASSERT_EQ(node.offsetToGlobalCoord(n), child) << n;
            }
        }
    }
    EXPECT_TRUE(node.contains(origin));
    EXPECT_TRUE(node.contains(origin.offsetBy(127)));
    EXPECT_FALSE(node.contains(origin.offsetBy(-1, 0, 0)));
    EXPECT_FALSE(node.contains(origin.offsetBy(0, 128, 0)));
}

// contains() must not overflow for coordinates far from the node (UBSan checks this).
TEST(InternalNode, ContainsIsFalseForExtremeCoordinates) {
    constexpr Int32 lo = std::numeric_limits<Int32>::min();
    constexpr Int32 hi = std::numeric_limits<Int32>::max();
    const Node16 negative(Coord(-128), 0.0f);
    const Node16 positive(Coord(128), 0.0f);
    EXPECT_FALSE(negative.contains(Coord(hi)));
    EXPECT_FALSE(negative.contains(Coord(hi, -1, -1)));
    EXPECT_FALSE(positive.contains(Coord(lo)));
    EXPECT_FALSE(positive.contains(Coord(lo, 200, 200)));
}

// The top of a bounded tree covers [-DIM/2, DIM/2) and still maps offsets from global bits.
TEST(InternalNode, CenteredNodeMapsEveryChildOfItsDomain) {
    const Node16 node(tree::CenteredDomain{}, 2.0f);
    EXPECT_EQ(node.origin(), Coord(-64));
    std::set<Index> offsets;
    for (Int32 x = -64; x < 64; x += 8) {
        for (Int32 y = -64; y < 64; y += 8) {
            for (Int32 z = -64; z < 64; z += 8) {
                const Coord child(x, y, z);
                const Index n = Node16::coordToOffset(child);
                ASSERT_LT(n, Node16::NUM_VALUES);
                ASSERT_TRUE(offsets.insert(n).second) << "two children share offset " << n;
                ASSERT_EQ(node.offsetToGlobalCoord(n), child) << n;
                ASSERT_TRUE(node.contains(child.offsetBy(7))) << child;
            }
        }
    }
    EXPECT_FALSE(node.contains(Coord(64, 0, 0)));
    EXPECT_FALSE(node.contains(Coord(0, -65, 0)));
    EXPECT_EQ(node.getValue(Coord(-64, 63, 5)), 2.0f);
}

TEST(InternalNode, TilesAndChildrenAnswerLookupsAndCounts) {
    Node16 node(Coord(0), -1.0f, false);
    EXPECT_EQ(node.getValue(Coord(5, 6, 7)), -1.0f);
    EXPECT_EQ(node.leafCount(), 0u);
    EXPECT_EQ(node.nonLeafCount(), 1u);
    EXPECT_EQ(node.onVoxelCount(), 0u);
    EXPECT_TRUE(node.isBackground(-1.0f));

    const Index tile = Node16::coordToOffset(Coord(8, 0, 0));
    node.setTile(tile, 4.0f, true);
    EXPECT_TRUE(node.isTileOn(tile));
    EXPECT_EQ(node.getValue(Coord(15, 7, 7)), 4.0f);
    EXPECT_TRUE(node.isValueOn(Coord(8, 0, 0)));
    EXPECT_EQ(node.onTileCount(), 1u);
    EXPECT_EQ(node.onVoxelCount(), 512u);
    EXPECT_FALSE(node.isBackground(-1.0f));

    const Index child = Node16::coordToOffset(Coord(0, 8, 16));
    auto* leaf = new Leaf8(Coord(0, 8, 16), -1.0f, false);
    leaf->setValueOn(Coord(1, 9, 17), 3.0f);
    node.setChild(child, leaf);
    EXPECT_TRUE(node.isChild(child));
    EXPECT_EQ(node.getChild(child), leaf);
    EXPECT_EQ(node.getValue(Coord(1, 9, 17)), 3.0f);
    EXPECT_EQ(node.leafCount(), 1u);
    EXPECT_EQ(node.onLeafVoxelCount(), 1u);
    EXPECT_EQ(node.onVoxelCount(), 513u);
    CoordBBox bbox;
    node.evalActiveBoundingBox(bbox);
    EXPECT_EQ(bbox, CoordBBox(Coord(1, 0, 0), Coord(15, 9, 17)));

    Leaf8* stolen = node.stealChild(child, 0.5f, false);
    EXPECT_EQ(stolen, leaf);
    EXPECT_FALSE(node.isChild(child));
    EXPECT_EQ(node.getValue(Coord(1, 9, 17)), 0.5f);
    delete stolen;
    node.clear(-1.0f);
    EXPECT_TRUE(node.isBackground(-1.0f));
}

// ---- Root tables ------------------------------------------------------------------------------

// Random inserts and erases of keys that collide in a small hash table, compared with std::map:
// open addressing with backward-shift deletion must never lose or duplicate a key.
template <typename PolicyT>
class RootTableTyped : public ::testing::Test {};
using Policies = ::testing::Types<tree::HashTable, tree::MapTable>;
TYPED_TEST_SUITE(RootTableTyped, Policies);

TYPED_TEST(RootTableTyped, RandomInsertsAndErasesMatchStdMap) {
    constexpr Index kLog2 = 12;
    tree::detail::RootTable<int, kLog2, TypeParam> table;
    std::map<Coord, int> oracle;
    std::mt19937 rng(314159);
    for (int round = 0; round < 200; ++round) {
        // Each round starts from an empty table and draws from a few keys, so that the table
        // stays small (8 to 64 slots) and runs of probes often wrap around its end.
        table.clear();
        oracle.clear();
        std::vector<Coord> keys;
        const int keyCount = 2 + round % 20;
        for (int n = 0; n < keyCount; ++n) {
            keys.push_back(
                Coord(Int32(rng() % 64) - 32, Int32(rng() % 64) - 32, Int32(rng() % 64) - 32)
                << kLog2);
        }
        for (int n = 0; n < 2000; ++n) {
            const Coord k = keys[rng() % keys.size()];
            switch (rng() % 3) {
                case 0: {
                    const int v = int(rng() % 1000);
                    table.insert(k) = v;
                    oracle[k] = v;
                    break;
                }
                case 1:
                    table.erase(k);
                    oracle.erase(k);
                    break;
                default:
                    break;
            }
            ASSERT_EQ(table.size(), oracle.size()) << "round " << round << ", op " << n;
            // Every key the oracle holds is found with its value; no other key is.
            for (const Coord& key : keys) {
                const int* found = table.find(key);
                const auto it = oracle.find(key);
                ASSERT_EQ(found != nullptr, it != oracle.end())
                    << "key " << key << ", round " << round << ", op " << n;
                if (found) {
                    ASSERT_EQ(*found, it->second) << "key " << key;
                }
            }
        }
        std::map<Coord, int> visited;
        for (auto c = table.begin(); table.valid(c); table.next(c)) {
            ASSERT_TRUE(visited.emplace(table.key(c), table.entry(c)).second)
                << "key " << table.key(c) << " visited twice";
        }
        ASSERT_EQ(visited, oracle) << "round " << round;
    }
    table.clear();
    EXPECT_EQ(table.size(), 0u);
    EXPECT_EQ(table.find(Coord(0)), nullptr);
}

TYPED_TEST(RootTableTyped, RootNodeEntriesFollowTilesAndChildren) {
    using Child = tree::InternalNode<Node16, 5>;  // 4096^3 voxels per root entry
    using Root = tree::RootNode<Child, TypeParam>;
    Root root(-1.0f);
    std::map<Coord, std::pair<float, bool>> tiles;  // key -> tile
    std::set<Coord> children;
    std::mt19937 rng(2718);
    constexpr Int32 lo = std::numeric_limits<Int32>::min();
    auto key = [&] {
        const Int32 pick[] = {lo, lo + 4096, -4096, 0, 4096, 8192, Int32(0x7ffff000)};
        return Coord(pick[rng() % 7], pick[rng() % 7], pick[rng() % 3]);
    };
    for (int n = 0; n < 3000; ++n) {
        const Coord k = key();
        switch (rng() % 4) {
            case 0: {
                const float v = float(rng() % 3) - 1.0f;
                const bool on = rng() % 2;
                root.setTile(k.offsetBy(5), v, on);
                tiles[k] = {v, on};
                children.erase(k);
                break;
            }
            case 1:
                root.setChild(new Child(k, -1.0f));
                tiles.erase(k);
                children.insert(k);
                break;
            case 2:
                delete root.stealChild(k);
                children.erase(k);
                break;
            default: {
                const auto* e = root.findEntry(k);
                ASSERT_EQ(e != nullptr, tiles.count(k) + children.count(k) == 1) << k;
                if (e) {
                    ASSERT_EQ(e->child != nullptr, children.count(k) == 1) << k;
                }
                break;
            }
        }
        ASSERT_EQ(root.entryCount(), tiles.size() + children.size()) << "op " << n;
    }
    std::vector<Coord> keys;
    for (const auto& [k, t] : tiles) {
        keys.push_back(k);
        const auto* e = root.findEntry(k);
        ASSERT_NE(e, nullptr) << k;
        EXPECT_EQ(e->child, nullptr) << k;
        EXPECT_EQ(e->tile, t.first) << k;
        EXPECT_EQ(e->active, t.second) << k;
        tree::detail::NoCache none;
        EXPECT_EQ(root.template getAndCache<tree::ops::IsValueOn>(k.offsetBy(7), none), t.second)
            << k;
    }
    for (const Coord& k : children) {
        keys.push_back(k);
        const auto* e = root.findEntry(k);
        ASSERT_NE(e, nullptr) << k;
        EXPECT_NE(e->child, nullptr) << k;
    }
    std::sort(keys.begin(), keys.end());
    EXPECT_EQ(root.sortedKeys(), keys);
}

// ---- Tree statistics --------------------------------------------------------------------------

template <typename C>
class TreeStatistics : public ::testing::Test {};
using StatisticsConfigs =
    ::testing::Types<HashTree543, MapTree432, FixedTree643, FixedTree6545, FixedTree3333>;
TYPED_TEST_SUITE(TreeStatistics, StatisticsConfigs, test::ConfigName);

// Coordinates in a few clusters (all octants) and isolated points, inside every domain used.
std::vector<Coord> sampleCoords(uint32_t seed, int count) {
    std::mt19937 rng(seed);
    std::vector<Coord> result;
    const Coord centers[] = {Coord(0), Coord(-900, 300, -20), Coord(1500, -1700, 40)};
    for (int n = 0; n < count; ++n) {
        if (n % 200 == 0) {
            result.push_back(Coord(Int32(rng() % 3800) - 1900, Int32(rng() % 3800) - 1900,
                                   Int32(rng() % 3800) - 1900));
            continue;
        }
        const Coord& c = centers[rng() % 3];
        result.push_back(
            c.offsetBy(Int32(rng() % 41) - 20, Int32(rng() % 41) - 20, Int32(rng() % 41) - 20));
    }
    return result;
}

TYPED_TEST(TreeStatistics, NodeCountsMatchDistinctRegionsOfWrittenVoxels) {
    using TreeT = typename TypeParam::TreeType;
    const test::TreeShape shape = TypeParam::shape();
    TreeT tree(0.0f);
    test::SparseVolumeModel<float> model(0.0f);
    tree::ValueAccessor<TreeT> acc(tree);
    std::vector<std::unordered_set<Coord, test::CoordHash>> regions(shape.topLevel());
    Index64 memory = tree.memUsage();
    for (const Coord& ijk : sampleCoords(5, 20000)) {
        acc.setValue(ijk, 1.0f);
        model.setValue(ijk, 1.0f);
        bool newNode = false;
        for (Index level = 0; level < shape.topLevel(); ++level) {
            newNode |= regions[level].insert(ijk.alignedDown(shape.regionLog2(level))).second;
        }
        // Memory grows exactly when a node is added.
        const Index64 now = tree.memUsage();
        ASSERT_EQ(now > memory, newNode) << ijk << ": memUsage " << memory << " -> " << now;
        memory = now;
    }
    EXPECT_EQ(tree.leafCount(), regions[0].size());
    Index64 nonLeaf = 1;  // the top node
    for (Index level = 1; level < shape.topLevel(); ++level)
        nonLeaf += regions[level].size();
    EXPECT_EQ(tree.nonLeafCount(), nonLeaf);
    EXPECT_EQ(tree.activeTileCount(), 0u);
    EXPECT_EQ(tree.activeVoxelCount(), model.activeVoxelCount());
    EXPECT_EQ(tree.activeLeafVoxelCount(), model.activeVoxelCount());
    CoordBBox bbox;
    EXPECT_TRUE(tree.evalActiveVoxelBoundingBox(bbox));
    EXPECT_EQ(bbox, model.activeBoundingBox());

    // Node-aligned fills add one active tile each and widen the bounding box.
    const Int32 dim = Int32(1) << shape.leafLog2();
    const CoordBBox tileA = CoordBBox::createCube(Coord(-5 * dim), dim);
    const CoordBBox tileB = CoordBBox::createCube(Coord(dim * 40, -dim * 41, dim * 3), dim);
    tree.fill(tileA, 2.0f, true);
    tree.fill(tileB, 2.0f, true);
    model.fill(tileA, 2.0f, true);
    model.fill(tileB, 2.0f, true);
    EXPECT_EQ(tree.activeTileCount(), 2u);
    EXPECT_EQ(tree.activeVoxelCount(), model.activeVoxelCount());
    EXPECT_EQ(tree.activeLeafVoxelCount(), model.activeVoxelCount() - 2 * tileA.volume());
    EXPECT_TRUE(tree.evalActiveVoxelBoundingBox(bbox));
    EXPECT_EQ(bbox, model.activeBoundingBox());
}

TYPED_TEST(TreeStatistics, MemoryShrinksWhenNodesAreFreed) {
    using TreeT = typename TypeParam::TreeType;
    const test::TreeShape shape = TypeParam::shape();
    TreeT tree(0.0f);
    const Index64 empty = tree.memUsage();
    const std::vector<Coord> coords = sampleCoords(9, 5000);
    for (const Coord& ijk : coords)
        tree.setValue(ijk, 1.0f);
    const Index64 full = tree.memUsage();
    EXPECT_GT(full, empty);

    // Erasing every voxel frees every node below the top (a root table keeps its capacity).
    for (const Coord& ijk : coords)
        tree.eraseValue(ijk);
    EXPECT_EQ(tree.leafCount(), 0u);
    EXPECT_EQ(tree.nonLeafCount(), 1u);
    EXPECT_LT(tree.memUsage(), full);
    if (TreeT::BOUNDED) {
        EXPECT_EQ(tree.memUsage(), empty);
    }
    EXPECT_TRUE(tree.empty());

    // Pruning replaces uniform leaves by tiles.
    for (const Coord& ijk : coords)
        tree.setValue(ijk, 1.0f);
    const Int32 dim = Int32(1) << shape.leafLog2();
    for (Int32 i = 0; i < dim; ++i)
        for (Int32 j = 0; j < dim; ++j)
            for (Int32 k = 0; k < dim; ++k)
                tree.setValue(Coord(-dim).offsetBy(i, j, k), 1.0f);
    const Index64 beforePrune = tree.memUsage();
    const Index32 leavesBeforePrune = tree.leafCount();
    tree.prune();
    EXPECT_EQ(tree.leafCount(), leavesBeforePrune - 1);
    EXPECT_LT(tree.memUsage(), beforePrune);

    tree.clear();
    EXPECT_EQ(tree.memUsage(), empty);
    EXPECT_TRUE(tree.empty());
}

// A bounded tree holds every voxel of its domain: inactive ones are counted too.
TEST(TreeStatistics, ActivePlusInactiveVoxelsOfBoundedTreeIsDomainVolume) {
    tree::FixedTree643<float> tree(1.0f);
    const Index64 volume = tree::FixedTree643<float>::domain().volume();
    EXPECT_EQ(volume, Index64(1) << 39);
    EXPECT_EQ(tree.inactiveVoxelCount(), volume);
    tree.setValue(Coord(-1), 2.0f);
    tree.fill(CoordBBox::createCube(Coord(128), 128), 3.0f, true);
    tree.fill(CoordBBox::createCube(Coord(-256), 8), 3.0f, false);
    EXPECT_EQ(tree.activeVoxelCount(), 1u + 128u * 128u * 128u);
    EXPECT_EQ(tree.activeVoxelCount() + tree.inactiveVoxelCount(), volume);
}

// The largest bounded domains hold more than 2^64 voxels; their counts must not wrap.
TEST(TreeStatistics, InactiveVoxelCountOfHugeDomainDoesNotWrap) {
    tree::FixedTree76543<float> tree(1.0f);
    EXPECT_GT(tree.inactiveVoxelCount(), Index64(1) << 62);
    tree::FixedTree6666<float> other(1.0f);
    EXPECT_GT(other.inactiveVoxelCount(), Index64(1) << 62);
}

// An inactive tile that holds a value other than the background is content.
TEST(TreeStatistics, TreeWithInactiveNonBackgroundTileIsNotEmpty) {
    tree::FixedTree643<float> bounded(0.0f);
    bounded.fill(CoordBBox::createCube(Coord(0), 128), 5.0f, false);  // one top-level tile
    EXPECT_EQ(bounded.getValue(Coord(3)), 5.0f);
    EXPECT_FALSE(bounded.empty());
    FloatTree unbounded(0.0f);
    unbounded.fill(CoordBBox::createCube(Coord(0), 4096), 5.0f, false);  // one root tile
    EXPECT_FALSE(unbounded.empty());
    unbounded.fill(CoordBBox::createCube(Coord(0), 4096), 0.0f, false);
    unbounded.prune();
    EXPECT_TRUE(unbounded.empty());
}

// Moving a tree hands its nodes over; a copy is deep.
TEST(TreeStatistics, MoveHandsNodesOverAndCopyIsDeep) {
    FloatTree tree(0.0f);
    tree.setValue(Coord(-5, 6, 7), 1.0f);
    const auto* leaf = tree.probeConstLeaf(Coord(-5, 6, 7));
    FloatTree copy(tree);
    EXPECT_NE(copy.probeConstLeaf(Coord(-5, 6, 7)), leaf);
    EXPECT_EQ(copy.getValue(Coord(-5, 6, 7)), 1.0f);
    FloatTree moved(std::move(tree));
    EXPECT_EQ(moved.probeConstLeaf(Coord(-5, 6, 7)), leaf);
    EXPECT_EQ(moved.getValue(Coord(-5, 6, 7)), 1.0f);
    FloatTree assigned(0.0f);
    assigned = std::move(moved);
    EXPECT_EQ(assigned.probeConstLeaf(Coord(-5, 6, 7)), leaf);
}

// ---- Bool and mask trees ----------------------------------------------------------------------

struct BoolTreeConfig : test::TreeConfig<BoolTree, false, 5, 4, 3> {
    static constexpr const char* NAME = "BoolTree";
};
struct MaskTreeConfig : test::TreeConfig<MaskTree, false, 5, 4, 3> {
    static constexpr const char* NAME = "MaskTree";
};
struct FixedBoolTree : test::TreeConfig<tree::FixedTree4444<bool>, true, 4, 4, 4, 4> {
    static constexpr const char* NAME = "FixedTree4444Bool";
};
struct FixedMaskTree : test::TreeConfig<tree::FixedTree643<ValueMask>, true, 6, 4, 3> {
    static constexpr const char* NAME = "FixedTree643Mask";
};

template <typename C>
class BitTreeDifferential : public ::testing::Test {};
using BitConfigs = ::testing::Types<BoolTreeConfig, MaskTreeConfig, FixedBoolTree, FixedMaskTree>;
TYPED_TEST_SUITE(BitTreeDifferential, BitConfigs, test::ConfigName);

TYPED_TEST(BitTreeDifferential, RandomOperationsMatchSparseVolumeModel) {
    using TreeT = typename TypeParam::TreeType;
    constexpr bool isMask = std::is_same_v<typename TreeT::BuildType, ValueMask>;
    // Bool trees run with either background; mask trees have background false.
    for (const bool background : {false, true}) {
        if (isMask && background)
            continue;
        SCOPED_TRACE(::testing::Message() << "background " << background);
        test::WorkloadOptions options;
        options.seed = 1234 + background;
        options.batches = 10;
        options.opsPerBatch = 20000;
        TreeT tree(background);
        test::TreeModelDriver<TreeT, tree::ValueAccessor<TreeT>, tree::ValueAccessor<const TreeT>>
            driver(tree, TypeParam::shape(), options, {false, true});
        EXPECT_TRUE(driver.run());
    }
}

}  // namespace
}  // namespace vdb
