// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels that knows nothing
// of nodes or tiles, driven through the same seeded operations as the tree; node sizes come
// from the paper's Table II, written out below rather than read from the templates.

#include <vdb/Exceptions.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class TreeDifferential : public ::testing::Test {};
using AllConfigs =
    ::testing::Types<HashTree543, MapTree543, HashTree432, MapTree432, FixedTree76543,
                     FixedTree6543, FixedTree643, FixedTree103, FixedTree6545, FixedTree6544,
                     FixedTree6542, FixedTree6666, FixedTree5555, FixedTree4444, FixedTree3333>;
TYPED_TEST_SUITE(TreeDifferential, AllConfigs, test::ConfigName);

// The [10,3] tree's 2^30-entry top table is only cheap when the background is all zero bits.
template <typename C>
constexpr float kBackground =
    std::is_same_v<typename C::TreeType, tree::FixedTree103<float>> ? 0.0f : 2.5f;

template <typename C>
std::vector<float> palette() {
    return {kBackground<C>, 0.0f, -1.0f, 1.0f, 2.0f, 3.5f, -7.25f, 100.0f};
}

// Checks the log2 edge of the node at each level against the configuration's name.
template <typename TopT, Index Level>
void expectLog2Dims(const test::TreeShape& shape) {
    using NodeT = tree::NodeAtLevelT<TopT, Level>;
    EXPECT_EQ(NodeT::LOG2DIM, shape.log2Dims[shape.log2Dims.size() - 1 - Level])
        << "level " << Level;
    if constexpr (Level + 1 < TopT::LEVEL ||
                  (Level + 1 == TopT::LEVEL && !tree::IS_ROOT_NODE<TopT>)) {
        expectLog2Dims<TopT, Level + 1>(shape);
    }
}

TYPED_TEST(TreeDifferential, ShapeMatchesTableTwo) {
    using TreeT = typename TypeParam::TreeType;
    const test::TreeShape shape = TypeParam::shape();
    EXPECT_EQ(TreeT::BOUNDED, shape.bounded);
    EXPECT_EQ(TreeT::DEPTH, shape.topLevel() + 1);
    EXPECT_EQ(TreeT::domain(), shape.domain());
    expectLog2Dims<typename TreeT::TopNodeType, 0>(shape);
}

TYPED_TEST(TreeDifferential, RandomOperationsMatchSparseVolumeModel) {
    using TreeT = typename TypeParam::TreeType;
    test::WorkloadOptions options;
    options.seed = 20130601;
    options.batches = 40;
    options.opsPerBatch = 25000;
    if constexpr (std::is_same_v<TreeT, tree::FixedTree103<float>>) {
        // Every whole-tree pass scans 2^24 mask words, so fewer batches and prunes; the
        // inactive-value walk would visit all 2^30 top-table entries, and a copy would commit
        // the whole 8 GiB table.
        options.batches = 8;
        options.pruneOrClearRate = 1e-4;
        options.checkInactiveValues = false;
        options.checkCopy = false;
    }
    if constexpr (std::is_same_v<TreeT, tree::FixedTree76543<float>> ||
                  std::is_same_v<TreeT, tree::FixedTree6666<float>>) {
        options.sparsePoints = 16;  // each isolated point costs megabytes of internal nodes
    }
    TreeT tree(kBackground<TypeParam>);
    test::TreeModelDriver<TreeT, tree::ValueAccessor<TreeT>, tree::ValueAccessor<const TreeT>>
        driver(tree, TypeParam::shape(), options, palette<TypeParam>());
    EXPECT_TRUE(driver.run());
}

