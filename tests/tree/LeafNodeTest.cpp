// SPDX-License-Identifier: Apache-2.0
// Oracle: plain nested arrays value[i][j][k] and on[i][j][k], indexed by the voxel's position in
// the brick, written independently of LeafNode's offset arithmetic and bit packing.

#include <vdb/Exceptions.h>
#include <vdb/tree/LeafNode.h>

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

namespace vdb::tree {
namespace {

// A dense oracle for one brick of DIM^3 voxels.
template <typename ValueT, Index Dim>
struct DenseBrick {
    ValueT value[Dim][Dim][Dim];
    bool on[Dim][Dim][Dim];

    DenseBrick(const ValueT& fill, bool active) {
        for (Index i = 0; i < Dim; ++i)
            for (Index j = 0; j < Dim; ++j)
                for (Index k = 0; k < Dim; ++k) {
                    value[i][j][k] = fill;
                    on[i][j][k] = active;
                }
    }
    Index64 onCount() const {
        Index64 n = 0;
        for (Index i = 0; i < Dim; ++i)
            for (Index j = 0; j < Dim; ++j)
                for (Index k = 0; k < Dim; ++k)
                    n += on[i][j][k];
        return n;
    }
};

// Compares every voxel of `leaf` with `oracle`; the message names the first differing voxel.
template <typename LeafT, typename OracleT>
::testing::AssertionResult matchesOracle(const LeafT& leaf, const OracleT& oracle) {
    constexpr Int32 dim = Int32(LeafT::DIM);
    for (Int32 i = 0; i < dim; ++i) {
        for (Int32 j = 0; j < dim; ++j) {
            for (Int32 k = 0; k < dim; ++k) {
                const Coord ijk = leaf.origin().offsetBy(i, j, k);
                const Index n = Index((i * dim + j) * dim + k);
                typename LeafT::ValueType probed{};
                const bool probedOn = leaf.probeValue(ijk, probed);
                if (!(leaf.getValue(ijk) == oracle.value[i][j][k]) ||
                    !(leaf.getValue(n) == oracle.value[i][j][k]) ||
                    !(probed == oracle.value[i][j][k]) ||
                    leaf.isValueOn(ijk) != oracle.on[i][j][k] ||
                    leaf.isValueOn(n) != oracle.on[i][j][k] || probedOn != oracle.on[i][j][k]) {
                    return ::testing::AssertionFailure()
                           << "voxel " << ijk << " (offset " << n << "): leaf "
                           << leaf.getValue(ijk) << (leaf.isValueOn(ijk) ? " on" : " off")
                           << "; oracle " << oracle.value[i][j][k]
                           << (oracle.on[i][j][k] ? " on" : " off");
                }
            }
        }
    }
    if (leaf.onVoxelCount() != oracle.onCount() ||
        leaf.offVoxelCount() != LeafT::NUM_VALUES - oracle.onCount()) {
        return ::testing::AssertionFailure()
               << "onVoxelCount() = " << leaf.onVoxelCount() << "; oracle " << oracle.onCount();
    }
    return ::testing::AssertionSuccess();
}

// ---- Leaves with a value buffer ---------------------------------------------------------------

template <typename LeafT>
class ValueLeaf : public ::testing::Test {};
using ValueLeafTypes =
    ::testing::Types<LeafNode<float, 3>, LeafNode<double, 3>, LeafNode<int32_t, 3>,
                     LeafNode<float, 2>, LeafNode<float, 4>, LeafNode<int64_t, 5>>;
TYPED_TEST_SUITE(ValueLeaf, ValueLeafTypes);

TYPED_TEST(ValueLeaf, OffsetsFollowNestedArrayOrderAndInvert) {
    using LeafT = TypeParam;
    constexpr Int32 dim = Int32(LeafT::DIM);
    const Coord origin(-2 * dim, dim, -5 * dim);
    const LeafT leaf(origin.offsetBy(1, 2, 3));
    EXPECT_EQ(leaf.origin(), origin);
    EXPECT_EQ(LeafT::NUM_VALUES, Index(dim * dim * dim));
    EXPECT_EQ(LeafT::DIM, Index(1) << LeafT::LOG2DIM);
    for (Int32 i = 0; i < dim; ++i) {
        for (Int32 j = 0; j < dim; ++j) {
            for (Int32 k = 0; k < dim; ++k) {
                const Coord ijk = origin.offsetBy(i, j, k);
                const Index n = Index((i * dim + j) * dim + k);
                ASSERT_EQ(LeafT::coordToOffset(ijk), n) << ijk;
                ASSERT_EQ(LeafT::offsetToLocalCoord(n), Coord(i, j, k)) << n;
                ASSERT_EQ(leaf.offsetToGlobalCoord(n), ijk) << n;
                ASSERT_TRUE(leaf.contains(ijk)) << ijk;
            }
        }
    }
    EXPECT_FALSE(leaf.contains(origin.offsetBy(-1, 0, 0)));
    EXPECT_FALSE(leaf.contains(origin.offsetBy(0, dim, 0)));
    EXPECT_EQ(leaf.getNodeBoundingBox(), CoordBBox::createCube(origin, dim));
}

TYPED_TEST(ValueLeaf, OriginSnapsDownToBrickCornerForNegativeCoords) {
    using LeafT = TypeParam;
    constexpr Int32 dim = Int32(LeafT::DIM);
    EXPECT_EQ(LeafT(Coord(-1, -dim, -dim - 1)).origin(), Coord(-dim, -dim, -2 * dim));
    EXPECT_EQ(LeafT(Coord(dim - 1, dim, 0)).origin(), Coord(0, dim, 0));
    constexpr Int32 lo = std::numeric_limits<Int32>::min();
    constexpr Int32 hi = std::numeric_limits<Int32>::max();
    EXPECT_EQ(LeafT(Coord(lo)).origin(), Coord(lo));
    EXPECT_EQ(LeafT(Coord(hi)).origin(), Coord(hi - dim + 1));
}

TYPED_TEST(ValueLeaf, RandomWritesMatchDenseOracle) {
    using LeafT = TypeParam;
    using ValueT = typename LeafT::ValueType;
    constexpr Index dim = LeafT::DIM;
    const Coord origin(-Int32(dim), 0, Int32(dim) * 3);
    LeafT leaf(origin, ValueT(7), false);
    DenseBrick<ValueT, dim> oracle(ValueT(7), false);
    ASSERT_TRUE(matchesOracle(leaf, oracle));

    std::mt19937 rng(20130601);  // fixed seed: a failure must reproduce
    for (int n = 0; n < 4000; ++n) {
        const Index i = rng() % dim, j = rng() % dim, k = rng() % dim;
        const Coord ijk = origin.offsetBy(Int32(i), Int32(j), Int32(k));
        const Index offset = (i * dim + j) * dim + k;
        const ValueT v = ValueT(rng() % 9);
        const bool byOffset = rng() % 2;
        switch (rng() % 8) {
            case 0:
                byOffset ? leaf.setValueOn(offset, v) : leaf.setValueOn(ijk, v);
                oracle.value[i][j][k] = v;
                oracle.on[i][j][k] = true;
                break;
            case 1:
                byOffset ? leaf.setValueOn(offset) : leaf.setValueOn(ijk);
                oracle.on[i][j][k] = true;
                break;
            case 2:
                byOffset ? leaf.setValueOff(offset, v) : leaf.setValueOff(ijk, v);
                oracle.value[i][j][k] = v;
                oracle.on[i][j][k] = false;
                break;
            case 3:
                byOffset ? leaf.setValueOff(offset) : leaf.setValueOff(ijk);
                oracle.on[i][j][k] = false;
                break;
            case 4:
                byOffset ? leaf.setValueOnly(offset, v) : leaf.setValueOnly(ijk, v);
                oracle.value[i][j][k] = v;
                break;
            case 5: {
                const bool on = rng() % 2;
                byOffset ? leaf.setActiveState(offset, on) : leaf.setActiveState(ijk, on);
                oracle.on[i][j][k] = on;
                break;
            }
            default: {
                // A box that sticks out of the leaf on some sides: only the inside changes.
                const Coord a = ijk.offsetBy(-Int32(rng() % 3), -Int32(rng() % 3), 0);
                const CoordBBox box(
                    a, a.offsetBy(Int32(rng() % 4), Int32(rng() % 4), Int32(rng() % 12)));
                const bool on = rng() % 2;
                leaf.fill(box, v, on);
                for (Index x = 0; x < dim; ++x)
                    for (Index y = 0; y < dim; ++y)
                        for (Index z = 0; z < dim; ++z)
                            if (box.isInside(origin.offsetBy(Int32(x), Int32(y), Int32(z)))) {
                                oracle.value[x][y][z] = v;
                                oracle.on[x][y][z] = on;
                            }
                break;
            }
        }
        if (n % 500 == 0) {
            ASSERT_TRUE(matchesOracle(leaf, oracle)) << "after write " << n;
        }
    }
    ASSERT_TRUE(matchesOracle(leaf, oracle));

    // The value iterators visit the oracle's voxels in offset order.
    std::vector<Index> on, off, all;
    for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
        const Coord l = LeafT::offsetToLocalCoord(n);
        (oracle.on[l[0]][l[1]][l[2]] ? on : off).push_back(n);
        all.push_back(n);
    }
    auto visit = [&](auto it) {
        std::vector<Index> result;
        for (; it; ++it) {
            EXPECT_EQ(it.getCoord(), leaf.offsetToGlobalCoord(it.pos()));
            EXPECT_EQ(*it, leaf.getValue(it.pos()));
            EXPECT_EQ(it.isValueOn(), leaf.isValueOn(it.pos()));
            result.push_back(it.pos());
        }
        return result;
    };
    EXPECT_EQ(visit(leaf.cbeginValueOn()), on);
    EXPECT_EQ(visit(leaf.cbeginValueOff()), off);
    EXPECT_EQ(visit(leaf.cbeginValueAll()), all);

