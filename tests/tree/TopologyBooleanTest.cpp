// SPDX-License-Identifier: Apache-2.0
// Oracle: plain coordinate sets. Each tree is built from an ActiveSet (a std::set<Coord> of
// active voxels plus active boxes, which the tree stores as tiles where they cover whole nodes);
// the expected result of a boolean is the set operation on the two models, checked in both
// directions (every active value of the result is expected, every expected voxel is active).
// Values are checked against a copy of the tree taken before the operation.

#include <vdb/Grid.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

namespace vdb {
namespace {

enum class Op { Union, Intersection, Difference };

bool expectedState(Op op, bool inA, bool inB) {
    switch (op) {
        case Op::Union:
            return inA || inB;
        case Op::Intersection:
            return inA && inB;
        default:
            return inA && !inB;
    }
}

const char* opName(Op op) {
    return op == Op::Union ? "union" : op == Op::Intersection ? "intersection" : "difference";
}

/// A set of active voxels: single voxels plus boxes.
struct ActiveSet {
    std::set<Coord> voxels;
    std::vector<CoordBBox> boxes;

    bool contains(const Coord& ijk) const {
        for (const CoordBBox& box : boxes) {
            if (box.isInside(ijk))
                return true;
        }
        return voxels.count(ijk) > 0;
    }
    /// True when every voxel of `bbox` lies in one of the boxes.
    bool coversBox(const CoordBBox& bbox) const {
        for (const CoordBBox& box : boxes) {
            if (box.isInside(bbox))
                return true;
        }
        return false;
    }
    /// True when no voxel of `bbox` is in the set.
    bool disjointFrom(const CoordBBox& bbox) const {
        for (const CoordBBox& box : boxes) {
            if (box.hasOverlap(bbox))
                return false;
        }
        for (const Coord& ijk : voxels) {
            if (bbox.isInside(ijk))
                return false;
        }
        return true;
    }
    /// Calls fn on every voxel, and on the voxels of every `stride`-th x-y row of the boxes.
    template <typename Fn>
    void forEach(Fn&& fn, Int32 stride = 1) const {
        for (const Coord& ijk : voxels)
            fn(ijk);
        for (const CoordBBox& box : boxes) {
            for (Int32 x = box.min()[0]; x <= box.max()[0]; x += stride)
                for (Int32 y = box.min()[1]; y <= box.max()[1]; y += stride)
                    for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z)
                        fn(Coord(x, y, z));
        }
    }
};

/// True when every voxel of `bbox` is certainly expected; false means "check voxel by voxel".
bool wholeBoxExpected(Op op, const ActiveSet& a, const ActiveSet& b, const CoordBBox& bbox) {
    switch (op) {
        case Op::Union:
            return a.coversBox(bbox) || b.coversBox(bbox);
        case Op::Intersection:
            return a.coversBox(bbox) && b.coversBox(bbox);
        default:
            return a.coversBox(bbox) && b.disjointFrom(bbox);
    }
}

/// The active set of `tree` equals { ijk : expectedState(op, a(ijk), b(ijk)) }.
template <typename TreeT>
::testing::AssertionResult activeSetMatches(const TreeT& tree, Op op, const ActiveSet& a,
                                            const ActiveSet& b) {
    // Every active voxel or tile voxel of the result is expected.
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        if (it.isTileValue() && wholeBoxExpected(op, a, b, box))
            continue;
        for (Int32 x = box.min()[0]; x <= box.max()[0]; ++x)
            for (Int32 y = box.min()[1]; y <= box.max()[1]; ++y)
                for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z) {
                    const Coord ijk(x, y, z);
                    if (!expectedState(op, a.contains(ijk), b.contains(ijk)))
                        return ::testing::AssertionFailure()
                               << opName(op) << ": " << ijk << " is active but should not be";
                }
    }
    // Every expected voxel is active (expected voxels lie in a, or in b for a union).
    typename TreeT::ConstAccessor acc(tree);
    Coord missing;
    bool ok = true;
    auto check = [&](const Coord& ijk) {
        if (ok && !acc.isValueOn(ijk) && expectedState(op, a.contains(ijk), b.contains(ijk))) {
            ok = false;
            missing = ijk;
        }
    };
    // The sanitizer's reduced workload samples every third row of the boxes.
    const Int32 stride = test::workloadScale() < 0.5 ? 3 : 1;
    a.forEach(check, stride);
    if (op == Op::Union)
        b.forEach(check, stride);
    if (!ok)
        return ::testing::AssertionFailure()
               << opName(op) << ": " << missing << " should be active but is not";
    return ::testing::AssertionSuccess();
}

