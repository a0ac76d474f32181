// SPDX-License-Identifier: Apache-2.0
// The leaf index (Tree::buildLeafIndex, tree/LeafIndex.h). Oracles: SparseVolumeModel driven
// through random edits while the index is rebuilt at random moments, and the walk from the top
// (checkLeafIndex: every leaf the index lists is the one the walk finds at its origin).

#include <vdb/tree/LeafIndex.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class LeafIndexDifferential : public ::testing::Test {};
using IndexConfigs = ::testing::Types<HashTree543, MapTree543, HashTree432, FixedTree6543,
                                      FixedTree643, FixedTree5555>;
TYPED_TEST_SUITE(LeafIndexDifferential, IndexConfigs, test::ConfigName);

// Runs the model workload on `tree` with the index rebuilt at `rate` per operation and checks
// that it really ran with a current index for a good share of its operations.
template <typename TreeT>
void runWithIndex(TreeT& tree, const test::TreeShape& shape, uint32_t seed, int batches,
                  double rate, std::vector<typename TreeT::ValueType> palette) {
    test::WorkloadOptions options;
    options.seed = seed;
    options.batches = batches;
    options.opsPerBatch = 20000;
    options.leafIndexRate = rate;
    options.checkCopy = false;
    test::TreeModelDriver<TreeT, tree::ValueAccessor<TreeT>, tree::ValueAccessor<const TreeT>>
        driver(tree, shape, options, std::move(palette));
    EXPECT_TRUE(driver.run());
    EXPECT_GT(double(driver.leafIndexBuilds()), double(driver.opCount()) * rate / 2);
    EXPECT_GT(driver.opsWithLeafIndex(), driver.opCount() / 5);
}

// Random writes, erasures, fills, prunes and clears through the tree and two long-lived
// accessors, with the index rebuilt about every 150 operations: every read (top-down, accessor,
// const accessor) must match the model whether the index is current, retired by a freeing
// edit, or missing the leaves added since it was built.
TYPED_TEST(LeafIndexDifferential, RandomEditsWithIndexMatchSparseVolumeModel) {
    using TreeT = typename TypeParam::TreeType;
    TreeT tree(2.5f);
    runWithIndex(tree, TypeParam::shape(), 41, 16, 1.0 / 150,
                 {2.5f, 0.0f, -1.0f, 1.0f, 3.5f, 100.0f});
}

// A mask tree, whose leaves hold no values: the index serves isValueOn and the accessors.
TEST(LeafIndex, MaskTreeRandomEditsMatchModel) {
    MaskTree tree(false);
    runWithIndex(tree, HashTree543::shape(), 7, 8, 1.0 / 200, {false, true});
}

// A tree with leaves in a few clusters, far apart, the corners of the index space included.
FloatTree clusteredTree(uint32_t seed) {
    FloatTree tree(1.0f);
    std::mt19937 rng(seed);
    const Int32 lo = std::numeric_limits<Int32>::min(), hi = std::numeric_limits<Int32>::max();
    const std::vector<Coord> centres = {Coord(0), Coord(lo + 40), Coord(hi - 40),
                                        Coord(lo + 40, hi - 40, 7), Coord(1000, -2000, 3000)};
    for (const Coord& c : centres)
        for (int n = 0; n < 3000; ++n)
            tree.setValue(
                c.offsetBy(Int32(rng() % 80) - 40, Int32(rng() % 80) - 40, Int32(rng() % 80) - 40),
                float(n));
    return tree;
}

TEST(LeafIndex, FindsEveryLeafFromEveryVoxelAndNothingElse) {
    FloatTree tree = clusteredTree(1);
    EXPECT_FALSE(tree.hasLeafIndex());
    EXPECT_EQ(tree.leafIndex(), nullptr);
    const Index64 before = tree.memUsage();
    tree.buildLeafIndex();
    ASSERT_TRUE(tree.hasLeafIndex());
    const auto& index = *tree.leafIndex();
    EXPECT_EQ(index.size(), tree.leafCount());
    EXPECT_GE(index.capacity(), 2 * index.size());
    EXPECT_LE(index.capacity(), 4 * index.size());
    EXPECT_EQ(tree.memUsage(), before + index.memUsage());
    EXPECT_TRUE(test::checkLeafIndex(tree));
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const Coord o = leaf->origin();
        for (const Coord& d : {Coord(0), Coord(7), Coord(3, 0, 5), Coord(7, 7, 0)})
            ASSERT_EQ(index.find(o + d), &*leaf) << o + d;
        // The neighbouring bricks hold this leaf's neighbours or nothing, never this leaf.
        for (const Coord& d : {Coord(-1, 0, 0), Coord(8, 0, 0), Coord(0, 8, 0), Coord(0, 0, -1)}) {
            const auto* found = index.find(o + d);
            ASSERT_NE(found, &*leaf) << o + d;
            ASSERT_EQ(found, tree.probeConstLeaf(o + d)) << o + d;
        }
    }
    EXPECT_EQ(index.find(Coord(500, 500, 500)), nullptr);
}

