// SPDX-License-Identifier: Apache-2.0
// Oracle: brute-force dilation and erosion of plain coordinate sets (MorphologyOracle.h), with
// each tile policy written out as a set rule, on random sparse clouds, dense balls across leaf
// and internal-node boundaries, negative coordinates, active and inactive tiles and domain
// corners; for every neighbourhood, tile policy and iteration count, on several value types
// and tree configurations (root and bounded tops, 4^3, 8^3 and 32^3 leaves).

#include <vdb/Grid.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tree/TreeConfigs.h>

#include "MorphologyOracle.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <iterator>
#include <random>
#include <sstream>
#include <string>
#include <type_traits>

namespace vdb::tools {
namespace {

using test::morph::CoordSet;

// ---- Configurations ---------------------------------------------------------------------------

struct Float543 {
    using TreeType = FloatTree;
    static constexpr const char* NAME = "Float543";
    static constexpr bool FULL = true;
};
struct FloatBounded6543 {
    using TreeType = tree::FixedTree6543<float>;
    static constexpr const char* NAME = "FloatBounded6543";
    static constexpr bool FULL = true;
};
struct FloatLeaf4 {
    using TreeType = tree::HashTree432<float>;
    static constexpr const char* NAME = "FloatRoot432";
    static constexpr bool FULL = true;
};
struct FloatBoundedLeaf4 {
    using TreeType = tree::FixedTree6542<float>;
    static constexpr const char* NAME = "FloatBounded6542";
    static constexpr bool FULL = false;
};
struct DoubleBoundedLeaf32 {
    using TreeType = tree::FixedTree6545<double>;
    static constexpr const char* NAME = "DoubleBounded6545";
    static constexpr bool FULL = false;
};
struct Int32543 {
    using TreeType = Int32Tree;
    static constexpr const char* NAME = "Int32";
    static constexpr bool FULL = true;
};
struct Bool543 {
    using TreeType = BoolTree;
    static constexpr const char* NAME = "Bool";
    static constexpr bool FULL = true;
};
struct Mask543 {
    using TreeType = MaskTree;
    static constexpr const char* NAME = "Mask";
    static constexpr bool FULL = true;
};
struct MaskLeaf4 {
    using TreeType = tree::MapTree432<ValueMask>;
    static constexpr const char* NAME = "MaskMap432";
    static constexpr bool FULL = false;
};
struct Vec3s543 {
    using TreeType = Vec3STree;
    static constexpr const char* NAME = "Vec3s";
    static constexpr bool FULL = false;
};

template <typename TreeT>
constexpr bool IS_MASK = std::is_same_v<typename TreeT::BuildType, ValueMask>;

/// A value for label `i` (1 to 9), never the background.
template <typename ValueT>
ValueT valueOf(int i) {
    if constexpr (std::is_same_v<ValueT, bool>) {
        return true;
    } else if constexpr (std::is_same_v<ValueT, Vec3s>) {
        return Vec3s(float(i), -float(i), 0.5f * float(i));
    } else {
        return ValueT(i);
    }
}

// ---- Scenes -----------------------------------------------------------------------------------

/// A tree with: active tiles of leaf size (isolated, touching a ball, and one two leaves from
/// another tile) unless `withTiles` is false, an inactive tile of a non-background value beside
/// active voxels, two balls (at the origin and at a corner of internal nodes), a random cloud
/// with some inactive non-background voxels, and, in a bounded tree, voxels at the domain
/// corners. (Tiles larger than a leaf are in MorphologyBehaviourTest.cpp.)
template <typename TreeT>
TreeT makeScene(uint32_t seed, int cloudPoints, Int32 cloudRadius, bool withTiles = true) {
    using ValueT = typename TreeT::ValueType;
    using TopT = typename TreeT::TopNodeType;
    constexpr Int32 LEAF = Int32(TreeT::LeafNodeType::DIM);
    constexpr Int32 NODE1 = Int32(tree::NodeAtLevelT<TopT, 1>::DIM);
    TreeT tree(ValueT{});
    std::mt19937 rng(seed);
    auto value = [&] { return valueOf<ValueT>(1 + int(rng() % 9)); };

    // Tiles one leaf region in size (level 1), some touching the ball at the origin; just one
    // when leaves are large, to keep the set model small.
    const Coord tileOrigins[] = {Coord(3 * LEAF, 3 * LEAF, -3 * LEAF), Coord(LEAF, 0, 0),
                                 Coord(-2 * LEAF, -LEAF, 0), Coord(0, 3 * LEAF, LEAF),
                                 Coord(0, 3 * LEAF, 3 * LEAF)};
    const size_t tileCount = !withTiles ? 0 : LEAF > 8 ? 1 : std::size(tileOrigins);
    for (size_t t = 0; t < tileCount; ++t)
        tree.fill(CoordBBox::createCube(tileOrigins[t], LEAF), value(), true);
    // An inactive tile of a non-background value next to active voxels.
    if constexpr (!IS_MASK<TreeT>) {
        tree.fill(CoordBBox::createCube(Coord(-LEAF, 2 * LEAF, 0), LEAF), value(), false);
        tree.setValue(Coord(-1, 2 * LEAF + 1, 2), value());
    }
    // Balls across leaf boundaries, signs and internal-node boundaries.
    for (const Coord& c : {Coord(1, -2, 0), Coord(NODE1, -NODE1, NODE1)}) {
        const int r = 4;
        for (int x = -r; x <= r; ++x)
            for (int y = -r; y <= r; ++y)
                for (int z = -r; z <= r; ++z)
                    if (x * x + y * y + z * z <= r * r)
                        tree.setValue(c.offsetBy(x, y, z), value());
    }
    // A random cloud; every fifth point inactive with a value.
    std::uniform_int_distribution<Int32> coord(-cloudRadius, cloudRadius);
    for (int i = 0; i < cloudPoints; ++i) {
        const Coord ijk(coord(rng), coord(rng), coord(rng));
        if (i % 5 == 4 && !IS_MASK<TreeT>) {
            tree.setValueOff(ijk, value());
        } else {
            tree.setValue(ijk, value());
        }
    }
    if constexpr (TreeT::BOUNDED) {
        const CoordBBox d = TreeT::domain();
        tree.setValue(d.min(), value());
        tree.setValue(d.max(), value());
        tree.setValue(Coord(d.max()[0], 0, d.min()[2] + 1), value());
    }
    return tree;
}

std::string describe(bool dilate, NearestNeighbors nn, TilePolicy mode, int iterations) {
    static const char* policies[] = {"IGNORE_TILES", "EXPAND_TILES", "PRESERVE_TILES"};
    std::ostringstream s;
    s << (dilate ? "dilate" : "erode") << " nn=" << int(nn) << " " << policies[mode] << " x"
      << iterations;
    return s.str();
}

/// Runs one operation on a copy of `scene` and checks it against the set model, the values
/// and the structural promises of the policy.
template <typename TreeT>
void checkOperation(const TreeT& scene, const test::morph::Snapshot<TreeT>& before, bool dilate,
                    NearestNeighbors nn, TilePolicy mode, int iterations, bool threaded = true) {
    SCOPED_TRACE(describe(dilate, nn, mode, iterations));
    TreeT tree = scene;
    if (dilate) {
        dilateActiveValues(tree, iterations, nn, mode, threaded);
    } else {
        erodeActiveValues(tree, iterations, nn, mode, threaded);
    }
    const CoordSet expected = test::morph::expectedActive(before, dilate, nn, iterations, mode);
    ASSERT_TRUE(test::morph::sameActiveSet(tree, expected));

    const bool removesBranches = !dilate && mode == PRESERVE_TILES && iterations > 0;
    if constexpr (!IS_MASK<TreeT>) {
        const auto dead = removesBranches ? test::morph::deadBranches(scene, expected)
                                          : std::set<std::pair<Index, Coord>>{};
        ASSERT_TRUE(test::morph::valuesKept(scene, tree, expected, dead));
    }
    if (iterations <= 0) {
        EXPECT_TRUE(test::morph::identicalTrees(tree, scene));
        return;
    }
    if (mode == EXPAND_TILES) {
        EXPECT_EQ(tree.activeTileCount(), 0u);
    } else if (mode == IGNORE_TILES) {
        EXPECT_TRUE(test::morph::activeTiles(tree) == test::morph::activeTiles(scene))
            << "active tiles changed";
    }
    if (mode != PRESERVE_TILES) {
        // No node is removed: every leaf of the scene is still there.
        for (auto leaf = scene.cbeginLeaf(); leaf; ++leaf)
            ASSERT_NE(tree.probeConstLeaf(leaf->origin()), nullptr) << leaf->origin();
    } else if (dilate) {
        EXPECT_TRUE(test::morph::isPruned(tree));
    } else {
        EXPECT_TRUE(test::morph::noInactiveBranches(tree));
    }
    // Nothing outside a bounded tree's domain.
    CoordBBox bbox;
    if (tree.evalActiveVoxelBoundingBox(bbox)) {
        EXPECT_TRUE(TreeT::domain().isInside(bbox)) << bbox;
    }
}

// ---- Typed tests ------------------------------------------------------------------------------

template <typename ConfigT>
class MorphologyModel : public ::testing::Test {};
using ModelConfigs =
    ::testing::Types<Float543, FloatBounded6543, FloatLeaf4, FloatBoundedLeaf4, DoubleBoundedLeaf32,
                     Int32543, Bool543, Mask543, MaskLeaf4, Vec3s543>;
TYPED_TEST_SUITE(MorphologyModel, ModelConfigs, test::ConfigName);

TYPED_TEST(MorphologyModel, MatchesSetModelForEveryNeighbourhoodPolicyAndIterationCount) {
    // The full matrix on the main configurations; two steps on the others.
    using TreeT = typename TypeParam::TreeType;
    const int points = std::max(20, int(150 * test::workloadScale()));
    const TreeT scene = makeScene<TreeT>(20130601u, points, 40);
    const test::morph::Snapshot<TreeT> before(scene);
    ASSERT_FALSE(before.tiles.empty());
    const std::vector<int> iterationCounts =
        TypeParam::FULL ? std::vector<int>{1, 2, 3} : std::vector<int>{2};
    const bool reduced = !TypeParam::FULL && test::workloadScale() < 0.5;  // sanitizer run
    for (bool dilate : {true, false})
        for (NearestNeighbors nn : {NN_FACE, NN_FACE_EDGE, NN_FACE_EDGE_VERTEX})
            if (!reduced || nn == NN_FACE_EDGE)
                for (TilePolicy mode : {IGNORE_TILES, EXPAND_TILES, PRESERVE_TILES})
                    for (int iterations : iterationCounts) {
                        checkOperation(scene, before, dilate, nn, mode, iterations);
                        if (::testing::Test::HasFatalFailure())
                            return;
                    }
}

TYPED_TEST(MorphologyModel, ManyIterationsMatchSetModel) {
    // More steps than a leaf is wide: erosion reaches two regions deep into tiles.
    using TreeT = typename TypeParam::TreeType;
    constexpr int DIM = int(TreeT::LeafNodeType::DIM);
    if (!TypeParam::FULL && DIM > 4)
        GTEST_SKIP() << "covered by the main configurations";
    const int iterations = std::min(DIM + 2, 10);
    const TreeT scene = makeScene<TreeT>(7u, 0, 0);
    const test::morph::Snapshot<TreeT> before(scene);
    const bool reduced = test::workloadScale() < 0.5;  // the sanitizer run
    for (bool dilate : {true, false})
        for (NearestNeighbors nn : {NN_FACE, NN_FACE_EDGE_VERTEX})
            for (TilePolicy mode : {IGNORE_TILES, EXPAND_TILES, PRESERVE_TILES}) {
                // Faces only dilate, to keep the run short; reduced: PRESERVE_TILES only.
                if ((nn == NN_FACE && !dilate) || (reduced && mode != PRESERVE_TILES))
                    continue;
                checkOperation(scene, before, dilate, nn, mode, iterations);
                if (::testing::Test::HasFatalFailure())
                    return;
            }
}

TYPED_TEST(MorphologyModel, SingleThreadedWithoutTilesMatchesSetModel) {
    using TreeT = typename TypeParam::TreeType;
    const TreeT scene = makeScene<TreeT>(99u, std::max(20, int(100 * test::workloadScale())), 30,
                                         /*withTiles=*/false);
    const test::morph::Snapshot<TreeT> before(scene);
    ASSERT_TRUE(before.tiles.empty());
    for (bool dilate : {true, false})
        for (NearestNeighbors nn : {NN_FACE, NN_FACE_EDGE, NN_FACE_EDGE_VERTEX})
            for (TilePolicy mode : {IGNORE_TILES, PRESERVE_TILES}) {
                checkOperation(scene, before, dilate, nn, mode, 2, /*threaded=*/false);
                if (::testing::Test::HasFatalFailure())
                    return;
            }
}

TYPED_TEST(MorphologyModel, NonPositiveIterationsChangeNothing) {
    using TreeT = typename TypeParam::TreeType;
    const TreeT scene = makeScene<TreeT>(5u, 50, 30);
    const test::morph::Snapshot<TreeT> before(scene);
    for (bool dilate : {true, false})
        for (int iterations : {0, -3})
            checkOperation(scene, before, dilate, NN_FACE, EXPAND_TILES, iterations);
}

}  // namespace
}  // namespace vdb::tools