template <typename TreeT>
constexpr bool IS_MASK_TREE = std::is_same_v<typename TreeT::BuildType, ValueMask>;

template <typename ValueT>
ValueT randomValue(std::mt19937& rng) {
    if constexpr (std::is_same_v<ValueT, bool>) {
        return (rng() & 1u) != 0;
    } else if constexpr (std::is_floating_point_v<ValueT>) {
        return ValueT(int(rng() % 2000u) - 1000) / ValueT(8);
    } else if constexpr (std::is_integral_v<ValueT>) {
        return ValueT(int(rng() % 2000u) - 1000);
    } else {
        using T = typename ValueT::ValueType;
        return ValueT(T(int(rng() % 200u) - 100), T(int(rng() % 200u) - 100),
                      T(int(rng() % 200u) - 100));
    }
}

template <typename ValueT>
ValueT testBackground() {
    if constexpr (std::is_same_v<ValueT, bool>) {
        return false;
    } else if constexpr (std::is_arithmetic_v<ValueT>) {
        return ValueT(3);
    } else {
        return ValueT(1, 2, 3);
    }
}

/// What one tree of a test holds: active boxes and voxels (the model) and inactive boxes and
/// voxels with non-background values (which the booleans must leave alone or free).
struct Scene {
    ActiveSet active;
    std::vector<CoordBBox> inactiveBoxes;
    std::vector<Coord> inactiveVoxels;

    /// Writes the scene into `tree`: inactive boxes, active boxes, inactive voxels, active
    /// voxels, in that order (inactive voxels avoid the active boxes, so the model holds).
    template <typename TreeT>
    void build(TreeT& tree, uint32_t seed) const {
        using ValueT = typename TreeT::ValueType;
        std::mt19937 rng(seed);
        if constexpr (IS_MASK_TREE<TreeT>) {
            for (const CoordBBox& box : active.boxes)
                tree.fill(box, true, true);
            for (const Coord& ijk : active.voxels)
                tree.setValueOn(ijk);
        } else {
            for (const CoordBBox& box : inactiveBoxes)
                tree.fill(box, randomValue<ValueT>(rng), false);
            for (const CoordBBox& box : active.boxes)
                tree.fill(box, randomValue<ValueT>(rng), true);
            for (const Coord& ijk : inactiveVoxels)
                tree.setValueOff(ijk, randomValue<ValueT>(rng));
            for (const Coord& ijk : active.voxels)
                tree.setValueOn(ijk, randomValue<ValueT>(rng));
        }
    }
};

Coord randomCoord(std::mt19937& rng, Int32 lo, Int32 hi) {
    std::uniform_int_distribution<Int32> d(lo, hi - 1);
    return Coord(d(rng), d(rng), d(rng));
}