// Reads through the index and through the walk of an index-free copy agree everywhere.
void expectSameReads(const FloatTree& indexed, const FloatTree& plain, uint32_t seed) {
    FloatTree::ConstAccessor acc(indexed);
    for (auto v = plain.cbeginValueOn(); v; ++v) {
        const Coord ijk = v.getCoord();
        ASSERT_EQ(indexed.getValue(ijk), *v) << ijk;
        ASSERT_TRUE(indexed.isValueOn(ijk)) << ijk;
        ASSERT_EQ(acc.getValue(ijk), *v) << ijk;
    }
    EXPECT_EQ(indexed.activeVoxelCount(), plain.activeVoxelCount());
    std::mt19937 rng(seed);
    for (int n = 0; n < 20000; ++n) {
        const Coord ijk(Int32(rng() % 200) - 100, Int32(rng() % 200) - 100,
                        Int32(rng() % 200) - 100);
        float a, b;
        const bool onA = indexed.probeValue(ijk, a), onB = plain.probeValue(ijk, b);
        ASSERT_EQ(a, b) << ijk;
        ASSERT_EQ(onA, onB) << ijk;
        ASSERT_EQ(acc.isValueOn(ijk), onB) << ijk;
        ASSERT_EQ(indexed.probeConstLeaf(ijk) != nullptr, plain.probeConstLeaf(ijk) != nullptr);
    }
}

FloatTree cubeTree() {
    FloatTree tree(0.0f);
    for (Int32 x = -40; x < 40; x += 3)
        for (Int32 y = -40; y < 40; y += 2)
            for (Int32 z = -40; z < 40; z += 5)
                tree.setValue(Coord(x, y, z), float(x + 2 * y + 3 * z));
    return tree;
}

TEST(LeafIndex, EditsThatFreeNodesRetireItAndReadsStayRight) {
    struct Edit {
        const char* name;
        std::function<void(FloatTree&)> apply;
    };
    const std::vector<Edit> edits = {
        {"prune of a uniform leaf",
         [](FloatTree& t) {
             for (Int32 x = 200; x < 208; ++x)
                 for (Int32 y = 200; y < 208; ++y)
                     for (Int32 z = 200; z < 208; ++z)
                         t.setValue(Coord(x, y, z), 2.0f);
             t.buildLeafIndex();
             t.prune();
         }},
        {"clear", [](FloatTree& t) { t.clear(); }},
        {"eraseValue of a leaf's last value",
         [](FloatTree& t) {
             t.setValue(Coord(500), 1.0f);
             t.buildLeafIndex();
             t.eraseValue(Coord(500));
         }},
        {"fill over leaves", [](FloatTree& t) { t.fill(CoordBBox(Coord(-64), Coord(63)), 9.0f); }},
        {"addLeaf over a leaf",
         [](FloatTree& t) {
             t.addLeaf(std::make_unique<FloatTree::LeafNodeType>(Coord(0), 4.0f, true));
         }},
        {"addTile over leaves", [](FloatTree& t) { t.addTile(2, Coord(0), 5.0f, true); }},
        {"topologyIntersection",
         [](FloatTree& t) {
             FloatTree other(0.0f);
             other.setValue(Coord(1), 1.0f);
             t.topologyIntersection(other);
         }},
        {"topologyDifference",
         [](FloatTree& t) {
             FloatTree other(0.0f);
             other.fill(CoordBBox(Coord(0), Coord(300)), 1.0f);
             t.topologyDifference(other);
         }},
        {"copy assignment", [](FloatTree& t) { t = cubeTree(); }},
        {"move assignment",
         [](FloatTree& t) {
             FloatTree other = cubeTree();
             t = std::move(other);
         }},
    };
    for (const Edit& edit : edits) {
        SCOPED_TRACE(edit.name);
        FloatTree tree = cubeTree();
        FloatTree::ConstAccessor acc(tree);  // lives across the edit
        tree.buildLeafIndex();
        ASSERT_TRUE(tree.hasLeafIndex());
        (void)acc.getValue(Coord(0));
        FloatTree plain = cubeTree();
        edit.apply(tree);
        edit.apply(plain);
        EXPECT_FALSE(tree.hasLeafIndex());
        EXPECT_EQ(acc.getValue(Coord(0)), plain.getValue(Coord(0)));
        expectSameReads(tree, plain, 3);
        tree.buildLeafIndex();
        EXPECT_TRUE(test::checkLeafIndex(tree));
        expectSameReads(tree, plain, 4);
    }
}

