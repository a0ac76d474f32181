// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic signed distance functions (sphere, torus, box). Only the narrow band is
// written; after the fill every inactive voxel and every tile of every level must carry the
// sign of the analytic distance over its whole region and the magnitude of the background.
// Hand-made trees check the scanline rules (seeds, line starts, root gaps, the bounded top's
// spatial order) against values worked out by hand.

#include <vdb/Grid.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/TreeConfigs.h>

#include "LevelSetTestUtil.h"
#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

constexpr float kBackground = 2.0f;
constexpr double kHalfWidth = 2.0;

struct BandVoxel {
    Coord ijk;
    float value;
};

struct Shape {
    std::string name;
    test::Sdf sdf;
    CoordBBox bounds;
};

/// The test shapes: each crosses the origin, so the band spans the boundaries of the nodes of
/// every level and several root keys; the box also crosses x = 128.
const std::vector<Shape>& shapes() {
    // The box around centre c with half extents h, plus three voxels.
    auto around = [](double cx, double cy, double cz, double hx, double hy, double hz) {
        return CoordBBox(Coord(Int32(std::floor(cx - hx - 3)), Int32(std::floor(cy - hy - 3)),
                               Int32(std::floor(cz - hz - 3))),
                         Coord(Int32(std::ceil(cx + hx + 3)), Int32(std::ceil(cy + hy + 3)),
                               Int32(std::ceil(cz + hz + 3))));
    };
    static const std::vector<Shape> list = {
        {"sphere", test::sphereSdf(3.3, -5.7, 1.2, 40.0), around(3.3, -5.7, 1.2, 40, 40, 40)},
        {"torus", test::torusSdf(-2.5, 4.25, -1.5, 36.0, 12.0),
         around(-2.5, 4.25, -1.5, 48, 48, 12)},
        {"box", test::boxSdf(52.5, -10.5, 20.25, 82.5, 20.0, 30.0),
         around(52.5, -10.5, 20.25, 82.5, 20.0, 30.0)},
    };
    return list;
}

/// The shapes a test runs on: all three, or fewer in a scaled-down (sanitizer) run.
std::vector<Shape> testShapes() {
    const auto& all = shapes();
    return {all.begin(), all.begin() + std::min<int>(3, test::scaledBatchCount(3))};
}

/// The band |d| < kHalfWidth of a shape, values in voxel units; computed once per shape.
const std::vector<BandVoxel>& bandOf(const Shape& shape) {
    static std::map<std::string, std::vector<BandVoxel>> cache;
    auto& band = cache[shape.name];
    if (band.empty()) {
        const CoordBBox& b = shape.bounds;
        for (Int32 i = b.min()[0]; i <= b.max()[0]; ++i)
            for (Int32 j = b.min()[1]; j <= b.max()[1]; ++j)
                for (Int32 k = b.min()[2]; k <= b.max()[2]; ++k) {
                    const double d = test::sdfAt(shape.sdf, Coord(i, j, k));
                    if (std::abs(d) < kHalfWidth)
                        band.push_back({Coord(i, j, k), float(d)});
                }
    }
    return band;
}

template <typename C>
class SignedFloodFill : public ::testing::Test {
protected:
    using TreeT = typename C::TreeType;

    static void writeBand(TreeT& tree, const Shape& shape) {
        typename TreeT::Accessor acc(tree);
        for (const BandVoxel& v : bandOf(shape))
            acc.setValueOn(v.ijk, v.value);
    }