/// Two scenes scaled to a tree whose level-1 nodes have edge `d1`: tiles on either side over
/// tiles, over children and over nothing; partial boxes and random voxels, dense near the
/// origin and sparse further out, in every octant.
std::pair<Scene, Scene> makeScenes(Int32 d1, uint32_t seed) {
    std::mt19937 rng(seed);
    const int dense = std::max(20, int(1500 * test::workloadScale()));
    const int sparse = std::max(10, int(300 * test::workloadScale()));
    Scene a, b;
    // A: an active tile, two inactive non-background tiles, a partial box across the origin.
    a.active.boxes.push_back(CoordBBox::createCube(Coord(-d1), d1));
    a.inactiveBoxes.push_back(CoordBBox::createCube(Coord(0, -d1, 0), d1));
    a.inactiveBoxes.push_back(CoordBBox::createCube(Coord(-2 * d1, -d1, -2 * d1), d1));
    a.active.boxes.push_back(
        CoordBBox(Coord(-d1 / 2 - 3, -5, -d1 / 4), Coord(d1 / 2 + 2, 6, d1 / 4)));
    // B: the same active tile (tile over tile), an active tile over A's children near the
    // origin, an active tile over A's inactive tile, a partial box inside A's active tile
    // (children under A's tile), and voxels under A's inactive tile.
    b.active.boxes.push_back(CoordBBox::createCube(Coord(-d1), d1));
    b.active.boxes.push_back(CoordBBox::createCube(Coord(0, 0, -d1), d1));
    b.active.boxes.push_back(CoordBBox::createCube(Coord(-2 * d1, -d1, -2 * d1), d1));
    b.active.boxes.push_back(CoordBBox(Coord(-d1 + 3, -d1 + 5, -d1 + 2), Coord(-d1 + 20)));
    b.inactiveBoxes.push_back(CoordBBox::createCube(Coord(d1, d1, d1), d1));
    for (int i = 0; i < sparse / 3; ++i)
        b.active.voxels.insert(randomCoord(rng, 0, d1) + Coord(0, -d1, 0));
    // Random voxels on both sides.
    for (Scene* s : {&a, &b}) {
        for (int i = 0; i < dense; ++i)
            s->active.voxels.insert(randomCoord(rng, -d1 / 2, d1 / 2));
        for (int i = 0; i < sparse; ++i)
            s->active.voxels.insert(randomCoord(rng, -2 * d1, 2 * d1));
        for (int i = 0; i < sparse; ++i) {
            const Coord ijk = randomCoord(rng, -d1, d1);
            bool inBox = false;
            for (const CoordBBox& box : s->active.boxes)
                inBox = inBox || box.isInside(ijk);
            if (!inBox)
                s->inactiveVoxels.push_back(ijk);
        }
    }
    return {a, b};
}

template <typename TreeT>
constexpr Int32 levelOneDim() {
    return Int32(tree::NodeAtLevelT<typename TreeT::TopNodeType, 1>::DIM);
}

/// Values after the operation: unchanged where the result is active; for a union unchanged
/// everywhere; otherwise unchanged or the background (where a branch was freed). In a mask
/// tree every value equals its state.
template <typename TreeT>
::testing::AssertionResult valuesMatch(const TreeT& before, const TreeT& after, Op op,
                                       const std::vector<Coord>& probes) {
    typename TreeT::ConstAccessor was(before), is(after);
    auto compare = [&](const Coord& ijk) -> ::testing::AssertionResult {
        typename TreeT::ValueType value;
        const bool on = is.probeValue(ijk, value);
        if constexpr (IS_MASK_TREE<TreeT>) {
            if (value != on)
                return ::testing::AssertionFailure() << "mask value differs from state at " << ijk;
        } else {
            const auto old = was.getValue(ijk);
            const bool mayBeBackground = op != Op::Union && !on;
            if (!(value == old) && !(mayBeBackground && value == after.background()))
                return ::testing::AssertionFailure()
                       << opName(op) << ": value at " << ijk << " changed";
        }
        return ::testing::AssertionSuccess();
    };
    for (const Coord& ijk : probes) {
        auto result = compare(ijk);
        if (!result)
            return result;
    }
    for (auto it = after.cbeginValueOn(); it; ++it) {
        if (it.isVoxelValue()) {
            auto result = compare(it.getCoord());
            if (!result)
                return result;
        }
    }
    if constexpr (IS_MASK_TREE<TreeT>) {
        for (auto it = after.cbeginValueAll(); it; ++it) {
            if (it.isTileValue() && it.getValue() != it.isValueOn())
                return ::testing::AssertionFailure()
                       << "mask tile at " << it.getCoord() << " has value != state";
        }
    }
    return ::testing::AssertionSuccess();
}

template <typename A, typename B>
struct TreePair {
    using TreeA = A;
    using TreeB = B;
};

template <typename P>
class TopologyBoolean : public ::testing::Test {
protected:
    using TreeA = typename P::TreeA;
    using TreeB = typename P::TreeB;
    using ValueA = typename TreeA::ValueType;
    using ValueB = typename TreeB::ValueType;
    static constexpr Int32 D1 = levelOneDim<TreeA>();

