// SPDX-License-Identifier: Apache-2.0
// Oracle: two SparseVolumeModels (tests/support/Oracles.h) fed the same writes as trees A and B,
// combined voxel by voxel: every voxel of A becomes op(a, b) and is active where either was
// (compMax, compMin, compSum, compMul, compDiv, combine), takes the value and state an extended
// op chooses (combineExtended), or takes B's value and state where B is active (compReplace). Every
// voxel of a box around both contents is checked, through tiles of either tree over leaves of the
// other; threaded runs must equal serial ones item for item.

#include <vdb/Grid.h>
#include <vdb/tools/Composite.h>
#include <vdb/tree/TreeConfigs.h>

#include "GridContents.h"
#include "VoxelChecks.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace vdb {
namespace {

using test::expectVoxels;
using test::SparseVolumeModel;

// The box checked: the voxels, and slabs of the level-2 tiles on either side of x = 0.
const CoordBBox kRegion(Coord(-32, -32, -24), Coord(32, 32, 24));

/// Random voxels in [-30, 30]^3 and tiles at level 1 and 2, some over the other tree's leaves.
template <typename TreeT>
void populate(TreeT& tree, SparseVolumeModel<typename TreeT::ValueType>& model, uint32_t seed) {
    using ValueT = typename TreeT::ValueType;
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> c(-30, 30);
    std::uniform_int_distribution<int> v(-6, 6);
    const auto value = [&] {
        if constexpr (std::is_arithmetic_v<ValueT>) {
            return ValueT(v(rng));
        } else {
            return ValueT(float(v(rng)), float(v(rng)), float(v(rng)));
        }
    };
    for (int n = 0; n < 1500; ++n) {
        const Coord ijk(c(rng), c(rng), c(rng));
        const ValueT x = value();
        test::setBoth(tree, model, ijk, x, rng() % 3 != 0);
    }
    for (int n = 0; n < 4; ++n) {
        const Coord origin = Coord(c(rng), c(rng), c(rng)).alignedDown(3);
        const ValueT x = value();
        test::fillBoth(tree, model, CoordBBox::createCube(origin, 8), x, rng() % 2 == 0);
    }
    // A level-2 tile beside the voxels (different per seed); the model holds only the part of
    // it that the checks visit.
    const CoordBBox big = CoordBBox::createCube(Coord(seed % 2 ? -128 : 0, 0, -128), 128);
    const ValueT x = value();
    tree.fill(big, x, seed % 3 == 0);
    model.fill(CoordBBox(Coord::maxComponent(big.min(), kRegion.min()),
                         Coord::minComponent(big.max(), kRegion.max())),
               x, seed % 3 == 0);
}

/// Runs `comp` on trees A (seed 1) and B (seed 2) and checks every voxel of A against
/// expect(a, b) with state aOn || bOn, B's emptiness, and threaded == serial.
template <typename TreeT, typename CompT, typename ExpectT>
void checkCombine(typename TreeT::ValueType bgA, typename TreeT::ValueType bgB, const CompT& comp,
                  const ExpectT& expect) {
    using ValueT = typename TreeT::ValueType;
    TreeT a(bgA), b(bgB);
    SparseVolumeModel<ValueT> ma(bgA), mb(bgB);
    populate(a, ma, 1);
    populate(b, mb, 2);
    TreeT a2(a), b2(b);
    comp(a, b, true);
    comp(a2, b2, false);
    EXPECT_TRUE(b.empty());
    EXPECT_TRUE(a.background() == expect(bgA, bgB));
    expectVoxels(a, kRegion, [&](const Coord& ijk) {
        return std::pair<ValueT, bool>(expect(ma.getValue(ijk), mb.getValue(ijk)),
                                       ma.isValueOn(ijk) || mb.isValueOn(ijk));
    });
    EXPECT_TRUE(a.getValue(Coord(5000, 5000, -5000)) == expect(bgA, bgB));
    EXPECT_TRUE(test::sameContents(a, a2));
}

TEST(CompositeOps, MaxMinSumMulDivOfFloatTrees) {
    const auto call = [](auto fn) {
        return [fn](FloatTree& a, FloatTree& b, bool threaded) { fn(a, b, threaded); };
    };
    checkCombine<FloatTree>(0.5f, -1.0f,
                            call([](auto& a, auto& b, bool t) { tools::compMax(a, b, t); }),
                            [](float a, float b) { return std::max(a, b); });
    checkCombine<FloatTree>(0.5f, -1.0f,
                            call([](auto& a, auto& b, bool t) { tools::compMin(a, b, t); }),
                            [](float a, float b) { return std::min(a, b); });
    checkCombine<FloatTree>(0.5f, 2.0f,
                            call([](auto& a, auto& b, bool t) { tools::compSum(a, b, t); }),
                            [](float a, float b) { return a + b; });
    checkCombine<FloatTree>(0.5f, 2.0f,
                            call([](auto& a, auto& b, bool t) { tools::compMul(a, b, t); }),
                            [](float a, float b) { return a * b; });
    checkCombine<FloatTree>(0.5f, 2.0f,
                            call([](auto& a, auto& b, bool t) { tools::compDiv(a, b, t); }),
                            [](float a, float b) { return a / b; });
}

TEST(CompositeOps, IntegerDivisionByZeroSaturates) {
    checkCombine<Int32Tree>(
        Int32(3), Int32(0), [](auto& a, auto& b, bool t) { tools::compDiv(a, b, t); },
        [](Int32 a, Int32 b) -> Int32 {
            if (b != 0)
                return a / b;
            if (a == 0)
                return 0;
            return a > 0 ? std::numeric_limits<Int32>::max() : -std::numeric_limits<Int32>::max();
        });
}

TEST(CompositeOps, VectorsCompareByLength) {
    const auto longer = [](const Vec3s& a, const Vec3s& b) {
        const float la = a.lengthSqr(), lb = b.lengthSqr();
        if (la != lb)
            return la < lb ? b : a;
        for (int i = 0; i < 3; ++i)
            if (a[i] != b[i])
                return a[i] < b[i] ? b : a;
        return a;
    };
    checkCombine<Vec3STree>(
        Vec3s(0.0f), Vec3s(1.0f, 0.0f, 0.0f),
        [](auto& a, auto& b, bool t) { tools::compMax(a, b, t); }, longer);
    checkCombine<Vec3STree>(
        Vec3s(0.0f), Vec3s(1.0f, 0.0f, 0.0f),
        [](auto& a, auto& b, bool t) { tools::compMin(a, b, t); },
        [&](const Vec3s& a, const Vec3s& b) { return longer(a, b) == a && !(a == b) ? b : a; });
}

TEST(CompositeOps, ReplaceCopiesTheActiveValuesOfB) {
    FloatTree a(0.0f), b(1.0f);
    SparseVolumeModel<float> ma(0.0f), mb(1.0f);
    populate(a, ma, 4);
    populate(b, mb, 5);
    const FloatTree bBefore(b);
    FloatTree a2(a);
    tools::compReplace(a, b);
    tools::compReplace(a2, b, false);
    expectVoxels(a, kRegion, [&](const Coord& ijk) {
        if (mb.isValueOn(ijk))
            return std::pair<float, bool>(mb.getValue(ijk), true);
        return std::pair<float, bool>(ma.getValue(ijk), ma.isValueOn(ijk));
    });
    EXPECT_TRUE(test::sameContents(b, bBefore));
    EXPECT_TRUE(test::sameContents(a, a2));
}

TEST(CompositeOps, CombineAppliesTheOpToEveryValue) {
    // OpenVDB's form: op(a, b, result); tiles and leaves on both sides, the backgrounds too.
    const auto op = [](float a, float b) { return 2.0f * a - b + 0.25f; };
    checkCombine<FloatTree>(
        0.5f, -1.0f,
        [&](FloatTree& a, FloatTree& b, bool threaded) {
            tools::combine(
                a, b, [&](const float& x, const float& y, float& r) { r = op(x, y); },
                /*prune=*/false, threaded);
        },
        op);
    checkCombine<Int32Tree>(
        Int32(3), Int32(-2),
        [](Int32Tree& a, Int32Tree& b, bool threaded) {
            tools::combine(
                a, b, [](const Int32& x, const Int32& y, Int32& r) { r = x * 3 + y; }, false,
                threaded);
        },
        [](Int32 a, Int32 b) { return a * 3 + b; });
}

TEST(CompositeOps, CombineExtendedSetsTheStatesTheOpChooses) {
    // Active only where both are; the value of b where b alone is active.
    const auto value = [](float a, bool aOn, float b, bool bOn) {
        return bOn && !aOn ? b : a + 1.0f;
    };
    for (bool threaded : {false, true}) {
        FloatTree a(0.5f), b(-1.0f);
        SparseVolumeModel<float> ma(0.5f), mb(-1.0f);
        populate(a, ma, 1);
        populate(b, mb, 2);
        tools::combineExtended(
            a, b,
            [&](CombineArgs<float>& args) {
                args.setResult(value(args.a(), args.aIsActive(), args.b(), args.bIsActive()));
                args.setResultIsActive(args.aIsActive() && args.bIsActive());
            },
            false, threaded);
        EXPECT_TRUE(b.empty());
        EXPECT_EQ(a.background(), 1.5f);
        expectVoxels(a, kRegion, [&](const Coord& ijk) {
            const bool aOn = ma.isValueOn(ijk), bOn = mb.isValueOn(ijk);
            return std::pair<float, bool>(value(ma.getValue(ijk), aOn, mb.getValue(ijk), bOn),
                                          aOn && bOn);
        });
    }
}

TEST(CompositeOps, CombineWithPruneCollapsesConstantNodesBelowTheTop) {
    // A constant result: every leaf whose states are uniform becomes a tile, and so does every
    // node left with uniform tiles, but the top node's children stay (as in OpenVDB).
    FloatTree a(0.5f), b(-1.0f);
    SparseVolumeModel<float> ma(0.5f), mb(-1.0f);
    populate(a, ma, 1);
    populate(b, mb, 2);
    tools::combine(
        a, b, [](const float&, const float&, float& r) { r = 7.0f; }, true);
    expectVoxels(a, kRegion, [&](const Coord& ijk) {
        return std::pair<float, bool>(7.0f, ma.isValueOn(ijk) || mb.isValueOn(ijk));
    });
    EXPECT_GT(a.leafCount(), 0u);
    for (auto leaf = a.cbeginLeaf(); leaf; ++leaf) {
        const auto& mask = leaf->getValueMask();
        EXPECT_FALSE(mask.isOn() || mask.isOff()) << leaf->origin();
    }
    FloatTree same(a);
    same.prune();
    EXPECT_EQ(a.leafCount(), same.leafCount());
    // The root's children are not pruned: a level-2 node of only active 7s stays.
    FloatTree c(0.0f), d(0.0f);
    c.fill(CoordBBox::createCube(Coord(0), 4096), 1.0f, true);
    c.setValueOn(Coord(1), 2.0f);  // a branch down to a leaf below the root tile
    tools::combine(
        c, d, [](const float&, const float&, float& r) { r = 7.0f; }, true);
    EXPECT_EQ(c.leafCount(), 0u);
    EXPECT_EQ(c.nonLeafCount(), 2u);  // the root and its child, now constant
    EXPECT_EQ(c.getValue(Coord(1)), 7.0f);
    EXPECT_THROW(tools::combine(
                     c, c, [](const float&, const float&, float& r) { r = 0.0f; }, true),
                 ValueError);
}

TEST(CompositeOps, GridFormsCheckTransforms) {
    auto a = FloatGrid::create(0.0f), b = FloatGrid::create(0.0f);
    a->tree().setValueOn(Coord(1, 2, 3), 2.0f);
    b->tree().setValueOn(Coord(1, 2, 3), 5.0f);
    tools::compMax(*a, *b);
    EXPECT_EQ(a->tree().getValue(Coord(1, 2, 3)), 5.0f);
    b->setTransform(math::Transform::createLinearTransform(2.0));
    EXPECT_THROW(tools::compSum(*a, *b), ValueError);
    EXPECT_THROW(tools::compMax(a->tree(), a->tree()), ValueError);
}

}  // namespace
}  // namespace vdb
