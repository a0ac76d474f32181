// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels fed the same writes
// as the tree (voxels, and boxes that the tree stores as tiles): copyToDense must give the
// model's value at every voxel of the box, and copyFromDense must leave the tree reading as
// the model after the same rule is applied voxel by voxel (active where the dense value
// differs from the background by more than the tolerance, inactive background elsewhere,
// everything outside the box unchanged).

#include <vdb/Grid.h>
#include <vdb/tools/Dense.h>
#include <vdb/tree/ValueAccessor.h>

#include "GridContents.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <vector>

namespace vdb {
namespace {

using test::SparseVolumeModel;

/// A tree with scattered voxels, a leaf-sized and a larger active tile, and an inactive tile of
/// a non-background value, mirrored in `model`.
template <typename TreeT>
void populate(TreeT& tree, SparseVolumeModel<typename TreeT::ValueType>& model, uint32_t seed) {
    using ValueT = typename TreeT::ValueType;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-20, 40);
    for (int n = 0; n < 400; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        const ValueT v = test::randomValue<ValueT>(rng);
        if (rng() % 4 == 0) {
            tree.setValueOff(ijk, v);
            model.setValueOff(ijk, v);
        } else {
            tree.setValueOn(ijk, v);
            model.setValueOn(ijk, v);
        }
    }
    const ValueT a = test::randomValue<ValueT>(rng), b = test::randomValue<ValueT>(rng);
    const CoordBBox leafTile(Coord(48, 0, 0), Coord(55, 7, 7));
    tree.fill(leafTile, a, true);
    model.fill(leafTile, a, true);
    const CoordBBox big(Coord(-128, -128, 0), Coord(-1, -1, 127));
    tree.fill(big, b, false);
    model.fill(CoordBBox(Coord(-30, -30, 0), Coord(-1, -1, 50)), b, false);  // the part we read
}

template <typename DenseT, typename ModelT>
void expectDenseMatches(const DenseT& dense, const ModelT& model) {
    const CoordBBox& box = dense.bbox();
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                ASSERT_EQ(dense.getValue(ijk), model.getValue(ijk)) << ijk;
            }
}

template <typename TreeT>
class DenseTyped : public ::testing::Test {};
using DenseTrees = ::testing::Types<FloatTree, DoubleTree, Int32Tree, Vec3STree, BoolTree>;
TYPED_TEST_SUITE(DenseTyped, DenseTrees);

TYPED_TEST(DenseTyped, CopyToDenseReadsEveryVoxelTileAndBackground) {
    using ValueT = typename TypeParam::ValueType;
    const ValueT bg = test::randomValue<ValueT>(3u);
    TypeParam tree(bg);
    SparseVolumeModel<ValueT> model(bg);
    populate(tree, model, 7);
    const CoordBBox box(Coord(-30, -25, -3), Coord(57, 41, 50));
    tools::Dense<ValueT> zyx(box);
    tools::copyToDense(tree, zyx);
    expectDenseMatches(zyx, model);
    tools::Dense<ValueT, tools::LayoutXYZ> xyz(box);
    tools::copyToDense(tree, xyz, /*serial=*/true);
    expectDenseMatches(xyz, model);
    // A view with reversed z and a padded y stride, as a NumPy slice would be.
    const auto e = box.extents();
    // (Not a std::vector: std::vector<bool> has no data().)
    const auto memory = std::make_unique<ValueT[]>(size_t(e[0] * (e[1] + 3) * e[2]));
    tools::Dense<ValueT> view(box, memory.get() + (e[2] - 1),
                              {std::ptrdiff_t((e[1] + 3) * e[2]), std::ptrdiff_t(e[2]), -1});
    tools::copyToDense(tree, view);
    expectDenseMatches(view, model);
}