    void SetUp() override {
        auto [sa, sb] = makeScenes(D1, 20130601);
        sceneA = sa;
        sceneB = sb;
        sceneA.build(a, 11);
        sceneB.build(b, 12);
        std::mt19937 rng(7);
        for (int i = 0; i < int(20000 * test::workloadScale()) + 100; ++i)
            probes.push_back(randomCoord(rng, -2 * D1 - 8, 2 * D1 + 8));
        for (const Scene* s : {&sceneA, &sceneB}) {
            probes.insert(probes.end(), s->active.voxels.begin(), s->active.voxels.end());
            probes.insert(probes.end(), s->inactiveVoxels.begin(), s->inactiveVoxels.end());
        }
    }

    void run(Op op, bool preserveTiles = false) {
        TreeA result(a);
        switch (op) {
            case Op::Union:
                result.topologyUnion(b, preserveTiles);
                break;
            case Op::Intersection:
                result.topologyIntersection(b);
                break;
            case Op::Difference:
                result.topologyDifference(b);
                break;
        }
        EXPECT_TRUE(activeSetMatches(result, op, sceneA.active, sceneB.active));
        EXPECT_TRUE(valuesMatch(a, result, op, probes));
    }

    TreeA a{testBackground<ValueA>()};
    TreeB b{testBackground<ValueB>()};
    Scene sceneA, sceneB;
    std::vector<Coord> probes;
};

using Pairs = ::testing::Types<TreePair<FloatTree, FloatTree>, TreePair<FloatTree, BoolTree>,
                               TreePair<FloatTree, MaskTree>, TreePair<Int32Tree, Vec3STree>,
                               TreePair<MaskTree, FloatTree>,
                               TreePair<tree::FixedTree3333<float>, tree::FixedTree3333<ValueMask>>,
                               TreePair<tree::FixedTree643<float>, tree::FixedTree643<Int64>>,
                               TreePair<tree::MapTree432<float>, tree::HashTree432<bool>>>;

struct PairName {
    template <typename P>
    static std::string GetName(int i) {
        return "Pair" + std::to_string(i);
    }
};
TYPED_TEST_SUITE(TopologyBoolean, Pairs, PairName);

TYPED_TEST(TopologyBoolean, UnionActivatesEveryVoxelActiveInEither) {
    this->run(Op::Union);
}

TYPED_TEST(TopologyBoolean, UnionWithPreservedTilesHasTheSameActiveSet) {
    this->run(Op::Union, /*preserveTiles=*/true);
}

TYPED_TEST(TopologyBoolean, IntersectionKeepsOnlyVoxelsActiveInBoth) {
    this->run(Op::Intersection);
}

TYPED_TEST(TopologyBoolean, DifferenceKeepsOnlyVoxelsNotActiveInOther) {
    this->run(Op::Difference);
}

TYPED_TEST(TopologyBoolean, OtherTreeIsUnchanged) {
    using TreeB = typename TestFixture::TreeB;
    const TreeB copy(this->b);
    typename TestFixture::TreeA result(this->a);
    result.topologyUnion(this->b);
    result.topologyIntersection(this->b);
    result.topologyDifference(this->b);
    EXPECT_EQ(this->b.activeVoxelCount(), copy.activeVoxelCount());
    EXPECT_EQ(this->b.leafCount(), copy.leafCount());
    EXPECT_TRUE(activeSetMatches(this->b, Op::Union, this->sceneB.active, ActiveSet{}));
}

// ---- Tile handling, node by node

using FloatTree432 = tree::HashTree432<float>;  // leaves 4^3, level-1 nodes 32^3