// Filling exactly the region of one child of a node at `level` must leave one tile there.
TYPED_TEST(TreeDifferential, FillOfWholeChildRegionBecomesOneTileAtEveryLevel) {
    using TreeT = typename TypeParam::TreeType;
    const test::TreeShape shape = TypeParam::shape();
    const float bg = kBackground<TypeParam>;
    for (Index level = 1; level <= shape.topLevel(); ++level) {
        SCOPED_TRACE(::testing::Message() << "level " << level);
        const Index log2 = shape.tileLog2(level);
        const Int32 dim = Int32(Index64(1) << log2);
        // A child region in the negative octant, next to the origin.
        const Coord origin(-dim, -dim, -dim);
        const CoordBBox box = CoordBBox::createCube(origin, dim);
        TreeT tree(bg);
        tree::ValueAccessor<TreeT> acc(tree);
        tree.fill(box, 5.0f, true);
        EXPECT_EQ(tree.leafCount(), 0u);
        EXPECT_EQ(tree.activeTileCount(), 1u);
        EXPECT_EQ(tree.activeVoxelCount(), box.volume());
        int items = 0;
        for (auto it = tree.cbeginValueOn(); it; ++it, ++items) {
            CoordBBox bbox;
            it.getBoundingBox(bbox);
            EXPECT_TRUE(it.isTileValue());
            EXPECT_EQ(it.getLevel(), level);
            EXPECT_EQ(bbox, box);
            EXPECT_EQ(it.getCoord(), origin);
            EXPECT_EQ(*it, 5.0f);
        }
        EXPECT_EQ(items, 1);
        CoordBBox bbox;
        EXPECT_TRUE(tree.evalActiveVoxelBoundingBox(bbox));
        EXPECT_EQ(bbox, box);
        for (const Coord& ijk : {box.min(), box.max(), Coord(-1, -dim, -1)}) {
            EXPECT_EQ(tree.getValue(ijk), 5.0f) << ijk;
            EXPECT_TRUE(acc.isValueOn(ijk)) << ijk;
        }
        for (const Coord& ijk : {box.min().offsetBy(-1, 0, 0), Coord(0, -1, -1), Coord(0)}) {
            if (!shape.domain().isInside(ijk))
                continue;
            EXPECT_EQ(acc.getValue(ijk), bg) << ijk;
            EXPECT_FALSE(tree.isValueOn(ijk)) << ijk;
        }

        // Erasing one voxel splits the tile down to one leaf and keeps every other voxel.
        const Coord corner = box.max();
        acc.eraseValue(corner);
        EXPECT_EQ(tree.leafCount(), 1u);
        EXPECT_EQ(tree.activeVoxelCount(), box.volume() - 1);
        EXPECT_EQ(acc.getValue(corner), bg);
        EXPECT_FALSE(acc.isValueOn(corner));
        EXPECT_EQ(acc.getValue(corner.offsetBy(0, 0, -1)), 5.0f);
        EXPECT_TRUE(tree.isValueOn(box.min()));
        ASSERT_NE(tree.probeConstLeaf(corner), nullptr);
        EXPECT_EQ(tree.probeConstLeaf(corner)->onVoxelCount(),
                  (Index64(1) << (3 * shape.leafLog2())) - 1);

        // Writing the voxel back and pruning restores the single tile.
        acc.setValue(corner, 5.0f);
        tree.prune();
        EXPECT_EQ(tree.leafCount(), 0u);
        EXPECT_EQ(tree.activeTileCount(), 1u);
        EXPECT_EQ(acc.getValue(corner), 5.0f);
    }
}

TYPED_TEST(TreeDifferential, WritesOutsideBoundedDomainThrowIndexError) {
    using TreeT = typename TypeParam::TreeType;
    if constexpr (!TreeT::BOUNDED) {
        GTEST_SKIP() << "unbounded tree";
    } else {
        const float bg = kBackground<TypeParam>;
        const CoordBBox domain = TreeT::domain();
        TreeT tree(bg);
        tree::ValueAccessor<TreeT> acc(tree);
        const Coord inside = domain.max();
        tree.setValue(inside, 1.0f);
        constexpr Int32 lo = std::numeric_limits<Int32>::min();
        constexpr Int32 hi = std::numeric_limits<Int32>::max();
        const std::vector<Coord> outside = {domain.max().offsetBy(1, 0, 0),
                                            domain.max().offsetBy(0, 1, 0),
                                            domain.max().offsetBy(0, 0, 1),
                                            domain.min().offsetBy(-1, 0, 0),
                                            domain.min().offsetBy(0, -1, 0),
                                            domain.min().offsetBy(0, 0, -1),
                                            Coord(lo),
                                            Coord(hi),
                                            Coord(0, hi, 0),
                                            Coord(lo, 0, 0)};
        for (const Coord& ijk : outside) {
            SCOPED_TRACE(::testing::Message() << "at " << ijk);
            EXPECT_THROW(tree.setValue(ijk, 1.0f), IndexError);
            EXPECT_THROW(tree.setValueOn(ijk), IndexError);
            EXPECT_THROW(tree.setValueOn(ijk, 1.0f), IndexError);
            EXPECT_THROW(tree.setValueOff(ijk), IndexError);
            EXPECT_THROW(tree.setValueOff(ijk, 1.0f), IndexError);
            EXPECT_THROW(tree.setValueOnly(ijk, 1.0f), IndexError);
            EXPECT_THROW(tree.setActiveState(ijk, true), IndexError);
            EXPECT_THROW(tree.touchLeaf(ijk), IndexError);
            EXPECT_THROW(acc.setValue(ijk, 1.0f), IndexError);
            EXPECT_THROW(acc.setValueOff(ijk, 1.0f), IndexError);
            EXPECT_THROW(acc.touchLeaf(ijk), IndexError);
            const CoordBBox across(Coord::minComponent(inside, ijk),
                                   Coord::maxComponent(inside, ijk));
            EXPECT_THROW(tree.fill(across, 1.0f, true), IndexError);
            // Erasing outside has nothing to erase.
            EXPECT_NO_THROW(tree.eraseValue(ijk));
            EXPECT_EQ(tree.getValue(ijk), bg);
            EXPECT_FALSE(tree.isValueOn(ijk));
            float value = 0;
            EXPECT_FALSE(tree.probeValue(ijk, value));
            EXPECT_EQ(value, bg);
            EXPECT_EQ(acc.getValue(ijk), bg);
            EXPECT_EQ(tree.probeConstLeaf(ijk), nullptr);
        }
        // The failed writes changed nothing.
        EXPECT_EQ(tree.activeVoxelCount(), 1u);
        EXPECT_EQ(tree.getValue(inside), 1.0f);
        EXPECT_EQ(tree.leafCount(), 1u);
    }
}