TYPED_TEST(DenseTyped, CopyFromDenseAppliesTheToleranceRuleInsideTheBoxOnly) {
    using ValueT = typename TypeParam::ValueType;
    const ValueT bg = test::randomValue<ValueT>(11u);
    TypeParam tree(bg);
    SparseVolumeModel<ValueT> model(bg);
    populate(tree, model, 13);
    // Dense values: mostly the background (so that whole blocks come out constant), some
    // random, and one leaf-aligned block entirely of one value.
    const CoordBBox box(Coord(-13, -7, 2), Coord(50, 20, 33));
    tools::Dense<ValueT> dense(box);
    std::mt19937 rng(17);
    const ValueT constant = test::randomValue<ValueT>(rng);
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                ValueT v = rng() % 5 == 0 ? test::randomValue<ValueT>(rng) : bg;
                if (i >= 16 && i < 24 && j >= 8 && j < 16 && k >= 8 && k < 16)
                    v = constant;
                dense.setValue(ijk, v);
                if (v == bg)
                    model.setValueOff(ijk, bg);
                else
                    model.setValueOn(ijk, v);
            }
    TypeParam serial(tree);
    tools::copyFromDense(dense, tree, ValueT{});
    tools::copyFromDense(dense, serial, ValueT{}, /*serial=*/true);
    EXPECT_TRUE(test::treeContents(tree) == test::treeContents(serial));
    const CoordBBox check(Coord(-30, -30, -5), Coord(60, 45, 50));  // modelled part
    tree::ValueAccessor<const TypeParam> acc(tree);
    for (Int32 i = check.min()[0]; i <= check.max()[0]; ++i)
        for (Int32 j = check.min()[1]; j <= check.max()[1]; ++j)
            for (Int32 k = check.min()[2]; k <= check.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                ASSERT_EQ(acc.getValue(ijk), model.getValue(ijk)) << ijk;
                ASSERT_EQ(acc.isValueOn(ijk), model.isValueOn(ijk)) << ijk;
            }
    // The constant block became a tile, not a leaf.
    EXPECT_EQ(tree.probeConstLeaf(Coord(16, 8, 8)), nullptr);
}

TEST(Dense, ToleranceDecidesWhatIsBackground) {
    FloatTree tree(1.0f);
    tools::Dense<float> dense(CoordBBox(Coord(0), Coord(7)), 1.0f);
    dense.setValue(Coord(1, 2, 3), 1.05f);
    dense.setValue(Coord(4, 5, 6), 1.2f);
    tools::copyFromDense(dense, tree, 0.1f);
    EXPECT_EQ(tree.activeVoxelCount(), 1u);
    EXPECT_FALSE(tree.isValueOn(Coord(1, 2, 3)));
    EXPECT_EQ(tree.getValue(Coord(1, 2, 3)), 1.0f);
    EXPECT_EQ(tree.getValue(Coord(4, 5, 6)), 1.2f);
}

TEST(Dense, WholeContiguousBlocksFollowTheRuleForEverySpecialValue) {
    // Whole leaf-aligned blocks of a z-contiguous array take a vectorised path; every voxel must
    // still follow the rule: inactive background within the tolerance (NaN is within none),
    // active with its own value otherwise. Backgrounds of +0, -0 and NaN; tolerances 0 and 0.25.
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const CoordBBox box(Coord(-8, 0, 8), Coord(7, 15, 23));  // 2 x 2 x 2 whole leaves
    for (const float bg : {0.0f, -0.0f, 1.0f, nan}) {
        for (const float tol : {0.0f, 0.25f}) {
            std::mt19937 rng(5);
            const float special[] = {0.0f, -0.0f, 1.0f, 1.2f, 0.8f, 1.25f, 0.75f, inf, -inf, nan};
            tools::Dense<float> dense(box);
            for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
                for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                    for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                        dense.setValue(Coord(i, j, k), rng() % 2
                                                           ? special[rng() % std::size(special)]
                                                           : float(int(rng() % 9) - 4) * 0.125f);
            FloatTree tree(bg);
            tree.setValueOn(Coord(0, 3, 9), 7.0f);  // an existing leaf, replaced
            tools::copyFromDense(dense, tree, tol);
            const auto same = [](float a, float b) {
                return std::bit_cast<uint32_t>(a) == std::bit_cast<uint32_t>(b) ||
                       (std::isnan(a) && std::isnan(b));
            };
            for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
                for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
                    for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                        const Coord ijk{i, j, k};
                        const float v = dense.getValue(ijk);
                        const bool off = v == bg || std::abs(v - bg) <= tol;
                        ASSERT_EQ(tree.isValueOn(ijk), !off) << ijk << " " << v << " " << bg;
                        ASSERT_TRUE(same(tree.getValue(ijk), off ? bg : v))
                            << ijk << " " << v << " " << bg;
                    }
        }
    }
}