TEST(TopologyBooleanTiles, ActiveTileOverOtherChildIsDensifiedUnlessPreserved) {
    FloatTree432 a(0.0f);
    a.fill(CoordBBox::createCube(Coord(-32), 32), 2.0f, true);  // one level-1 tile
    tree::HashTree432<bool> b(false);
    b.setValueOn(Coord(-30, -20, -10), true);
    {
        FloatTree432 result(a);
        result.topologyUnion(b, /*preserveTiles=*/true);
        EXPECT_EQ(result.leafCount(), 0u);
        EXPECT_EQ(result.activeTileCount(), 1u);
    }
    FloatTree432 result(a);
    result.topologyUnion(b);
    EXPECT_EQ(result.leafCount(), 1u);
    EXPECT_EQ(result.activeVoxelCount(), 32u * 32u * 32u);
    const auto* leaf = result.probeConstLeaf(Coord(-30, -20, -10));
    ASSERT_NE(leaf, nullptr);
    EXPECT_TRUE(leaf->isDense());
    EXPECT_EQ(leaf->getValue(Coord(-30, -20, -10)), 2.0f);
}

TEST(TopologyBooleanTiles, OtherActiveTileActivatesWholeChildKeepingValues) {
    FloatTree a(1.0f);
    a.setValueOff(Coord(-5, 6, -7), 9.0f);
    a.setValueOn(Coord(-5, 6, -6), 4.0f);
    MaskTree b;
    b.fill(CoordBBox::createCube(Coord(-128, 0, -128), 128), true, true);
    a.topologyUnion(b);
    EXPECT_EQ(a.leafCount(), 1u);
    EXPECT_EQ(a.activeVoxelCount(), Index64(128) * 128 * 128);
    EXPECT_TRUE(a.isValueOn(Coord(-5, 6, -7)));
    EXPECT_EQ(a.getValue(Coord(-5, 6, -7)), 9.0f);
    EXPECT_EQ(a.getValue(Coord(-5, 6, -6)), 4.0f);
    EXPECT_EQ(a.getValue(Coord(-100, 100, -100)), 1.0f);
}

TEST(TopologyBooleanTiles, UnionGivesNewVoxelsTheBackground) {
    Int32Tree a(7);
    Vec3STree b(Vec3s(1, 1, 1));
    b.setValueOn(Coord(-1000, 2000, -3000), Vec3s(5, 5, 5));
    b.fill(CoordBBox::createCube(Coord(4096, 0, 0), 4096), Vec3s(2, 2, 2), true);
    a.topologyUnion(b);
    EXPECT_TRUE(a.isValueOn(Coord(-1000, 2000, -3000)));
    EXPECT_EQ(a.getValue(Coord(-1000, 2000, -3000)), 7);
    EXPECT_EQ(a.leafCount(), 1u);
    EXPECT_EQ(a.activeTileCount(), 1u);  // b's root tile arrives as an active root tile
    EXPECT_EQ(a.getValue(Coord(5000, 5, 5)), 7);
    EXPECT_EQ(a.activeVoxelCount(), Index64(4096) * 4096 * 4096 + 1);
}

TEST(TopologyBooleanTiles, IntersectionFreesChildrenUnderInactiveRegionsAndKeepsThemUnderTiles) {
    FloatTree a(0.5f);
    a.setValueOn(Coord(10, 10, 10), 1.0f);    // under b's active tile: kept unchanged
    a.setValueOff(Coord(12, 10, 10), 3.0f);   // inactive, same leaf: kept
    a.setValueOn(Coord(-300, 10, 10), 1.0f);  // b has nothing there: freed
    a.setValueOn(Coord(5000, 10, 10), 1.0f);  // b has an inactive child there: off, kept
    a.fill(CoordBBox::createCube(Coord(0, 0, 256), 128), 6.0f, true);  // over b's leaf
    BoolTree b(false);
    b.fill(CoordBBox::createCube(Coord(0), 128), true, true);
    b.setValueOff(Coord(5001, 10, 10), true);
    b.setValueOn(Coord(3, 4, 260), true);
    a.topologyIntersection(b);
    EXPECT_TRUE(a.isValueOn(Coord(10, 10, 10)));
    EXPECT_EQ(a.getValue(Coord(12, 10, 10)), 3.0f);
    EXPECT_EQ(a.probeConstLeaf(Coord(-300, 10, 10)), nullptr);
    EXPECT_EQ(a.getValue(Coord(-300, 10, 10)), 0.5f);
    EXPECT_FALSE(a.isValueOn(Coord(5000, 10, 10)));
    EXPECT_NE(a.probeConstLeaf(Coord(5000, 10, 10)), nullptr);
    // The active tile took b's topology: one leaf, one active voxel, tile value kept.
    const auto* leaf = a.probeConstLeaf(Coord(3, 4, 260));
    ASSERT_NE(leaf, nullptr);
    EXPECT_EQ(leaf->onVoxelCount(), 1u);
    EXPECT_EQ(a.getValue(Coord(3, 4, 260)), 6.0f);
    EXPECT_EQ(a.getValue(Coord(3, 4, 261)), 6.0f);
    EXPECT_EQ(a.activeVoxelCount(), 2u);
}

