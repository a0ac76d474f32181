// SPDX-License-Identifier: Apache-2.0
// Oracles: the distance of two integers computed exactly in a wider type (or by hand at the
// extremes of int64), and a snapshot of every voxel of a tree taken before pruning: an exact
// prune must leave every voxel's value and state as the snapshot has it, whatever the values.

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/ValueAccessor.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <unordered_map>
#include <vector>

namespace vdb {
namespace {

template <typename T>
constexpr T kMin = std::numeric_limits<T>::min();
template <typename T>
constexpr T kMax = std::numeric_limits<T>::max();

TEST(ValueComparison, IntegersOfOppositeSignAtTheExtremesAreFarApart) {
    using math::isApproxEqual;
    // int32: every pair of the set compared against the exact distance in int64.
    const std::vector<Int32> values = {kMin<Int32>, kMin<Int32> + 1, -2,         -1, 0, 1,
                                       2,           kMax<Int32> - 1, kMax<Int32>};
    for (Int32 a : values) {
        for (Int32 b : values) {
            const Int64 distance = std::abs(Int64(a) - Int64(b));
            EXPECT_EQ(math::absDiff(a, b), uint32_t(distance)) << a << " " << b;
            EXPECT_EQ(isApproxEqual(a, b, Int32(0)), a == b) << a << " " << b;
            EXPECT_EQ(isApproxEqual(a, b), a == b) << a << " " << b;
            for (Int32 tol : {Int32(1), Int32(2), kMax<Int32>}) {
                EXPECT_EQ(isApproxEqual(a, b, tol), distance <= Int64(tol))
                    << a << " " << b << " tol " << tol;
            }
        }
    }
    // The pair that a difference in int32 turned into a tiny distance: 2^31 - 1 - (-1).
    EXPECT_FALSE(isApproxEqual(kMax<Int32>, Int32(-1), Int32(0)));
    EXPECT_FALSE(isApproxEqual(Int32(-1), kMax<Int32>, Int32(5)));
    EXPECT_FALSE(isApproxEqual(kMin<Int32>, Int32(1), Int32(5)));

    // int64 at its extremes: the distances are known without a wider type.
    EXPECT_EQ(math::absDiff(kMax<Int64>, kMin<Int64>), ~uint64_t(0));
    EXPECT_FALSE(isApproxEqual(kMax<Int64>, kMin<Int64>, kMax<Int64>));
    EXPECT_FALSE(isApproxEqual(kMax<Int64>, Int64(-1), Int64(0)));
    // max - (-1) = 2^63, one above the largest tolerance int64 can express.
    EXPECT_EQ(math::absDiff(kMax<Int64>, Int64(-1)), uint64_t(1) << 63);
    EXPECT_FALSE(isApproxEqual(kMax<Int64>, Int64(-1), kMax<Int64>));
    EXPECT_TRUE(isApproxEqual(kMax<Int64>, Int64(0), kMax<Int64>));
}

TEST(ValueComparison, NegativeToleranceMatchesOnlyEqualValues) {
    EXPECT_TRUE(math::isApproxEqual(5, 5, -1));
    EXPECT_FALSE(math::isApproxEqual(5, 4, -1));
    EXPECT_TRUE(math::isApproxEqual(1.5f, 1.5f, -1.0f));
    EXPECT_FALSE(math::isApproxEqual(1.5f, 1.25f, -1.0f));
}

TEST(ValueComparison, FloatingPointExtremesAndNan) {
    using math::isApproxEqual;
    const float inf = std::numeric_limits<float>::infinity();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float big = std::numeric_limits<float>::max();
    EXPECT_TRUE(isApproxEqual(inf, inf, 0.0f));
    EXPECT_FALSE(isApproxEqual(inf, -inf, big));
    EXPECT_FALSE(isApproxEqual(inf, 1.0f, big));
    EXPECT_FALSE(isApproxEqual(big, -big, big));  // the difference overflows to infinity
    EXPECT_FALSE(isApproxEqual(nan, nan, 1.0f));
    EXPECT_FALSE(isApproxEqual(nan, 1.0f, inf));
    EXPECT_FALSE(isApproxEqual(1.0f, nan, inf));
    EXPECT_TRUE(isApproxEqual(1.0f, 1.5f, 0.5f));
    EXPECT_FALSE(isApproxEqual(1.0f, 1.5f, 0.4999f));
    EXPECT_TRUE(isApproxEqual(0.0f, -0.0f, 0.0f));
    EXPECT_FALSE(math::isRelOrApproxEqual(nan, nan, 1.0f, 1.0f));
    EXPECT_TRUE(math::isRelOrApproxEqual(1e20f, 1.0000005e20f, 0.0f, 1e-6f));
    EXPECT_FALSE(math::isRelOrApproxEqual(1e20f, 1.00001e20f, 0.0f, 1e-6f));
    EXPECT_TRUE(math::isRelOrApproxEqual(kMin<Int32>, kMax<Int32>, 0, 2));
    EXPECT_FALSE(math::isRelOrApproxEqual(kMin<Int32>, kMax<Int32>, 0, 1));
}

TEST(ValueComparison, VectorsCompareEveryComponentWithoutOverflow) {
    using math::isApproxEqual;
    const Vec3i a(kMax<Int32>, 0, 0), b(-1, 0, 0);
    EXPECT_FALSE(isApproxEqual(a, b, Vec3i(0)));
    EXPECT_FALSE(isApproxEqual(a, b));
    EXPECT_TRUE(isApproxEqual(a, a));
    // OpenVDB's default for float vectors: within 1e-7, absolute or relative.
    EXPECT_TRUE(isApproxEqual(Vec3s(1e6f, 0, 0), Vec3s(1e6f + 0.0625f, 0, 0)));
    EXPECT_FALSE(isApproxEqual(Vec3s(1e6f, 0, 0), Vec3s(1e6f + 1.0f, 0, 0)));
    EXPECT_FALSE(isApproxEqual(Vec3s(0, 0, std::nanf("")), Vec3s(0, 0, std::nanf(""))));
}

TEST(ValueComparison, BoolsCompareExactly) {
    EXPECT_TRUE(math::isApproxEqual(true, true, false));
    EXPECT_FALSE(math::isApproxEqual(true, false, true));
    EXPECT_EQ(math::absDiff(true, false), true);
}

TEST(ValueComparison, DifferenceComparisonIsExactForIntegerComponents) {
    EXPECT_GT(math::compareDifference(Int32(-1), kMax<Int32>, Int32(0)), 0);
    EXPECT_GT(math::compareDifference(kMin<Int32>, kMax<Int32>, kMax<Int32>), 0);
    EXPECT_EQ(math::compareDifference(Int32(-1), kMax<Int32>, kMin<Int32>), 1);
    EXPECT_EQ(math::compareDifference(Int32(3), Int32(5), Int32(2)), 0);
    EXPECT_LT(math::compareDifference(Int32(3), Int32(4), Int32(2)), 0);
    EXPECT_EQ(math::compareDifference(uint32_t(0), ~uint32_t(0), ~uint32_t(0)), 0);
}

// ---- Pruning integer trees over their whole range ----------------------------------------------

/// Every voxel of `tree` and its state, read through the tree's API.
template <typename TreeT>
using Snapshot = std::unordered_map<Coord, std::pair<typename TreeT::ValueType, bool>>;

template <typename TreeT>
Snapshot<TreeT> snapshot(const TreeT& tree, const std::vector<Coord>& coords) {
    Snapshot<TreeT> out;
    for (const Coord& ijk : coords)
        out[ijk] = {tree.getValue(ijk), tree.isValueOn(ijk)};
    return out;
}

/// Fills the 8^3 leaves at `origins` with one value and one state, then puts one voxel of a
/// value of the opposite sign at the other end of the type's range in some of them; returns
/// every coordinate of those leaves.
template <typename TreeT>
std::vector<Coord> populateExtremes(TreeT& tree, uint32_t seed) {
    using ValueT = typename TreeT::ValueType;
    std::mt19937 rng(seed);
    const std::vector<ValueT> palette = {
        kMin<ValueT>, ValueT(kMin<ValueT> + 1), ValueT(-1),  ValueT(0),
        ValueT(1),    ValueT(kMax<ValueT> - 1), kMax<ValueT>};
    std::vector<Coord> coords;
    tree::ValueAccessor<TreeT> acc(tree);
    for (int n = 0; n < 64; ++n) {
        const Coord origin(Int32(n % 4) * 8, Int32(n / 4 % 4) * 8, Int32(n / 16) * 8);
        const ValueT fill = palette[rng() % palette.size()];
        const bool on = rng() % 2 == 0;
        for (Int32 i = 0; i < 8; ++i)
            for (Int32 j = 0; j < 8; ++j)
                for (Int32 k = 0; k < 8; ++k) {
                    const Coord ijk = origin.offsetBy(i, j, k);
                    on ? acc.setValueOn(ijk, fill) : acc.setValueOff(ijk, fill);
                    coords.push_back(ijk);
                }
        if (n % 3 != 0) {
            // One voxel at the other end of the range: 2^31 - 1 and -1 are 2^31 apart.
            const ValueT odd =
                fill < ValueT(0) ? kMax<ValueT> : ValueT(fill == ValueT(-1) ? kMax<ValueT> : -1);
            const Coord ijk = origin.offsetBy(Int32(rng() % 8), Int32(rng() % 8), Int32(rng() % 8));
            on ? acc.setValueOn(ijk, odd) : acc.setValueOff(ijk, odd);
        }
    }
    return coords;
}

template <typename TreeT>
class IntegerPrune : public ::testing::Test {};
using IntegerTrees = ::testing::Types<Int32Tree, Int64Tree>;
TYPED_TEST_SUITE(IntegerPrune, IntegerTrees);

TYPED_TEST(IntegerPrune, ExactTreePruneKeepsEveryValueAcrossTheWholeRange) {
    TypeParam tree(0);
    const std::vector<Coord> coords = populateExtremes(tree, 7);
    const auto before = snapshot(tree, coords);
    const Index64 leavesBefore = tree.leafCount();
    tree.prune();
    EXPECT_EQ(snapshot(tree, coords), before);
    // The constant leaves became tiles; the ones with an odd voxel stayed.
    EXPECT_LT(tree.leafCount(), leavesBefore);
    EXPECT_EQ(tree.leafCount(), 42u);  // 64 leaves, one in three (n % 3 == 0) constant
}

TYPED_TEST(IntegerPrune, ThreadedPruneKeepsEveryValueAcrossTheWholeRange) {
    TypeParam tree(0);
    const std::vector<Coord> coords = populateExtremes(tree, 11);
    const auto before = snapshot(tree, coords);
    tools::prune(tree);
    EXPECT_EQ(snapshot(tree, coords), before);
    EXPECT_EQ(tree.leafCount(), 42u);
}

TYPED_TEST(IntegerPrune, ToleranceBelowTheSpreadKeepsLeavesWithBothEnds) {
    using ValueT = typename TypeParam::ValueType;
    // A leaf of -1 with one voxel of the maximum: spread 2^31 (2^63), above any tolerance
    // of at most max - 1.
    for (const bool threaded : {false, true}) {
        TypeParam tree(0);
        tree.touchLeaf(Coord(0))->fill(ValueT(-1), true);
        tree.setValue(Coord(1, 2, 3), kMax<ValueT>);
        if (threaded)
            tools::prune(tree, ValueT(kMax<ValueT> - 1));
        else
            tree.prune(ValueT(kMax<ValueT> - 1));
        EXPECT_EQ(tree.leafCount(), 1u) << threaded;
        EXPECT_EQ(tree.getValue(Coord(1, 2, 3)), kMax<ValueT>) << threaded;
        // With the largest tolerance, the spread of max - (-1) still exceeds it by one.
        tree.prune(kMax<ValueT>);
        EXPECT_EQ(tree.leafCount(), 1u) << threaded;
    }
    // A spread equal to the tolerance prunes: 0 and max are max apart.
    TypeParam tree(0);
    tree.touchLeaf(Coord(0))->fill(ValueT(0), true);
    tree.setValue(Coord(1, 2, 3), kMax<ValueT>);
    tools::prune(tree, kMax<ValueT>);
    EXPECT_EQ(tree.leafCount(), 0u);
}

TYPED_TEST(IntegerPrune, NodeIsConstantComparesExactDistances) {
    using ValueT = typename TypeParam::ValueType;
    using LeafT = typename TypeParam::LeafNodeType;
    LeafT leaf(Coord(0), kMax<ValueT>, true);
    leaf.setValueOn(Coord(0), ValueT(-1));
    ValueT first{};
    bool state = false;
    EXPECT_FALSE(leaf.isConstant(first, state, ValueT(0)));
    EXPECT_FALSE(leaf.isConstant(first, state, ValueT(kMax<ValueT> - 1)));
    leaf.setValueOn(Coord(0), kMax<ValueT>);
    EXPECT_TRUE(leaf.isConstant(first, state, ValueT(0)));
    EXPECT_EQ(first, kMax<ValueT>);
    EXPECT_TRUE(state);
}

TEST(VectorPrune, IntegerVectorSpreadIsExact) {
    Vec3ITree tree(Vec3i(0));
    tree.touchLeaf(Coord(0))->fill(Vec3i(-1, 0, 0), true);
    tree.setValue(Coord(4), Vec3i(kMax<Int32>, 0, 0));
    tools::prune(tree);
    tree.prune();
    EXPECT_EQ(tree.leafCount(), 1u);
    EXPECT_EQ(tree.getValue(Coord(4)), Vec3i(kMax<Int32>, 0, 0));
    EXPECT_EQ(tree.getValue(Coord(5)), Vec3i(-1, 0, 0));
}

TEST(FloatPrune, NanIsNeverPrunedAway) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const bool threaded : {false, true}) {
        FloatTree tree(0.0f);
        tree.touchLeaf(Coord(0))->fill(1.0f, true);
        tree.setValue(Coord(3), nan);
        if (threaded)
            tools::prune(tree, 1e30f);
        else
            tree.prune(1e30f);
        EXPECT_EQ(tree.leafCount(), 1u) << threaded;
        EXPECT_TRUE(std::isnan(tree.getValue(Coord(3)))) << threaded;
        EXPECT_EQ(tree.getValue(Coord(4)), 1.0f) << threaded;
    }
    // Infinities of one sign are one value; of both signs, not within any tolerance.
    FloatTree tree(0.0f);
    const float inf = std::numeric_limits<float>::infinity();
    tree.touchLeaf(Coord(0))->fill(inf, true);
    tree.touchLeaf(Coord(8, 0, 0))->fill(inf, true);
    tree.setValue(Coord(8, 0, 0), -inf);
    tools::prune(tree, std::numeric_limits<float>::max());
    EXPECT_EQ(tree.leafCount(), 1u);
    EXPECT_EQ(tree.getValue(Coord(8, 0, 0)), -inf);
    EXPECT_EQ(tree.getValue(Coord(0)), inf);
}

TEST(SignedFloodFillValues, IntegerMinimumBackgroundIsRejected) {
    Int32Tree tree(kMin<Int32>);
    tree.setValue(Coord(0), 5);
    EXPECT_THROW(tools::signedFloodFill(tree), ValueError);
    EXPECT_THROW(tools::signedFloodFillWithValues(tree, 3, kMin<Int32>), ValueError);
    EXPECT_EQ(tree.getValue(Coord(0)), 5);
    // The largest magnitude the type holds works.
    Int32Tree ok(kMax<Int32>);
    ok.setValue(Coord(0), -5);
    ok.setValue(Coord(0, 0, 2), 5);
    tools::signedFloodFill(ok);
    EXPECT_EQ(ok.background(), kMax<Int32>);
}

}  // namespace
}  // namespace vdb