TEST(LeafIndex, LeavesAddedAfterTheBuildAreFoundByTheWalk) {
    FloatTree tree = cubeTree();
    tree.buildLeafIndex();
    FloatTree::Accessor acc(tree);
    const Index32 indexed = tree.leafCount();
    for (Int32 n = 0; n < 50; ++n) {
        tree.setValue(Coord(1000 + 8 * n, 0, 0), float(n));  // a new leaf each
        acc.setValue(Coord(0, 2000 + 8 * n, 0), float(-n));
    }
    acc.touchLeaf(Coord(0, 0, 3000));
    tree.addLeaf(std::make_unique<FloatTree::LeafNodeType>(Coord(-3000), 6.0f, true));
    ASSERT_TRUE(tree.hasLeafIndex());  // nothing was freed
    EXPECT_EQ(tree.leafIndex()->size(), indexed);
    EXPECT_TRUE(test::checkLeafIndex(tree));
    FloatTree::ConstAccessor reader(tree);
    for (Int32 n = 0; n < 50; ++n) {
        EXPECT_EQ(tree.getValue(Coord(1000 + 8 * n, 0, 0)), float(n));
        EXPECT_EQ(reader.getValue(Coord(0, 2000 + 8 * n, 0)), float(-n));
        EXPECT_TRUE(tree.isValueOn(Coord(0, 2000 + 8 * n, 0)));
    }
    EXPECT_NE(tree.probeConstLeaf(Coord(0, 0, 3001)), nullptr);
    EXPECT_EQ(reader.getValue(Coord(-3000)), 6.0f);
    // Values written through the index land in the indexed leaves.
    acc.clear();
    acc.setValue(Coord(1, 2, 3), 77.0f);
    EXPECT_EQ(tree.getValue(Coord(1, 2, 3)), 77.0f);
    EXPECT_TRUE(acc.isCached(Coord(1, 2, 3)));
}

TEST(LeafIndex, CopiesAndMovesDoNotShareIt) {
    FloatTree tree = cubeTree();
    tree.buildLeafIndex();
    const FloatTree copy(tree);
    EXPECT_FALSE(copy.hasLeafIndex());
    EXPECT_TRUE(tree.hasLeafIndex());
    FloatTree moved(std::move(tree));
    EXPECT_FALSE(moved.hasLeafIndex());
    EXPECT_FALSE(tree.hasLeafIndex());
    EXPECT_EQ(tree.getValue(Coord(0)), 0.0f);
    expectSameReads(moved, copy, 5);
    const Index64 bytes = moved.memUsage();
    moved.buildLeafIndex();
    EXPECT_GT(moved.memUsage(), bytes);
    moved.releaseLeafIndex();
    EXPECT_FALSE(moved.hasLeafIndex());
    EXPECT_EQ(moved.memUsage(), bytes);
}

TEST(LeafIndex, BoundedTreeAndOtherLeafSizes) {
    tree::FixedTree643<float> bounded(0.5f);
    HashTree432::TreeType small(0.5f);
    std::mt19937 rng(9);
    for (int n = 0; n < 20000; ++n) {
        const Coord ijk(Int32(rng() % 2000) - 1000, Int32(rng() % 2000) - 1000,
                        Int32(rng() % 64) - 32);
        bounded.setValue(ijk, float(n));
        small.setValue(ijk, float(n));
    }
    bounded.buildLeafIndex();
    small.buildLeafIndex();
    EXPECT_TRUE(test::checkLeafIndex(bounded));
    EXPECT_TRUE(test::checkLeafIndex(small));
    for (auto v = small.cbeginValueOn(); v; ++v) {
        ASSERT_EQ(bounded.getValue(v.getCoord()), *v);
        ASSERT_EQ(small.getValue(v.getCoord()), *v);
    }
    // Outside the bounded tree's domain: the background, without touching the index.
    EXPECT_EQ(bounded.getValue(Coord(std::numeric_limits<Int32>::max())), 0.5f);
}

}  // namespace
}  // namespace vdb