TEST(TopologyBooleanTiles, DifferenceFreesChildrenUnderActiveTilesAndSplitsTiles) {
    FloatTree a(0.5f);
    a.setValueOn(Coord(-10, -10, -10), 1.0f);  // under b's active tile: freed
    a.fill(CoordBBox::createCube(Coord(256, 0, 0), 128), 6.0f, true);  // b has a voxel inside
    a.fill(CoordBBox::createCube(Coord(0, 256, 0), 128), 7.0f, true);  // b has a tile there
    MaskTree b;
    b.fill(CoordBBox::createCube(Coord(-128), 128), true, true);
    b.fill(CoordBBox::createCube(Coord(0, 256, 0), 128), true, true);
    b.setValueOn(Coord(300, 1, 2));
    a.topologyDifference(b);
    EXPECT_EQ(a.probeConstLeaf(Coord(-10, -10, -10)), nullptr);
    EXPECT_FALSE(a.isValueOn(Coord(-10, -10, -10)));
    EXPECT_FALSE(a.isValueOn(Coord(300, 1, 2)));
    EXPECT_TRUE(a.isValueOn(Coord(300, 1, 3)));
    EXPECT_EQ(a.getValue(Coord(300, 1, 2)), 6.0f);
    EXPECT_EQ(a.leafCount(), 1u);
    EXPECT_FALSE(a.isValueOn(Coord(5, 300, 5)));
    EXPECT_EQ(a.getValue(Coord(5, 300, 5)), 7.0f);
    EXPECT_EQ(a.activeVoxelCount(), Index64(128) * 128 * 128 - 1);
}

TEST(TopologyBooleanTiles, BoundedTopTilesFollowTheSameRules) {
    using T = tree::FixedTree643<float>;  // top 64^3 children of 128^3 voxels
    T a(0.0f);
    a.fill(CoordBBox::createCube(Coord(-128), 128), 1.0f, true);
    a.setValueOn(Coord(200, -300, 17), 2.0f);
    tree::FixedTree643<bool> b(false);
    b.fill(CoordBBox::createCube(Coord(128, -384, 0), 128), true, true);
    b.setValueOn(Coord(-100, -100, -100), true);
    T u(a), i(a), d(a);
    u.topologyUnion(b);
    i.topologyIntersection(b);
    d.topologyDifference(b);
    const Index64 tile = Index64(128) * 128 * 128;
    EXPECT_EQ(u.activeVoxelCount(), 2 * tile);  // a's voxel lies in b's tile; a's tile densified
    EXPECT_EQ(u.getValue(Coord(130, -380, 5)), 0.0f);
    EXPECT_EQ(u.getValue(Coord(200, -300, 17)), 2.0f);
    EXPECT_EQ(i.activeVoxelCount(), 2u);
    EXPECT_EQ(i.getValue(Coord(-100, -100, -100)), 1.0f);
    EXPECT_EQ(d.activeVoxelCount(), tile - 1);
    EXPECT_TRUE(d.isValueOn(Coord(-100, -100, -99)));
    EXPECT_FALSE(d.isValueOn(Coord(200, -300, 17)));
}

