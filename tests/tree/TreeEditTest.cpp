// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels: adding a leaf or a
// tile must change exactly the voxels of its region, whatever the tree held there before (a
// leaf, a tile of another level, nothing), at every level of every Table II configuration.

#include <vdb/Exceptions.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <memory>
#include <random>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class TreeEdit : public ::testing::Test {};
using Configs = ::testing::Types<HashTree543, MapTree432, FixedTree6543, FixedTree643,
                                 FixedTree5555, FixedTree3333>;
TYPED_TEST_SUITE(TreeEdit, Configs, test::ConfigName);

/// Expects every voxel of `box` to read as the model says.
template <typename TreeT>
void expectBox(const TreeT& tree, const test::SparseVolumeModel<float>& model,
               const CoordBBox& box) {
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                float expected = 0.0f, got = 0.0f;
                const bool expectedOn = model.probeValue(ijk, expected);
                const bool on = tree.probeValue(ijk, got);
                ASSERT_EQ(got, expected) << ijk;
                ASSERT_EQ(on, expectedOn) << ijk;
            }
}

/// Fills the part of `region` that lies in `window` (the model stores voxels one by one).
void fillWithin(test::SparseVolumeModel<float>& model, CoordBBox region, const CoordBBox& window,
                float value, bool on) {
    region.intersect(window);
    model.fill(region, value, on);
}

/// The edge of the region a tile at `level` covers: the edge of the nodes one level down.
template <typename TopT, Index Level = 1>
Int32 regionDim(Index level) {
    if (level == Level)
        return Int32(tree::NodeAtLevelT<TopT, Level - 1>::DIM);
    if constexpr (Level < TopT::LEVEL)
        return regionDim<TopT, Level + 1>(level);
    return 0;
}

TYPED_TEST(TreeEdit, AddLeafAndAddTileChangeExactlyTheirRegion) {
    using TreeT = typename TypeParam::TreeType;
    using TopT = typename TreeT::TopNodeType;
    using LeafT = typename TreeT::LeafNodeType;
    const float bg = 0.5f;
    TreeT tree(bg);
    test::SparseVolumeModel<float> model(bg);
    tree::ValueAccessor<TreeT> acc(tree);
    const Int32 leafDim = Int32(LeafT::DIM);
    const Int32 tile1 = regionDim<TopT>(1);
    const CoordBBox around = CoordBBox::createCube(Coord(-leafDim), 4 * leafDim);

    // A tile of level 2 (or the top), then a leaf inside it: the new parents take the tile's
    // value and state, the rest of the tile is unchanged.
    const Index big = std::min<Index>(2, TopT::LEVEL);
    const Int32 bigDim = regionDim<TopT>(big);
    tree.addTile(big, Coord(0), 3.0f, true);
    fillWithin(model, CoordBBox::createCube(Coord(0), bigDim), around, 3.0f, true);
    acc.getValue(Coord(1));  // cache the tile's node
    auto leaf = std::make_unique<LeafT>(Coord(leafDim), -1.0f, false);
    leaf->setValueOn(Coord(leafDim + 1, leafDim, leafDim), 7.0f);
    tree.addLeaf(std::move(leaf));
    model.fill(CoordBBox::createCube(Coord(leafDim), leafDim), -1.0f, false);
    model.setValueOn(Coord(leafDim + 1, leafDim, leafDim), 7.0f);
    EXPECT_EQ(acc.getValue(Coord(leafDim + 1, leafDim, leafDim)), 7.0f);
    expectBox(tree, model, around);

    // A leaf replacing a leaf: an accessor that cached the old one sees the new one.
    auto other = std::make_unique<LeafT>(Coord(leafDim), 2.0f, true);
    tree.addLeaf(std::move(other));
    model.fill(CoordBBox::createCube(Coord(leafDim), leafDim), 2.0f, true);
    EXPECT_EQ(acc.getValue(Coord(leafDim + 1, leafDim, leafDim)), 2.0f);
    expectBox(tree, model, around);

    // A leaf-sized tile over that leaf frees it; a top-level tile frees everything below.
    tree.addTile(1, Coord(leafDim + 2), -4.0f, false);
    fillWithin(model, CoordBBox::createCube(Coord(leafDim), tile1), around, -4.0f, false);
    EXPECT_EQ(acc.getValue(Coord(leafDim + 1, leafDim, leafDim)), -4.0f);
    EXPECT_EQ(tree.probeConstLeaf(Coord(leafDim)), nullptr);
    expectBox(tree, model, around);
    tree.addTile(TopT::LEVEL, Coord(5), 9.0f, true);
    if constexpr (TreeT::BOUNDED) {
        EXPECT_EQ(tree.leafCount(), 0u);
        EXPECT_EQ(tree.getValue(Coord(1)), 9.0f);
    } else {
        fillWithin(model, CoordBBox::createCube(Coord(0), regionDim<TopT>(TopT::LEVEL)), around,
                   9.0f, true);
        EXPECT_EQ(tree.leafCount(), 0u);
        expectBox(tree, model, around);
    }
}

TYPED_TEST(TreeEdit, RandomLeavesAndTilesMatchTheModel) {
    using TreeT = typename TypeParam::TreeType;
    using LeafT = typename TreeT::LeafNodeType;
    const Int32 leafDim = Int32(LeafT::DIM);
    TreeT tree(0.0f);
    test::SparseVolumeModel<float> model(0.0f);
    std::mt19937 rng(5);
    const Int32 span = 4 * leafDim;
    std::uniform_int_distribution<Int32> coord(-span, span - 1);
    for (int n = 0; n < 60; ++n) {
        const Coord ijk(coord(rng), coord(rng), coord(rng));
        const float value = float(n);
        const bool on = rng() % 2 == 0;
        if (rng() % 3 == 0) {
            tree.addTile(1, ijk, value, on);
            model.fill(CoordBBox::createCube(ijk.alignedDown(LeafT::LOG2DIM), leafDim), value, on);
        } else {
            auto leaf = std::make_unique<LeafT>(ijk, value, on);
            leaf->setValueOn(LeafT::coordToOffset(ijk), -value);
            const Coord origin = leaf->origin();
            tree.addLeaf(std::move(leaf));
            model.fill(CoordBBox::createCube(origin, leafDim), value, on);
            model.setValueOn(ijk, -value);
        }
    }
    expectBox(tree, model, CoordBBox(Coord(-span - leafDim), Coord(span + leafDim)));
}

TEST(TreeEditDomain, BoundedTreeRefusesLeavesAndTilesOutside) {
    using TreeT = tree::FixedTree643<float>;
    using LeafT = TreeT::LeafNodeType;
    TreeT tree(0.0f);
    const Coord outside = TreeT::domain().max().offsetBy(1);
    EXPECT_THROW(tree.addLeaf(std::make_unique<LeafT>(outside, 1.0f, true)), IndexError);
    EXPECT_THROW(tree.addTile(1, outside, 1.0f, true), IndexError);
    EXPECT_TRUE(tree.empty());
}

}  // namespace
}  // namespace vdb