    /// Every inactive voxel and tile has magnitude `outside` (positive side) or `-inside`
    /// (negative side), on the side of the surface the analytic distance gives for each of its
    /// corners and its centre.
    static ::testing::AssertionResult inactiveSignsMatch(const TreeT& tree, const Shape& shape,
                                                         float outside, float inside,
                                                         Index64& insideTiles) {
        insideTiles = 0;
        for (auto it = tree.cbeginValueOff(); it; ++it) {
            CoordBBox bbox;
            it.getBoundingBox(bbox);
            const float value = it.getValue();
            const Int32 e = bbox.dim()[0] - 1;
            const Coord& lo = bbox.min();
            auto check = [&](const Coord& p) {
                const bool in = test::sdfAt(shape.sdf, p) < 0.0;
                if (value == (in ? inside : outside))
                    return ::testing::AssertionSuccess();
                return ::testing::AssertionFailure()
                       << (e == 0 ? "voxel " : "tile ") << bbox << " holds " << value
                       << " but the distance at " << p << " is " << test::sdfAt(shape.sdf, p);
            };
            if (e == 0) {
                if (auto r = check(lo); !r)
                    return r;
                continue;
            }
            for (const Coord& p : {lo, lo.offsetBy(e, e, e), lo.offsetBy(e / 2, e / 2, e / 2),
                                   lo.offsetBy(e, 0, 0), lo.offsetBy(0, e, 0), lo.offsetBy(0, 0, e),
                                   lo.offsetBy(e, e, 0), lo.offsetBy(0, e, e)}) {
                if (auto r = check(p); !r)
                    return r;
            }
            if (e > 0 && value < 0.0f)
                ++insideTiles;
        }
        return ::testing::AssertionSuccess();
    }
};

using FloodFillConfigs =
    ::testing::Types<HashTree543, MapTree432, FixedTree6543, FixedTree6545, FixedTree6542>;
TYPED_TEST_SUITE(SignedFloodFill, FloodFillConfigs, test::ConfigName);

TYPED_TEST(SignedFloodFill, InactiveValuesTakeTheSignOfTheAnalyticDistance) {
    using TreeT = typename TestFixture::TreeT;
    for (const Shape& shape : testShapes()) {
        SCOPED_TRACE(shape.name);
        TreeT tree(kBackground);
        TestFixture::writeBand(tree, shape);
        const Index32 leafCount = tree.leafCount();
        tools::signedFloodFill(tree);

        Index64 insideTiles = 0;
        EXPECT_TRUE(
            TestFixture::inactiveSignsMatch(tree, shape, kBackground, -kBackground, insideTiles));
        if constexpr (TreeT::LeafNodeType::DIM <= 8) {
            EXPECT_GT(insideTiles, 0u) << "no tile inside the shape: the test checks too little";
        }
        // Active values are untouched, and no node is added or removed.
        typename TreeT::ConstAccessor acc(tree);
        for (const BandVoxel& v : bandOf(shape)) {
            float value;
            ASSERT_TRUE(acc.probeValue(v.ijk, value)) << v.ijk;
            ASSERT_TRUE(test::sameBits(value, v.value)) << v.ijk;
        }
        EXPECT_EQ(tree.activeVoxelCount(), bandOf(shape).size());
        EXPECT_EQ(tree.leafCount(), leafCount);
        EXPECT_EQ(tree.background(), kBackground);
        EXPECT_EQ(tree.getValue(Coord(100000, -100000, 3)), kBackground);
    }
}

TYPED_TEST(SignedFloodFill, WithValuesUsesTheGivenMagnitudes) {
    using TreeT = typename TestFixture::TreeT;
    const Shape& shape = shapes()[0];
    TreeT tree(kBackground);
    TestFixture::writeBand(tree, shape);
    // The signs of the arguments do not matter: outside +|5|, inside -|1.5|.
    tools::signedFloodFillWithValues(tree, -5.0f, 1.5f);
    Index64 insideTiles = 0;
    EXPECT_TRUE(TestFixture::inactiveSignsMatch(tree, shape, 5.0f, -1.5f, insideTiles));
    EXPECT_EQ(tree.background(), 5.0f);
    EXPECT_EQ(tree.getValue(Coord(100000, -100000, 3)), 5.0f);
}

TYPED_TEST(SignedFloodFill, ThreadedMatchesSingleThreadedBitForBit) {
    using TreeT = typename TestFixture::TreeT;
    for (const Shape& shape : testShapes()) {
        SCOPED_TRACE(shape.name);
        TreeT a(kBackground);
        TestFixture::writeBand(a, shape);
        TreeT b(a);
        tools::signedFloodFill(a, true);
        tools::signedFloodFill(b, false);
        EXPECT_TRUE(test::identicalTrees(a, b));
    }
}

// ---- The scanline rules on hand-made trees -----------------------------------------------------