// The +-2^31 corners of an unbounded tree are ordinary voxels.
TYPED_TEST(TreeDifferential, ExtremeCoordinatesOfUnboundedTreeAreOrdinaryVoxels) {
    using TreeT = typename TypeParam::TreeType;
    if constexpr (TreeT::BOUNDED) {
        GTEST_SKIP() << "bounded tree";
    } else {
        constexpr Int32 lo = std::numeric_limits<Int32>::min();
        constexpr Int32 hi = std::numeric_limits<Int32>::max();
        const float bg = kBackground<TypeParam>;
        TreeT tree(bg);
        tree::ValueAccessor<TreeT> acc(tree);
        std::vector<Coord> corners;
        for (Int32 x : {lo, hi})
            for (Int32 y : {lo, hi})
                for (Int32 z : {lo, hi})
                    corners.push_back(Coord(x, y, z));
        float value = 1.0f;
        for (const Coord& ijk : corners)
            acc.setValue(ijk, value++);
        EXPECT_EQ(tree.activeVoxelCount(), corners.size());
        EXPECT_EQ(tree.leafCount(), corners.size());
        value = 1.0f;
        for (const Coord& ijk : corners) {
            EXPECT_EQ(tree.getValue(ijk), value) << ijk;
            EXPECT_TRUE(tree.isValueOn(ijk)) << ijk;
            EXPECT_EQ(tree.getValue(ijk.offsetBy(ijk[0] == lo ? 1 : -1, 0, 0)), bg) << ijk;
            const auto* leaf = tree.probeConstLeaf(ijk);
            ASSERT_NE(leaf, nullptr) << ijk;
            EXPECT_EQ(leaf->origin(), ijk.alignedDown(TypeParam::shape().leafLog2())) << ijk;
            value += 1.0f;
        }
        std::vector<Coord> visited;
        for (auto it = tree.cbeginValueOn(); it; ++it)
            visited.push_back(it.getCoord());
        std::sort(visited.begin(), visited.end());
        std::sort(corners.begin(), corners.end());
        EXPECT_EQ(visited, corners);
        CoordBBox bbox;
        EXPECT_TRUE(tree.evalActiveVoxelBoundingBox(bbox));
        EXPECT_EQ(bbox, CoordBBox::inf());

        // A fill that reaches INT32_MAX stops there.
        const CoordBBox edge(Coord(hi - 9), Coord(hi));
        tree.fill(edge, -1.0f, true);
        EXPECT_EQ(tree.getValue(Coord(hi)), -1.0f);
        EXPECT_EQ(tree.getValue(Coord(hi - 9)), -1.0f);
        EXPECT_EQ(tree.getValue(Coord(hi - 10)), bg);
        for (const Coord& ijk : corners)
            acc.eraseValue(ijk);
        tree.eraseValue(Coord(hi));
        EXPECT_EQ(tree.activeVoxelCount(), edge.volume() - 1);
    }
}

}  // namespace
}  // namespace vdb