    // The active bounding box is the oracle's.
    CoordBBox expected;
    for (Index n : on)
        expected.expand(leaf.offsetToGlobalCoord(n));
    CoordBBox bbox;
    leaf.evalActiveBoundingBox(bbox);
    EXPECT_EQ(bbox, expected);

    // Writing through the iterator changes values, not states.
    for (auto it = leaf.beginValueOn(); it; ++it) {
        it.setValue(ValueT(100));
        const Coord l = LeafT::offsetToLocalCoord(it.pos());
        oracle.value[l[0]][l[1]][l[2]] = ValueT(100);
    }
    EXPECT_TRUE(matchesOracle(leaf, oracle));
}

TYPED_TEST(ValueLeaf, IsConstantNeedsOneValueAndOneState) {
    using LeafT = TypeParam;
    using ValueT = typename LeafT::ValueType;
    LeafT leaf(Coord(0), ValueT(3), true);
    ValueT first{};
    bool state = false;
    EXPECT_TRUE(leaf.isConstant(first, state, ValueT(0)));
    EXPECT_EQ(first, ValueT(3));
    EXPECT_TRUE(state);
    EXPECT_TRUE(leaf.isDense());
    leaf.setValueOnly(Coord(1, 1, 1), ValueT(4));
    EXPECT_FALSE(leaf.isConstant(first, state, ValueT(0)));
    EXPECT_TRUE(leaf.isConstant(first, state, ValueT(1)));  // within tolerance
    leaf.setValueOnly(Coord(1, 1, 1), ValueT(3));
    leaf.setValueOff(Coord(0, 1, 1));
    EXPECT_FALSE(leaf.isConstant(first, state, ValueT(10)));
    leaf.fill(ValueT(5), false);
    EXPECT_TRUE(leaf.isConstant(first, state, ValueT(0)));
    EXPECT_FALSE(state);
    EXPECT_TRUE(leaf.isEmpty());
}

TYPED_TEST(ValueLeaf, TemporalBuffersHoldIndependentValuesAndSwap) {
    using LeafT = TypeParam;
    using ValueT = typename LeafT::ValueType;
    constexpr Index N = LeafT::NUM_VALUES;
    LeafT leaf(Coord(0), ValueT(1), true);
    EXPECT_EQ(leaf.bufferCount(), 1u);
    EXPECT_TRUE(leaf.isAllocated());
    const Index64 oneBuffer = leaf.memUsage();

    // New buffers start as copies of buffer 0.
    leaf.buffer(0)[5] = ValueT(2);
    leaf.setBufferCount(3);
    EXPECT_EQ(leaf.bufferCount(), 3u);
    EXPECT_EQ(leaf.memUsage(), oneBuffer + 2 * N * sizeof(ValueT));
    for (Index b = 0; b < 3; ++b) {
        ASSERT_EQ(leaf.buffer(b).size(), N);
        EXPECT_EQ(leaf.buffer(b)[5], ValueT(2)) << "buffer " << b;
        EXPECT_EQ(leaf.buffer(b)[6], ValueT(1)) << "buffer " << b;
    }
    // Each buffer holds its own values; buffer 0 is what getValue() reads.
    for (Index b = 0; b < 3; ++b)
        for (Index n = 0; n < N; ++n)
            leaf.buffer(b)[n] = ValueT(10 * (b + 1) + n % 7);
    for (Index n = 0; n < N; n += 3)
        EXPECT_EQ(leaf.getValue(n), ValueT(10 + n % 7));
    leaf.swapBuffers(0, 2);
    for (Index n = 0; n < N; ++n) {
        ASSERT_EQ(leaf.getValue(n), ValueT(30 + n % 7)) << n;
        ASSERT_EQ(leaf.buffer(1)[n], ValueT(20 + n % 7)) << n;
        ASSERT_EQ(leaf.buffer(2)[n], ValueT(10 + n % 7)) << n;
    }
    leaf.swapBuffers(1, 2);
    leaf.swapBuffers(0, 1);
    // Buffers after the swaps (0,2), (1,2), (0,1): 30 20 10, then 30 10 20, then 10 30 20.
    const ValueT expected[3] = {ValueT(10), ValueT(30), ValueT(20)};
    for (Index b = 0; b < 3; ++b)
        EXPECT_EQ(leaf.buffer(b)[0], expected[b]) << "buffer " << b;
    leaf.setValueOn(Index(0), ValueT(99));
    EXPECT_EQ(leaf.buffer(0)[0], ValueT(99));
    EXPECT_EQ(leaf.buffer(1)[0], ValueT(30));

    // Copies keep every buffer in order, whatever swaps happened.
    const LeafT copy(leaf);
    LeafT assigned(Coord(64), ValueT(0), false);
    assigned = leaf;
    for (const LeafT* other : {&copy, static_cast<const LeafT*>(&assigned)}) {
        ASSERT_EQ(other->bufferCount(), 3u);
        for (Index b = 0; b < 3; ++b)
            for (Index n = 0; n < N; ++n)
                ASSERT_EQ(other->buffer(b)[n], leaf.buffer(b)[n]) << "buffer " << b << ", " << n;
        EXPECT_EQ(other->origin(), leaf.origin());
        EXPECT_EQ(other->getValueMask(), leaf.getValueMask());
    }

    // Shrinking keeps the first buffers; zero frees the values but keeps the mask.
    leaf.setBufferCount(2);
    EXPECT_EQ(leaf.buffer(0)[0], ValueT(99));
    EXPECT_EQ(leaf.buffer(1)[0], ValueT(30));
    EXPECT_EQ(leaf.memUsage(), oneBuffer + N * sizeof(ValueT));
    leaf.setBufferCount(0);
    EXPECT_EQ(leaf.bufferCount(), 0u);
    EXPECT_FALSE(leaf.isAllocated());
    EXPECT_EQ(leaf.memUsage(), oneBuffer - N * sizeof(ValueT));
    EXPECT_TRUE(leaf.isDense());
    EXPECT_THROW(leaf.setBufferCount(4), ValueError);
    leaf.setBufferCount(1);
    EXPECT_EQ(leaf.bufferCount(), 1u);
    leaf.fill(ValueT(6), true);
    EXPECT_EQ(leaf.getValue(Coord(1, 2, 3)), ValueT(6));
}

// ---- Bool leaves: values are bits -------------------------------------------------------------

template <typename LeafT>
class BitLeaf : public ::testing::Test {};
using BitLeafTypes = ::testing::Types<LeafNode<bool, 3>, LeafNode<bool, 2>, LeafNode<bool, 4>>;
TYPED_TEST_SUITE(BitLeaf, BitLeafTypes);

TYPED_TEST(BitLeaf, ValuesAndStatesAreIndependentBits) {
    using LeafT = TypeParam;
    constexpr Index dim = LeafT::DIM;
    static_assert(std::is_same_v<typename LeafT::ValueType, bool>);
    const Coord origin(Int32(dim) * 5, -Int32(dim), 0);
    LeafT leaf(origin, true, false);
    DenseBrick<bool, dim> oracle(true, false);
    std::mt19937 rng(7);
    for (int n = 0; n < 3000; ++n) {
        const Index i = rng() % dim, j = rng() % dim, k = rng() % dim;
        const Coord ijk = origin.offsetBy(Int32(i), Int32(j), Int32(k));
        const bool v = rng() % 2;
        switch (rng() % 6) {
            case 0:
                leaf.setValueOn(ijk, v);
                oracle.value[i][j][k] = v;
                oracle.on[i][j][k] = true;
                break;
            case 1:
                leaf.setValueOff(ijk, v);
                oracle.value[i][j][k] = v;
                oracle.on[i][j][k] = false;
                break;
            case 2:
                leaf.setValueOnly(ijk, v);
                oracle.value[i][j][k] = v;
                break;
            case 3:
                leaf.setActiveState(ijk, v);
                oracle.on[i][j][k] = v;
                break;
            case 4:
                leaf.setValueOn(ijk);
                oracle.on[i][j][k] = true;
                break;
            default:
                leaf.setValueOff(ijk);
                oracle.on[i][j][k] = false;
                break;
        }
    }
    ASSERT_TRUE(matchesOracle(leaf, oracle));
    for (Index n = 0; n < LeafT::NUM_VALUES; ++n) {
        ASSERT_EQ(leaf.buffer().isOn(n), leaf.getValue(n)) << n;
    }
    // Two bits per voxel, plus the origin.
    EXPECT_LE(leaf.memUsage(), 2 * LeafT::NUM_VALUES / 8 + 64);
}

// Fills the leaf at the INT32_MAX corner through a box that ends there, in a child process
// that exits 0 when every voxel came out on. A loop counter that overflows past INT32_MAX
// would never end; the alarm turns that into a failure after a few seconds.
template <typename LeafT>
void expectFillAtInt32MaxEnds() {
    EXPECT_EXIT(
        {
            alarm(10);
            LeafT leaf(Coord(std::numeric_limits<Int32>::max()));
            leaf.fill(leaf.getNodeBoundingBox(), true, true);
            std::_Exit(leaf.onVoxelCount() == LeafT::NUM_VALUES ? 0 : 1);
        },
        ::testing::ExitedWithCode(0), "");
}

TYPED_TEST(BitLeaf, FillOfBoxEndingAtInt32MaxStopsThere) {
    expectFillAtInt32MaxEnds<TypeParam>();
}

// ---- Mask leaves: no values, a voxel's value is its state -------------------------------------

TEST(MaskLeaf, ValueIsActiveStateWhateverSetterIsUsed) {
    using LeafT = LeafNode<ValueMask, 3>;
    static_assert(std::is_same_v<LeafT::ValueType, bool>);
    static_assert(std::is_same_v<LeafT::BuildType, ValueMask>);
    const Coord ijk(-3, 4, 5);
    LeafT leaf(ijk);
    EXPECT_EQ(leaf.origin(), Coord(-8, 0, 0));
    EXPECT_TRUE(leaf.isEmpty());
    leaf.setValueOn(ijk, false);
    EXPECT_FALSE(leaf.isValueOn(ijk));
    leaf.setValueOff(ijk, true);
    EXPECT_TRUE(leaf.isValueOn(ijk));
    EXPECT_TRUE(leaf.getValue(ijk));
    leaf.setValueOnly(ijk, false);
    EXPECT_FALSE(leaf.getValue(ijk));
    leaf.setActiveState(ijk, true);
    bool value = false;
    EXPECT_TRUE(leaf.probeValue(ijk, value));
    EXPECT_TRUE(value);
    leaf.fill(CoordBBox(Coord(-8, 0, 0), Coord(-7, 1, 1)), false, true);
    EXPECT_EQ(leaf.onVoxelCount(), 8u + 1u);
    EXPECT_EQ(leaf.bufferCount(), 0u);
    // One bit per voxel, plus the origin.
    EXPECT_LE(leaf.memUsage(), LeafT::NUM_VALUES / 8 + 64);
}

TEST(MaskLeaf, RandomWritesMatchDenseOracle) {
    using LeafT = LeafNode<ValueMask, 3>;
    const Coord origin(8, -16, 24);
    LeafT leaf(origin);
    DenseBrick<bool, 8> oracle(false, false);
    std::mt19937 rng(11);
    for (int n = 0; n < 3000; ++n) {
        const Index i = rng() % 8, j = rng() % 8, k = rng() % 8;
        const Coord ijk = origin.offsetBy(Int32(i), Int32(j), Int32(k));
        const bool v = rng() % 2;
        switch (rng() % 4) {
            case 0:
                leaf.setValueOn(ijk);
                break;
            case 1:
                leaf.setValueOff(ijk);
                break;
            case 2:
                leaf.setValueOn(ijk, v);
                break;
            default:
                leaf.setActiveState(ijk, v);
                break;
        }
        oracle.on[i][j][k] = leaf.isValueOn(ijk);
        oracle.value[i][j][k] = oracle.on[i][j][k];
    }
    ASSERT_TRUE(matchesOracle(leaf, oracle));
    Index64 visited = 0;
    for (auto it = leaf.cbeginValueOn(); it; ++it, ++visited) {
        const Coord l = LeafT::offsetToLocalCoord(it.pos());
        EXPECT_TRUE(oracle.on[l[0]][l[1]][l[2]]);
    }
    EXPECT_EQ(visited, oracle.onCount());
}

TEST(MaskLeaf, FillOfBoxEndingAtInt32MaxStopsThere) {
    expectFillAtInt32MaxEnds<LeafNode<ValueMask, 3>>();
}

TEST(ValueLeafEdge, FillOfBoxEndingAtInt32MaxStopsThere) {
    expectFillAtInt32MaxEnds<LeafNode<float, 3>>();
}

// Every leaf class has the same iterators (LeafIterators.h): each filter, mutable and const,
// visits exactly the voxels a scan of isValueOn() selects, in offset order; a mutable
// iterator writes values through setValue() (in a mask leaf the value is the state).
template <typename LeafT>
void expectFullIteratorSet() {
    LeafT leaf(Coord(-8, 16, 24), typename LeafT::ValueType{}, false);
    std::mt19937 rng(11);
    for (int n = 0; n < 200; ++n)
        leaf.setValueOn(Index(rng() % LeafT::NUM_VALUES), typename LeafT::ValueType(1));
    std::vector<Index> on, off;
    for (Index n = 0; n < LeafT::NUM_VALUES; ++n)
        (leaf.isValueOn(n) ? on : off).push_back(n);
    ASSERT_FALSE(on.empty());
    ASSERT_FALSE(off.empty());
    const auto visit = [](auto it) {
        std::vector<Index> seen;
        for (; it; ++it) {
            EXPECT_EQ(it.getCoord(), it.leaf().offsetToGlobalCoord(it.pos()));
            seen.push_back(it.pos());
        }
        return seen;
    };
    const LeafT& cleaf = leaf;
    EXPECT_EQ(visit(leaf.beginValueOn()), on);
    EXPECT_EQ(visit(cleaf.beginValueOn()), on);
    EXPECT_EQ(visit(leaf.cbeginValueOn()), on);
    EXPECT_EQ(visit(leaf.beginValueOff()), off);
    EXPECT_EQ(visit(cleaf.beginValueOff()), off);
    EXPECT_EQ(visit(leaf.cbeginValueOff()), off);
    EXPECT_EQ(visit(leaf.beginValueAll()).size(), size_t(LeafT::NUM_VALUES));
    EXPECT_EQ(visit(cleaf.beginValueAll()).size(), size_t(LeafT::NUM_VALUES));
    EXPECT_EQ(&leaf.beginValueOn().leaf(), &leaf);
    // Writes through a mutable iterator.
    for (auto it = leaf.beginValueOff(); it; ++it)
        it.setValue(typename LeafT::ValueType(1));
    for (Index n : off) {
        EXPECT_EQ(leaf.getValue(n), typename LeafT::ValueType(1)) << n;
        EXPECT_EQ(leaf.isValueOn(n), IS_MASK_NODE<LeafT>) << n;
    }
}

TEST(LeafIterators, EveryLeafClassHasTheFullIteratorSet) {
    expectFullIteratorSet<LeafNode<float, 3>>();
    expectFullIteratorSet<LeafNode<Int64, 4>>();
    expectFullIteratorSet<LeafNode<bool, 3>>();
    expectFullIteratorSet<LeafNode<ValueMask, 3>>();
}

}  // namespace
}  // namespace vdb::tree