TEST(SignedFloodFillRules, LeafScanlinesCarryTheLastActiveSign) {
    FloatTree tree(1.0f);
    tree.setValueOn(Coord(0, 0, 3), -0.5f);
    tree.setValueOn(Coord(0, 0, 6), 0.5f);
    tree.setValueOn(Coord(1, 0, 0), 0.25f);   // starts slice x = 1 outside
    tree.setValueOn(Coord(1, 2, 0), -0.25f);  // starts line (1, 2) inside
    tree.setValueOn(Coord(2, 5, 4), -0.75f);  // mid-line only: slice 2 keeps slice 1's start
    tools::signedFloodFill(tree, false);
    auto v = [&](Int32 x, Int32 y, Int32 z) { return tree.getValue(Coord(x, y, z)); };
    // Slice 0: seeded by the first active voxel (-0.5): inside until (0, 0, 6).
    EXPECT_EQ(v(0, 0, 0), -1.0f);
    EXPECT_EQ(v(0, 0, 5), -1.0f);
    EXPECT_EQ(v(0, 0, 7), 1.0f);
    EXPECT_EQ(v(0, 1, 0), -1.0f);  // line (0, 1) starts as line (0, 0) started
    EXPECT_EQ(v(0, 7, 7), -1.0f);
    // Slice 1: (1, 0, 0) is outside; line (1, 2) restarts inside, later lines follow it.
    EXPECT_EQ(v(1, 0, 1), 1.0f);
    EXPECT_EQ(v(1, 1, 5), 1.0f);
    EXPECT_EQ(v(1, 2, 5), -1.0f);
    EXPECT_EQ(v(1, 7, 7), -1.0f);
    // Slice 2 starts from slice 1's start (outside): (2, 5, 4) flips the rest of its line only.
    EXPECT_EQ(v(2, 0, 0), 1.0f);
    EXPECT_EQ(v(2, 5, 3), 1.0f);
    EXPECT_EQ(v(2, 5, 5), -1.0f);
    EXPECT_EQ(v(2, 6, 5), 1.0f);
    EXPECT_EQ(v(7, 7, 7), 1.0f);
    EXPECT_EQ(v(0, 0, 3), -0.5f);  // active values stay
}

TEST(SignedFloodFillRules, ScanlinesLongerThanAMaskWordCarryAcrossWords) {
    // Leaves of edge 128: each z-line spans two 64-bit mask words.
    using Tree128 = tree::Tree<tree::InternalNode<tree::LeafNode<float, 7>, 2>>;
    Tree128 tree(1.0f);
    tree.setValueOn(Coord(0, 0, 10), -0.5f);  // inside from here across the word boundary
    tree.setValueOn(Coord(0, 0, 100), 0.5f);  // outside after this one
    tree.setValueOn(Coord(0, 1, 63), 0.5f);   // active last voxel of the first word
    tree.setValueOn(Coord(0, 2, 0), 0.5f);    // line (0, 2) starts outside,
    tree.setValueOn(Coord(0, 2, 5), -0.5f);   // turns inside and stays so in the second word
    tools::signedFloodFill(tree, false);
    auto v = [&](Int32 y, Int32 z) { return tree.getValue(Coord(0, y, z)); };
    EXPECT_EQ(v(0, 9), -1.0f);  // the leaf's first active voxel seeds the line
    EXPECT_EQ(v(0, 63), -1.0f);
    EXPECT_EQ(v(0, 64), -1.0f);
    EXPECT_EQ(v(0, 99), -1.0f);
    EXPECT_EQ(v(0, 101), 1.0f);
    EXPECT_EQ(v(0, 127), 1.0f);
    EXPECT_EQ(v(1, 62), -1.0f);  // line (0, 1) starts as line (0, 0) started
    EXPECT_EQ(v(1, 64), 1.0f);   // the second word starts after an outside voxel
    EXPECT_EQ(v(1, 127), 1.0f);
    EXPECT_EQ(v(2, 3), 1.0f);
    EXPECT_EQ(v(2, 63), -1.0f);
    EXPECT_EQ(v(2, 64), -1.0f);  // carried across the word boundary
    EXPECT_EQ(v(2, 127), -1.0f);
    EXPECT_EQ(v(3, 70), 1.0f);  // line (0, 3) starts as line (0, 2) started
}

