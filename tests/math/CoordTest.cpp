// SPDX-License-Identifier: Apache-2.0
// Oracles: 64-bit integer arithmetic reduced mod 2^32, std::tuple ordering, floor division, and
// brute-force enumeration of small boxes.

#include <vdb/math/Coord.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <tuple>
#include <unordered_set>

namespace vdb::math {
namespace {

constexpr Int32 kMax = std::numeric_limits<Int32>::max();
constexpr Int32 kMin = std::numeric_limits<Int32>::min();

// Two's-complement wrap of a 64-bit value to 32 bits, computed without Coord.
Int32 wrap(int64_t v) {
    return static_cast<Int32>(static_cast<uint32_t>(static_cast<uint64_t>(v)));
}

TEST(Coord, DefaultIsOriginAndAccessorsAgreeWithIndex) {
    const Coord origin;
    EXPECT_EQ(origin, Coord(0, 0, 0));
    const Coord ijk(-3, 5, kMax);
    EXPECT_EQ(ijk.x(), -3);
    EXPECT_EQ(ijk.y(), 5);
    EXPECT_EQ(ijk.z(), kMax);
    for (size_t i = 0; i < 3; ++i)
        EXPECT_EQ(ijk[i], ijk.data()[i]);
    EXPECT_EQ(Coord(7), Coord(7, 7, 7));
}

TEST(Coord, ArithmeticWrapsLikeTwosComplementNearIntMax) {
    EXPECT_EQ(Coord(kMax).offsetBy(1), Coord(kMin));
    EXPECT_EQ(Coord(kMin).offsetBy(-1), Coord(kMax));
    EXPECT_EQ(Coord(kMax, 0, kMin) + Coord(1, 1, -1), Coord(kMin, 1, kMax));
    EXPECT_EQ(Coord(kMin) - Coord(1), Coord(kMax));
    EXPECT_EQ(-Coord(kMin), Coord(kMin));  // -INT_MIN wraps to itself

    std::mt19937 rng(20130601);
    std::uniform_int_distribution<Int32> any(kMin, kMax);
    for (int n = 0; n < 10000; ++n) {
        const Coord a(any(rng), any(rng), any(rng)), b(any(rng), any(rng), any(rng));
        const Coord sum = a + b, diff = a - b, off = a.offsetBy(b[0], b[1], b[2]);
        for (size_t i = 0; i < 3; ++i) {
            ASSERT_EQ(sum[i], wrap(int64_t(a[i]) + b[i])) << a << " + " << b;
            ASSERT_EQ(diff[i], wrap(int64_t(a[i]) - b[i])) << a << " - " << b;
            ASSERT_EQ(off[i], sum[i]);
        }
        Coord c = a;
        c += b;
        ASSERT_EQ(c, sum);
        c -= b;
        ASSERT_EQ(c, a);
    }
}

TEST(Coord, AlignedDownFloorsToBlockOriginForNegativeCoords) {
    EXPECT_EQ(Coord(-1, -8, -9).alignedDown(3), Coord(-8, -8, -16));
    EXPECT_EQ(Coord(kMin, kMax, 0).alignedDown(12), Coord(kMin, kMax - 4095, 0));

    std::mt19937 rng(7);
    std::uniform_int_distribution<Int32> any(kMin, kMax);
    for (Index log2 = 0; log2 <= 12; ++log2) {
        const int64_t block = int64_t(1) << log2;
        for (int n = 0; n < 2000; ++n) {
            const Int32 v = any(rng);
            // Floor division in 64 bits: the oracle for clearing the low bits.
            const int64_t q =
                (int64_t(v) >= 0) ? int64_t(v) / block : -((-int64_t(v) + block - 1) / block);
            ASSERT_EQ(Coord(v).alignedDown(log2)[0], Int32(q * block)) << v << " log2 " << log2;
        }
    }
}

TEST(Coord, ShiftsAndMaskActOnEachComponent) {
    EXPECT_EQ(Coord(-16, 8, 3) >> 3, Coord(-2, 1, 0));
    EXPECT_EQ(Coord(-2, 1, 0) << 3, Coord(-16, 8, 0));
    EXPECT_EQ(Coord(kMax) << 1, Coord(-2));  // bits shifted out are lost, no UB
    EXPECT_EQ(Coord(-1, 9, 15) & 7, Coord(7, 1, 7));
}

TEST(Coord, LessThanIsLexicographicLikeTuple) {
    std::mt19937 rng(3);
    std::uniform_int_distribution<Int32> small(-2, 2);
    for (int n = 0; n < 5000; ++n) {
        const Coord a(small(rng), small(rng), small(rng)), b(small(rng), small(rng), small(rng));
        const bool oracle = std::make_tuple(a[0], a[1], a[2]) < std::make_tuple(b[0], b[1], b[2]);
        ASSERT_EQ(a < b, oracle) << a << " < " << b;
        ASSERT_EQ(a > b, b < a);
        ASSERT_EQ(a <= b, !(b < a));
        ASSERT_EQ(a >= b, !(a < b));
        ASSERT_EQ(a == b, !(a < b) && !(b < a));
    }
}

TEST(Coord, MinAndMaxComponentAreComponentwise) {
    const Coord a(-5, 7, kMin), b(3, -9, kMax);
    EXPECT_EQ(Coord::minComponent(a, b), Coord(-5, -9, kMin));
    EXPECT_EQ(Coord::maxComponent(a, b), Coord(3, 7, kMax));
    EXPECT_EQ(a.minComponent(), kMin);
    EXPECT_EQ(b.maxComponent(), kMax);
    EXPECT_EQ(Coord::min(), Coord(kMin));
    EXPECT_EQ(Coord::max(), Coord(kMax));
}

TEST(Coord, EqualCoordsHashEquallyAndWorkInUnorderedSet) {
    std::unordered_set<Coord> set;
    for (Int32 i = -4; i < 4; ++i) {
        for (Int32 j = -4; j < 4; ++j) {
            for (Int32 k = -4; k < 4; ++k)
                set.insert(Coord(i, j, k));
        }
    }
    EXPECT_EQ(set.size(), 512u);
    EXPECT_EQ(set.count(Coord(-4, 3, 0)), 1u);
    EXPECT_EQ(set.count(Coord(4, 0, 0)), 0u);
    EXPECT_EQ(Coord(1, 2, 3).hash(), Coord(1, 2, 3).hash());
}

TEST(Coord, StreamsAsBracketedTriple) {
    std::ostringstream os;
    os << Coord(-1, 0, kMax);
    EXPECT_EQ(os.str(), "[-1, 0, 2147483647]");
}

TEST(CoordBBox, DefaultIsEmptyAndExpandingItYieldsThePoint) {
    CoordBBox box;
    EXPECT_TRUE(box.empty());
    EXPECT_FALSE(bool(box));
    EXPECT_EQ(box.volume(), 0u);
    box.expand(Coord(-3, 4, kMin));
    EXPECT_FALSE(box.empty());
    EXPECT_EQ(box.min(), Coord(-3, 4, kMin));
    EXPECT_EQ(box.max(), Coord(-3, 4, kMin));
    EXPECT_EQ(box.volume(), 1u);
    box.expand(CoordBBox());  // expanding by an empty box changes nothing
    EXPECT_EQ(box, CoordBBox(Coord(-3, 4, kMin), Coord(-3, 4, kMin)));
}

TEST(CoordBBox, ExtentsAndVolumeOfHugeBoxesDoNotOverflow) {
    // Full 32-bit range along x: 2^32 voxels, more than Int32 or Index can count.
    const CoordBBox fullX(kMin, 0, 0, kMax, 0, 0);
    EXPECT_EQ(fullX.extents()[0], int64_t(1) << 32);
    EXPECT_EQ(fullX.volume(), Index64(1) << 32);

    // 2^32 x 2^31 x 1 voxels: 2^63, the largest power of two an Index64 holds.
    const CoordBBox slab(kMin, 0, 5, kMax, kMax, 5);
    EXPECT_EQ(slab.volume(), Index64(1) << 63);

    // A cube of edge 2^21 straddling the origin, also 2^63 voxels.
    const Int32 h = 1 << 20;
    EXPECT_EQ(CoordBBox(Coord(-h), Coord(h - 1)).volume(), Index64(1) << 63);

    const auto inf = CoordBBox::inf().extents();
    for (int64_t e : inf)
        EXPECT_EQ(e, int64_t(1) << 32);
}

TEST(CoordBBox, DimCreateCubeAndEmptyAgree) {
    const CoordBBox cube = CoordBBox::createCube(Coord(-8, 0, 16), 8);
    EXPECT_EQ(cube.min(), Coord(-8, 0, 16));
    EXPECT_EQ(cube.max(), Coord(-1, 7, 23));
    EXPECT_EQ(cube.dim(), Coord(8));
    EXPECT_EQ(cube.volume(), 512u);
    EXPECT_TRUE(CoordBBox(Coord(0), Coord(-1, 0, 0)).empty());
    EXPECT_EQ(CoordBBox(Coord(0), Coord(-1, 0, 0)).dim(), Coord(0));
}

// Every membership and overlap answer on small boxes with negative corners, checked by
// enumerating the lattice points.
TEST(CoordBBox, InsideOverlapAndIntersectMatchBruteForceEnumeration) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<Int32> corner(-4, 3);
    const auto randomBox = [&] {
        Coord a(corner(rng), corner(rng), corner(rng)), b(corner(rng), corner(rng), corner(rng));
        return CoordBBox(Coord::minComponent(a, b), Coord::maxComponent(a, b));
    };
    const auto inBox = [](const CoordBBox& b, const Coord& p) {
        return b.min()[0] <= p[0] && p[0] <= b.max()[0] && b.min()[1] <= p[1] &&
               p[1] <= b.max()[1] && b.min()[2] <= p[2] && p[2] <= b.max()[2];
    };
    for (int n = 0; n < 300; ++n) {
        const CoordBBox a = randomBox(), b = randomBox();
        CoordBBox both = a;
        both.intersect(b);
        bool anyCommon = false;
        Index64 countA = 0;
        for (Int32 i = -5; i <= 4; ++i) {
            for (Int32 j = -5; j <= 4; ++j) {
                for (Int32 k = -5; k <= 4; ++k) {
                    const Coord p(i, j, k);
                    ASSERT_EQ(a.isInside(p), inBox(a, p)) << a << " " << p;
                    ASSERT_EQ(both.isInside(p), inBox(a, p) && inBox(b, p)) << a << " & " << b;
                    anyCommon |= inBox(a, p) && inBox(b, p);
                    countA += inBox(a, p);
                }
            }
        }
        ASSERT_EQ(a.hasOverlap(b), anyCommon) << a << " " << b;
        ASSERT_EQ(both.empty(), !anyCommon);
        ASSERT_EQ(a.volume(), countA);
        ASSERT_EQ(a.isInside(b), inBox(a, b.min()) && inBox(a, b.max()));
    }
}

TEST(CoordBBox, ExpandAndTranslateMoveTheCorners) {
    CoordBBox box(Coord(-1, 0, 1), Coord(2, 3, 4));
    box.expand(2);
    EXPECT_EQ(box, CoordBBox(Coord(-3, -2, -1), Coord(4, 5, 6)));
    box.translate(Coord(-10, 0, 10));
    EXPECT_EQ(box, CoordBBox(Coord(-13, -2, 9), Coord(-6, 5, 16)));
    box.expand(CoordBBox(Coord(100), Coord(101)));
    EXPECT_EQ(box, CoordBBox(Coord(-13, -2, 9), Coord(101, 101, 101)));
    box.reset();
    EXPECT_TRUE(box.empty());
}

}  // namespace
}  // namespace vdb::math