TEST(Dense, LongRunsOfMixedBlocksFollowTheRule) {
    // A run of 75 blocks along z (partial at both ends) where every third block is constant
    // (a tile, its leaf reused for the next block) and every fifth all background, beside an
    // existing leaf and an active tile, must give every voxel the rule's value, threaded or
    // not, and copy back exactly.
    const CoordBBox box(Coord(-3, 8, -4), Coord(12, 15, 8 * 73 + 2));
    tools::Dense<float> dense(box);
    std::mt19937 rng(29);
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Int32 block = (k >> 3) + 1;
                float v = float(rng() % 7) * 0.5f;  // 0 (the background) one time in seven
                if (block % 3 == 0)
                    v = 2.5f;
                else if (block % 5 == 0)
                    v = 0.0f;
                dense.setValue(Coord(i, j, k), v);
            }
    FloatTree tree(0.0f);
    tree.setValueOn(Coord(0, 9, 40), 9.0f);         // a leaf inside a whole block
    tree.addTile(1, Coord(8, 8, 128), 4.0f, true);  // an active tile, partly inside the box
    FloatTree serial(tree);
    tools::copyFromDense(dense, tree, 0.0f);
    tools::copyFromDense(dense, serial, 0.0f, /*serial=*/true);
    EXPECT_TRUE(test::treeContents(tree) == test::treeContents(serial));
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                const float v = dense.getValue(ijk);
                ASSERT_EQ(tree.isValueOn(ijk), v != 0.0f) << ijk;
                ASSERT_EQ(tree.getValue(ijk), v) << ijk;
            }
    // Outside the box, the tile's voxels keep their value and state.
    EXPECT_EQ(tree.getValue(Coord(14, 9, 130)), 4.0f);
    EXPECT_TRUE(tree.isValueOn(Coord(14, 9, 130)));
    // The constant whole blocks became tiles.
    EXPECT_EQ(tree.probeConstLeaf(Coord(0, 8, 8 * 2)), nullptr);
    EXPECT_EQ(tree.getValue(Coord(0, 8, 8 * 2)), 2.5f);
    // And back, over a box one voxel larger on every side (leaves, tiles and background).
    const CoordBBox wider(box.min().offsetBy(-1), box.max().offsetBy(1));
    tools::Dense<float> back(wider, -1.0f), backSerial(wider, -1.0f);
    tools::copyToDense(tree, back);
    tools::copyToDense(tree, backSerial, /*serial=*/true);
    tree::ValueAccessor<const FloatTree> acc(tree);
    for (Int32 i = wider.min()[0]; i <= wider.max()[0]; ++i)
        for (Int32 j = wider.min()[1]; j <= wider.max()[1]; ++j)
            for (Int32 k = wider.min()[2]; k <= wider.max()[2]; ++k) {
                const Coord ijk{i, j, k};
                ASSERT_EQ(back.getValue(ijk), acc.getValue(ijk)) << ijk;
                ASSERT_EQ(backSerial.getValue(ijk), acc.getValue(ijk)) << ijk;
            }
}

TEST(Dense, AllBackgroundBlockReplacesAnExistingLeaf) {
    FloatTree tree(0.0f);
    tree.setValueOn(Coord(3), 5.0f);
    tools::Dense<float> dense(CoordBBox(Coord(0), Coord(7)), 0.0f);
    tools::copyFromDense(dense, tree, 0.0f);
    EXPECT_EQ(tree.activeVoxelCount(), 0u);
    EXPECT_EQ(tree.getValue(Coord(3)), 0.0f);
    EXPECT_EQ(tree.leafCount(), 0u);
}

TEST(Dense, RoundTripIsExactAndLayoutsAgree) {
    auto grid = FloatGrid::create(-1.0f);
    const CoordBBox box(Coord(-9, 0, 5), Coord(30, 17, 44));
    tools::Dense<float> dense(box);
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                dense.setValue(Coord(i, j, k), u(rng));
    tools::copyFromDense(dense, *grid, 0.0f);
    EXPECT_EQ(grid->activeVoxelCount(), box.volume());
    tools::Dense<float, tools::LayoutXYZ> back(box);
    tools::copyToDense(*grid, back);
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                ASSERT_EQ(back.getValue(Coord(i, j, k)), dense.getValue(Coord(i, j, k)));
    EXPECT_EQ(dense.xStride(), 18 * 40);
    EXPECT_EQ(back.yStride(), 40);
    EXPECT_THROW(tools::Dense<float>{CoordBBox()}, ValueError);
}

}  // namespace
}  // namespace vdb