TEST(SignedFloodFillRules, LeavesAndNodesWithoutActiveValuesTakeTheirFirstSign) {
    FloatTree tree(1.0f);
    tree.setValueOff(Coord(0, 0, 0), -3.0f);  // first value negative, no active voxel
    tree.setValueOff(Coord(9, 0, 0), -3.0f);  // first value (8,0,0) is the background: positive
    tree.setValueOn(Coord(1000, 0, 0), 0.5f);
    tools::signedFloodFill(tree);
    EXPECT_EQ(tree.getValue(Coord(7, 7, 7)), -1.0f);
    EXPECT_EQ(tree.getValue(Coord(9, 0, 0)), 1.0f);
}

TEST(SignedFloodFillRules, RootGapsBetweenInsideChildrenBecomeInsideTiles) {
    FloatTree tree(3.0f);
    // Children at z keys 0 and 12288 face each other with negative values: the keys between
    // them become inside tiles. Between 16384 (last value inside) and 24576 (first value
    // outside) nothing is added, nor between the adjacent 12288 and 16384.
    tree.setValueOn(Coord(4095, 4095, 4095), -1.0f);
    tree.setValueOn(Coord(0, 0, 12288), -1.0f);
    tree.setValueOn(Coord(4095, 4095, 20479), -1.0f);
    tree.setValueOn(Coord(0, 0, 24576), 1.0f);
    // An active root tile in the first gap keeps its value and state.
    tree.fill(CoordBBox::createCube(Coord(0, 0, 8192), 4096), 7.0f, true);
    tools::signedFloodFill(tree);
    const auto& root = tree.topNode();
    const auto* gap = root.findEntry(Coord(0, 0, 4096));
    ASSERT_NE(gap, nullptr);
    EXPECT_TRUE(!gap->child && !gap->active && gap->tile == -3.0f);
    EXPECT_EQ(tree.getValue(Coord(0, 0, 8192)), 7.0f);
    EXPECT_TRUE(tree.isValueOn(Coord(0, 0, 8192)));
    EXPECT_EQ(root.findEntry(Coord(0, 0, 20480)), nullptr);
    EXPECT_EQ(tree.getValue(Coord(0, 0, 20480)), 3.0f);
    EXPECT_EQ(root.entryCount(), 6u);
}

TEST(SignedFloodFillRules, BoundedTopScansInSpatialOrder) {
    // The top of a [6,5,4,3] tree covers [-2^17, 2^17) with 4096-voxel children; its table
    // starts at coordinate 0. A child just below z = 0 whose last value is inside makes the
    // tile at [0, 4096) inside; one at [4096, 8192) whose values are outside makes the
    // tiles after it outside, and the tiles before the first child follow its first value.
    using TreeT = tree::FixedTree6543<float>;
    TreeT tree(2.0f);
    tree.setValueOn(Coord(4095, 4095, -1), -1.0f);
    tree.setValueOn(Coord(0, 0, 4096), 1.0f);
    tools::signedFloodFill(tree);
    EXPECT_EQ(tree.getValue(Coord(0, 0, 0)), -2.0f);
    EXPECT_EQ(tree.getValue(Coord(0, 0, 8192)), 2.0f);
    EXPECT_EQ(tree.getValue(Coord(0, 0, -8192)), -2.0f);
    EXPECT_EQ(tree.getValue(Coord(-131072, -131072, -131072)), -2.0f);
}

TEST(SignedFloodFillRules, IntegerAndDoubleTrees) {
    Int32Tree ints(4);
    ints.setValueOn(Coord(0, 0, 1), -1);
    ints.setValueOn(Coord(0, 0, 3), 1);
    tools::signedFloodFill(ints);
    EXPECT_EQ(ints.getValue(Coord(0, 0, 0)), -4);
    EXPECT_EQ(ints.getValue(Coord(0, 0, 2)), -4);
    EXPECT_EQ(ints.getValue(Coord(0, 0, 4)), 4);

    DoubleTree doubles(-0.5);  // a negative background: outside becomes +0.5
    doubles.setValueOn(Coord(0, 0, 1), -1.0);
    tools::signedFloodFill(doubles);
    EXPECT_EQ(doubles.getValue(Coord(0, 0, 0)), -0.5);
    EXPECT_EQ(doubles.background(), 0.5);
    EXPECT_EQ(doubles.getValue(Coord(100000)), 0.5);
}

}  // namespace
}  // namespace vdb