TEST(TopologyBooleanTiles, TopNodeOfTwoToTheThirtyEntriesWorksWithoutCopies) {
    // One top node of 1024^3 entries over 8^3 leaves: its masks are 128 MiB each, so the
    // booleans must not copy them (onto the stack or anywhere). The trees are never copied
    // either (that would commit the 8 GiB table); the zero background keeps its pages untouched.
    // Whole-mask statistics cost 2^24 popcounts each, so the checks read single voxels.
    if (test::workloadScale() < 1.0)
        GTEST_SKIP() << "two 256 MiB top nodes are too slow for the sanitizer run";
    tree::FixedTree103<float> a(0.0f);
    tree::FixedTree103<ValueMask> b;
    a.setValueOn(Coord(1, 2, 3), 1.0f);
    a.setValueOn(Coord(-4000, 7, 9), 2.0f);
    a.fill(CoordBBox::createCube(Coord(64), 8), 3.0f, true);
    b.setValueOn(Coord(1, 2, 4));
    b.setValueOn(Coord(66));
    b.fill(CoordBBox::createCube(Coord(-4000, 0, 8), 8), true, true);
    a.topologyUnion(b);
    EXPECT_TRUE(a.isValueOn(Coord(1, 2, 3)));
    EXPECT_TRUE(a.isValueOn(Coord(1, 2, 4)));
    EXPECT_FALSE(a.isValueOn(Coord(1, 2, 5)));
    EXPECT_TRUE(a.isValueOn(Coord(-4000, 0, 8)));  // b's active tile over a's leaf
    EXPECT_EQ(a.getValue(Coord(-4000, 0, 8)), 0.0f);
    EXPECT_EQ(a.getValue(Coord(-4000, 7, 9)), 2.0f);
    ASSERT_NE(a.probeConstLeaf(Coord(66)), nullptr);  // a's tile took b's leaf, densified
    EXPECT_TRUE(a.probeConstLeaf(Coord(66))->isDense());
    a.topologyIntersection(b);
    EXPECT_FALSE(a.isValueOn(Coord(1, 2, 3)));
    EXPECT_TRUE(a.isValueOn(Coord(1, 2, 4)));
    EXPECT_TRUE(a.isValueOn(Coord(66)));
    EXPECT_FALSE(a.isValueOn(Coord(67)));
    EXPECT_EQ(a.getValue(Coord(66)), 3.0f);
    EXPECT_TRUE(a.probeConstLeaf(Coord(-4000, 0, 8))->isDense());
    a.topologyDifference(b);
    EXPECT_FALSE(a.isValueOn(Coord(1, 2, 4)));
    EXPECT_FALSE(a.isValueOn(Coord(66)));
    EXPECT_EQ(a.probeConstLeaf(Coord(-4000, 0, 8)), nullptr);  // under b's active tile: freed
    EXPECT_FALSE(a.isValueOn(Coord(-4000, 0, 8)));
    EXPECT_EQ(a.leafCount(), 2u);
}

TEST(TopologyBooleanTiles, SelfOperationsKeepOrClearTheActiveSet) {
    FloatTree a(0.0f);
    a.setValueOn(Coord(1, 2, 3), 1.0f);
    a.fill(CoordBBox::createCube(Coord(-4096), 4096), 2.0f, true);
    const Index64 count = a.activeVoxelCount();
    a.topologyUnion(a);
    EXPECT_EQ(a.activeVoxelCount(), count);
    a.topologyIntersection(a);
    EXPECT_EQ(a.activeVoxelCount(), count);
    a.topologyDifference(a);
    EXPECT_EQ(a.activeVoxelCount(), 0u);
    EXPECT_EQ(a.getValue(Coord(1, 2, 3)), 1.0f);
    EXPECT_EQ(a.getValue(Coord(-5)), 2.0f);
}

TEST(TopologyBooleanTiles, AccessorsSeeFreedBranchesAsGone) {
    FloatTree a(0.0f);
    a.setValueOn(Coord(1, 2, 3), 1.0f);
    FloatTree::Accessor acc(a);
    EXPECT_TRUE(acc.isValueOn(Coord(1, 2, 3)));  // caches the path to the leaf
    const FloatTree empty(0.0f);
    a.topologyIntersection(empty);
    EXPECT_EQ(a.leafCount(), 0u);
    EXPECT_FALSE(acc.isValueOn(Coord(1, 2, 3)));
    EXPECT_EQ(acc.getValue(Coord(1, 2, 3)), 0.0f);
}

}  // namespace
}  // namespace vdb
