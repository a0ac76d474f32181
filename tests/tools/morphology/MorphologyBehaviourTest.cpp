// SPDX-License-Identifier: Apache-2.0
// Oracles: analytic shapes (balls of each neighbourhood, boxes grown or shrunk by a distance),
// values written by hand before the operation, the 32-bit index limits, and the same
// operation run single-threaded (bit-for-bit equality of the trees).

#include <vdb/tools/Morphology.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/TreeConfigs.h>

#include "MorphologyOracle.h"
#include <Oracles.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <random>

namespace vdb::tools {
namespace {

constexpr NearestNeighbors ALL_NN[] = {NN_FACE, NN_FACE_EDGE, NN_FACE_EDGE_VERTEX};
constexpr TilePolicy ALL_POLICIES[] = {IGNORE_TILES, EXPAND_TILES, PRESERVE_TILES};

/// True when a voxel at per-axis distances (dx, dy, dz) from a set lies within `k` steps of
/// `nn`: the L1 ball for faces, the cube for faces, edges and corners, and between them the
/// cube cut at L1 distance 2k.
bool withinSteps(NearestNeighbors nn, Int64 dx, Int64 dy, Int64 dz, int k) {
    const Int64 maxD = std::max({dx, dy, dz}), sum = dx + dy + dz;
    if (nn == NN_FACE)
        return sum <= k;
    if (nn == NN_FACE_EDGE)
        return maxD <= k && sum <= 2 * k;
    return maxD <= k;
}

/// Per-axis distance from `v` to the box.
Int64 axisDistance(Int32 v, Int32 lo, Int32 hi) {
    return v < lo ? Int64(lo) - v : v > hi ? Int64(v) - hi : 0;
}

// ---- Balls ------------------------------------------------------------------------------------

TEST(Morphology, OneVoxelDilatesIntoTheBallOfItsNeighbourhoodAndErodesBack) {
    const Coord seed(-1, 7, 8);  // a leaf corner, so the ball spans eight leaves
    for (NearestNeighbors nn : ALL_NN) {
        for (int k = 1; k <= 4; ++k) {
            FloatTree tree(0.0f);
            tree.setValue(seed, 1.0f);
            dilateActiveValues(tree, k, nn);
            Index64 count = 0;
            for (int x = -k; x <= k; ++x)
                for (int y = -k; y <= k; ++y)
                    for (int z = -k; z <= k; ++z) {
                        const bool in = withinSteps(nn, std::abs(x), std::abs(y), std::abs(z), k);
                        count += in;
                        ASSERT_EQ(tree.isValueOn(seed.offsetBy(x, y, z)), in)
                            << "nn " << int(nn) << " k " << k << " at " << x << "," << y << ","
                            << z;
                    }
            EXPECT_EQ(tree.activeVoxelCount(), count);
            // The ball eroded by the same steps is its centre again.
            erodeActiveValues(tree, k, nn);
            EXPECT_EQ(tree.activeVoxelCount(), 1u);
            EXPECT_TRUE(tree.isValueOn(seed));
        }
    }
}

// ---- Values -----------------------------------------------------------------------------------

TEST(Morphology, DilatedVoxelsKeepTheirValueTileValueOrBackground) {
    for (TilePolicy mode : ALL_POLICIES) {
        FloatTree tree(0.5f);
        tree.fill(CoordBBox::createCube(Coord(8, 0, 0), 8), 5.0f, false);      // inactive leaf tile
        tree.fill(CoordBBox::createCube(Coord(128, 0, 0), 128), 7.0f, false);  // inactive node tile
        tree.setValue(Coord(7, 3, 3), 1.0f);
        tree.setValueOff(Coord(6, 3, 3), 9.0f);  // inactive voxel of the same leaf
        tree.setValue(Coord(127, 50, 50), 2.0f);
        tree.setValue(Coord(0, 0, 0), 3.0f);  // its -x neighbour lies outside every node
        dilateActiveValues(tree, 1, NN_FACE, mode);
        EXPECT_TRUE(tree.isValueOn(Coord(8, 3, 3)));
        EXPECT_EQ(tree.getValue(Coord(8, 3, 3)), 5.0f) << "tile value";
        EXPECT_TRUE(tree.isValueOn(Coord(6, 3, 3)));
        EXPECT_EQ(tree.getValue(Coord(6, 3, 3)), 9.0f) << "inactive value kept";
        EXPECT_TRUE(tree.isValueOn(Coord(128, 50, 50)));
        EXPECT_EQ(tree.getValue(Coord(128, 50, 50)), 7.0f) << "larger tile value";
        EXPECT_EQ(tree.getValue(Coord(129, 50, 50)), 7.0f);
        EXPECT_FALSE(tree.isValueOn(Coord(129, 50, 50)));
        EXPECT_TRUE(tree.isValueOn(Coord(-1, 0, 0)));
        EXPECT_EQ(tree.getValue(Coord(-1, 0, 0)), 0.5f) << "background";
        EXPECT_EQ(tree.getValue(Coord(7, 3, 3)), 1.0f);
        EXPECT_EQ(tree.activeVoxelCount(), 3u * 7u);
    }
}

TEST(Morphology, PreservedErosionReplacesEmptiedNodesByBackground) {
    // Leaf A holds one active voxel among inactive values; leaf B a 3^3 block; leaf C only
    // inactive values; beside B an inactive tile; a second internal node holds only leaf D,
    // with one active voxel, and an inactive tile.
    auto build = [] {
        FloatTree tree(0.0f);
        tree.setValueOff(Coord(1, 1, 1), 4.0f);
        tree.setValue(Coord(2, 2, 2), 1.0f);                                 // A
        tree.fill(CoordBBox(Coord(9, 1, 1), Coord(11, 3, 3)), 2.0f, true);   // B
        tree.setValueOff(Coord(8, 0, 0), 6.0f);                              // in B
        tree.setValueOff(Coord(20, 1, 1), 8.0f);                             // C
        tree.fill(CoordBBox::createCube(Coord(24, 0, 0), 8), 3.0f, false);   // tile
        tree.setValue(Coord(200, 1, 1), 5.0f);                               // D
        tree.fill(CoordBBox::createCube(Coord(208, 0, 0), 8), 9.0f, false);  // tile
        return tree;
    };
    {
        FloatTree tree = build();
        erodeActiveValues(tree, 1, NN_FACE_EDGE_VERTEX, PRESERVE_TILES);
        EXPECT_EQ(tree.activeVoxelCount(), 1u);
        EXPECT_TRUE(tree.isValueOn(Coord(10, 2, 2)));
        EXPECT_EQ(tree.leafCount(), 1u) << "only B keeps a leaf";
        EXPECT_EQ(tree.getValue(Coord(1, 1, 1)), 0.0f) << "A became background";
        EXPECT_EQ(tree.getValue(Coord(2, 2, 2)), 0.0f);
        EXPECT_EQ(tree.getValue(Coord(9, 1, 1)), 2.0f) << "B keeps its values";
        EXPECT_EQ(tree.getValue(Coord(8, 0, 0)), 6.0f);
        EXPECT_EQ(tree.getValue(Coord(20, 1, 1)), 0.0f) << "C became background";
        EXPECT_EQ(tree.getValue(Coord(24, 0, 0)), 3.0f) << "inactive tiles stay";
        EXPECT_EQ(tree.getValue(Coord(200, 1, 1)), 0.0f) << "D's node became background";
        EXPECT_EQ(tree.getValue(Coord(208, 0, 0)), 0.0f);
        EXPECT_TRUE(test::morph::noInactiveBranches(tree));
    }
    for (TilePolicy mode : {IGNORE_TILES, EXPAND_TILES}) {
        FloatTree tree = build();
        const Index32 leaves = tree.leafCount();
        erodeActiveValues(tree, 1, NN_FACE_EDGE_VERTEX, mode);
        EXPECT_EQ(tree.activeVoxelCount(), 1u);
        EXPECT_EQ(tree.leafCount(), leaves) << "no leaf removed";
        EXPECT_EQ(tree.getValue(Coord(1, 1, 1)), 4.0f);
        EXPECT_EQ(tree.getValue(Coord(2, 2, 2)), 1.0f);
        EXPECT_EQ(tree.getValue(Coord(20, 1, 1)), 8.0f);
        EXPECT_EQ(tree.getValue(Coord(208, 0, 0)), 9.0f);
    }
}

TEST(Morphology, PreservedDilationPrunesUniformNodes) {
    // A leaf of value 1 everywhere with its inner 6^3 active: one step fills it, and only
    // PRESERVE_TILES turns it into a tile.
    for (TilePolicy mode : ALL_POLICIES) {
        FloatTree tree(0.0f);
        tree.fill(CoordBBox(Coord(0), Coord(7)), 1.0f, false);
        tree.fill(CoordBBox(Coord(1), Coord(6)), 1.0f, true);
        ASSERT_NE(tree.probeConstLeaf(Coord(0)), nullptr);
        dilateActiveValues(tree, 1, NN_FACE_EDGE_VERTEX, mode);
        EXPECT_EQ(tree.activeVoxelCount(), 512u);
        EXPECT_EQ(tree.activeTileCount(), mode == PRESERVE_TILES ? 1u : 0u);
        EXPECT_EQ(tree.probeConstLeaf(Coord(0)) == nullptr, mode == PRESERVE_TILES);
        EXPECT_EQ(tree.getValue(Coord(0)), 1.0f);
    }
}

// ---- Tiles ------------------------------------------------------------------------------------

TEST(Morphology, IgnoredTilesNeitherBlockDilationNorErode) {
    FloatTree tree(0.0f);
    tree.fill(CoordBBox::createCube(Coord(0, 0, 0), 8), 2.0f, true);
    tree.setValue(Coord(-1, 4, 4), 1.0f);
    dilateActiveValues(tree, 10, NN_FACE, IGNORE_TILES);
    // The voxel grows through the tile's region as if it were absent; the tile stays.
    EXPECT_TRUE(tree.isValueOn(Coord(9, 4, 4)));
    EXPECT_FALSE(tree.isValueOn(Coord(10, 4, 4)));
    EXPECT_EQ(tree.activeTileCount(), 1u);
    EXPECT_EQ(tree.getValue(Coord(3, 3, 3)), 2.0f);

    // A slab on the tile's face erodes from its other faces only.
    FloatTree slab(0.0f);
    slab.fill(CoordBBox::createCube(Coord(0, 0, 0), 8), 2.0f, true);
    slab.fill(CoordBBox(Coord(-2, 0, 0), Coord(-1, 7, 7)), 1.0f, true);
    erodeActiveValues(slab, 1, NN_FACE, IGNORE_TILES);
    EXPECT_EQ(slab.activeTileCount(), 1u);
    EXPECT_TRUE(slab.isValueOn(Coord(-1, 3, 3)));   // its +x neighbour is the tile
    EXPECT_FALSE(slab.isValueOn(Coord(-2, 3, 3)));  // its -x neighbour is empty
    EXPECT_FALSE(slab.isValueOn(Coord(-1, 0, 3)));  // its -y neighbour is empty
    EXPECT_EQ(slab.activeVoxelCount(), 512u + 6u * 6u);
}

/// Two tiles of a level-2 node side by side, with a two-voxel layer of leaf voxels on top:
/// together the box [0, 2T) x [0, T) x [0, T + 2). Checks every voxel within k + 1 of it.
template <typename TreeT>
void checkBoxOfTiles(const std::vector<int>& dilations, const std::vector<int>& erosions,
                     std::initializer_list<NearestNeighbors> neighbourhoods) {
    using TopT = typename TreeT::TopNodeType;
    constexpr Int32 T = Int32(tree::NodeAtLevelT<TopT, 1>::DIM);  // a level-2 tile's edge
    constexpr Int32 LEAF = Int32(TreeT::LeafNodeType::DIM);
    constexpr Index LEAF_LOG2 = TreeT::LeafNodeType::LOG2DIM;
    const CoordBBox tile1 = CoordBBox::createCube(Coord(0), T);
    const CoordBBox tile2 = CoordBBox::createCube(Coord(T, 0, 0), T);
    const CoordBBox layer(Coord(0, 0, T), Coord(2 * T - 1, T - 1, T + 1));
    const CoordBBox box(Coord(0), layer.max());
    TreeT scene(0.0f);
    scene.fill(tile1, 1.0f, true);
    scene.fill(tile2, 2.0f, true);
    for (Int32 x = layer.min()[0]; x <= layer.max()[0]; ++x)
        for (Int32 y = layer.min()[1]; y <= layer.max()[1]; ++y)
            for (Int32 z = layer.min()[2]; z <= layer.max()[2]; ++z)
                scene.setValue(Coord(x, y, z), 3.0f);
    ASSERT_EQ(scene.activeTileCount(), 2u);

    auto dist = [](const Coord& v, const CoordBBox& b, Int64 d[3]) {
        for (int a = 0; a < 3; ++a)
            d[a] = axisDistance(v[a], b.min()[a], b.max()[a]);
    };
    for (bool dilate : {true, false})
        for (NearestNeighbors nn : neighbourhoods)
            for (TilePolicy mode : ALL_POLICIES)
                for (int k : dilate ? dilations : erosions) {
                    SCOPED_TRACE(::testing::Message()
                                 << (dilate ? "dilate" : "erode") << " nn " << int(nn) << " policy "
                                 << int(mode) << " x" << k);
                    TreeT tree = scene;
                    if (dilate) {
                        dilateActiveValues(tree, k, nn, mode);
                    } else {
                        erodeActiveValues(tree, k, nn, mode);
                    }
                    if (mode == EXPAND_TILES) {
                        EXPECT_EQ(tree.activeTileCount(), 0u);
                    } else if (mode == IGNORE_TILES) {
                        EXPECT_EQ(tree.activeTileCount(), 2u);
                    }
                    // Layer leaves die when PRESERVE_TILES erosion empties them.
                    const bool layerGone = !dilate && mode == PRESERVE_TILES && k >= 2;
                    auto expectedOn = [&](const Coord& v) {
                        const bool inTiles = tile1.isInside(v) || tile2.isInside(v);
                        if (dilate) {
                            const CoordBBox& source = mode == IGNORE_TILES ? layer : box;
                            Int64 d[3];
                            dist(v, source, d);
                            return withinSteps(nn, d[0], d[1], d[2], k) ||
                                   (mode == IGNORE_TILES && inTiles);
                        }
                        const Int32 x = v[0], y = v[1], z = v[2];
                        if (mode == IGNORE_TILES) {
                            // The layer's top erodes first; then its bottom row, on the
                            // tiles, has nothing left above it.
                            return inTiles || (k == 1 && z == T && x >= 1 && x < 2 * T - 1 &&
                                               y >= 1 && y < T - 1);
                        }
                        return x >= k && x < 2 * T - k && y >= k && y < T - k && z >= k &&
                               z < T + 2 - k;
                    };
                    auto expectedValue = [&](const Coord& v) {
                        return tile1.isInside(v)                 ? 1.0f
                               : tile2.isInside(v)               ? 2.0f
                               : layer.isInside(v) && !layerGone ? 3.0f
                                                                 : 0.0f;
                    };
                    // Region by region: a leaf's own bits, else one state and value for the
                    // whole region.
                    typename TreeT::ConstAccessor acc(tree);
                    CoordBBox scan = box;
                    scan.expand(k + 1);
                    const Coord lo = scan.min().alignedDown(LEAF_LOG2);
                    Index64 count = 0;
                    for (Int32 rx = lo[0]; rx <= scan.max()[0]; rx += LEAF)
                        for (Int32 ry = lo[1]; ry <= scan.max()[1]; ry += LEAF)
                            for (Int32 rz = lo[2]; rz <= scan.max()[2]; rz += LEAF) {
                                const Coord origin(rx, ry, rz);
                                const auto* leaf = acc.probeConstLeaf(origin);
                                const bool regionOn = acc.isValueOn(origin);
                                const float regionValue = acc.getValue(origin);
                                for (Int32 i = 0; i < LEAF; ++i)
                                    for (Int32 j = 0; j < LEAF; ++j)
                                        for (Int32 l = 0; l < LEAF; ++l) {
                                            const Coord v = origin.offsetBy(i, j, l);
                                            const bool on = leaf ? leaf->isValueOn(v) : regionOn;
                                            const float value =
                                                leaf ? leaf->getValue(v) : regionValue;
                                            const bool want = expectedOn(v);
                                            count += want;
                                            if (on != want || value != expectedValue(v)) {
                                                FAIL() << v << (on ? " on " : " off ") << value;
                                            }
                                        }
                            }
                    EXPECT_EQ(tree.activeVoxelCount(), count);
                    if (mode == PRESERVE_TILES) {
                        EXPECT_TRUE(dilate ? test::morph::isPruned(tree)
                                           : test::morph::noInactiveBranches(tree));
                    }
                }
}

TEST(Morphology, LargeTilesDilateAndErodeAsBoxes) {
    // 32^3 tiles of 4^3 leaves: erosion reaches up to three regions deep.
    checkBoxOfTiles<tree::HashTree432<float>>({1, 5, 10}, {1, 5, 10},
                                              {NN_FACE, NN_FACE_EDGE, NN_FACE_EDGE_VERTEX});
}

TEST(Morphology, LargeTilesOfTheStandardTreeDilateAndErodeAsBoxes) {
    // 128^3 tiles of 8^3 leaves; erosion reaches two regions deep. One neighbourhood in the
    // sanitizer run.
    if (test::workloadScale() < 0.5) {
        checkBoxOfTiles<FloatTree>({2}, {9}, {NN_FACE_EDGE_VERTEX});
    } else {
        checkBoxOfTiles<FloatTree>({2}, {9}, {NN_FACE, NN_FACE_EDGE_VERTEX});
    }
}

// ---- Domain limits ----------------------------------------------------------------------------

TEST(Morphology, BoundedTreeDilationStopsAtTheDomainEdge) {
    using TreeT = tree::FixedTree6543<float>;
    const CoordBBox domain = TreeT::domain();
    TreeT tree(0.0f);
    tree.setValue(domain.max(), 1.0f);
    tree.setValue(domain.min(), 1.0f);
    dilateActiveValues(tree, 3, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 2u * 4u * 4u * 4u);
    CoordBBox bbox;
    ASSERT_TRUE(tree.evalActiveVoxelBoundingBox(bbox));
    EXPECT_EQ(bbox, domain);
    EXPECT_EQ(tree.leafCount(), 2u);
    // Outside the domain counts as inactive: the corner cubes erode from every face.
    erodeActiveValues(tree, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 2u * 2u * 2u * 2u);
}

TEST(Morphology, UnboundedTreeDoesNotWrapAroundTheIndexSpace) {
    constexpr Int32 lo = std::numeric_limits<Int32>::min(), hi = std::numeric_limits<Int32>::max();
    FloatTree tree(0.0f);
    tree.setValue(Coord(hi, lo, 0), 1.0f);
    dilateActiveValues(tree, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 2u * 2u * 3u);
    EXPECT_FALSE(tree.isValueOn(Coord(lo, lo, 0)));
    EXPECT_FALSE(tree.isValueOn(Coord(hi, hi, 0)));
    EXPECT_TRUE(tree.isValueOn(Coord(hi - 1, lo + 1, 1)));
    erodeActiveValues(tree, 1, NN_FACE);
    EXPECT_EQ(tree.activeVoxelCount(), 0u);
}

// ---- Leaf manager -----------------------------------------------------------------------------

TEST(Morphology, LeafManagerOverloadsRebuildTheLeafArray) {
    FloatTree tree(0.0f);
    tree.setValue(Coord(7, 7, 7), 1.0f);
    tree::LeafManager<FloatTree> leaves(tree, 1);
    dilateActiveValues(leaves, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 27u);
    EXPECT_EQ(leaves.leafCount(), 8u);
    EXPECT_EQ(leaves.leafCount(), tree.leafCount());
    EXPECT_EQ(leaves.auxBufferCount(), 1u);
    erodeActiveValues(leaves, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 1u);
    EXPECT_EQ(leaves.leafCount(), 1u) << "PRESERVE_TILES erosion removed the emptied leaves";
}

template <typename TreeT>
void checkLeafManagerOverloadsWithoutBuffers() {
    TreeT tree(false);
    tree.setValueOn(Coord(7, 7, 7));
    tree::LeafManager<TreeT> leaves(tree);
    dilateActiveValues(leaves, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 27u);
    EXPECT_EQ(leaves.leafCount(), 8u);
    EXPECT_EQ(leaves.leafCount(), tree.leafCount());
    erodeActiveValues(leaves, 1, NN_FACE_EDGE_VERTEX);
    EXPECT_EQ(tree.activeVoxelCount(), 1u);
    EXPECT_EQ(leaves.leafCount(), tree.leafCount());
}

TEST(Morphology, LeafManagerOverloadsWorkOnBoolAndMaskTrees) {
    checkLeafManagerOverloadsWithoutBuffers<BoolTree>();
    checkLeafManagerOverloadsWithoutBuffers<MaskTree>();
}

// ---- Threads ----------------------------------------------------------------------------------

/// Balls, a random cloud and tiles of two sizes: about 4000 leaves at full scale.
template <typename TreeT>
TreeT makeLargeScene(uint32_t seed) {
    using ValueT = typename TreeT::ValueType;
    TreeT tree(ValueT(0));
    std::mt19937 rng(seed);
    std::uniform_int_distribution<Int32> coord(-300, 300);
    const int balls = std::max(2, int(10 * test::workloadScale()));
    for (int b = 0; b < balls; ++b) {
        const Coord c(coord(rng), coord(rng), coord(rng));
        const int r = 4 + int(rng() % 8);
        for (int x = -r; x <= r; ++x)
            for (int y = -r; y <= r; ++y)
                for (int z = -r; z <= r; ++z)
                    if (x * x + y * y + z * z <= r * r)
                        tree.setValue(c.offsetBy(x, y, z), ValueT(1 + rng() % 5));
    }
    for (int i = 0; i < int(4000 * test::workloadScale()); ++i)
        tree.setValue(Coord(coord(rng), coord(rng), coord(rng)), ValueT(1 + rng() % 5));
    for (int t = 0; t < 30; ++t) {
        const Coord c = Coord(coord(rng), coord(rng), coord(rng)).alignedDown(3);
        tree.fill(CoordBBox::createCube(c, 8), ValueT(1 + rng() % 5), true);
    }
    tree.fill(CoordBBox::createCube(Coord(-512, 0, 128), 128), ValueT(2), true);
    return tree;
}

template <typename TreeT>
void checkThreadedEqualsSingleThreaded(uint32_t seed) {
    const TreeT scene = makeLargeScene<TreeT>(seed);
    for (bool dilate : {true, false})
        for (NearestNeighbors nn : ALL_NN)
            for (TilePolicy mode : ALL_POLICIES) {
                SCOPED_TRACE(::testing::Message() << (dilate ? "dilate" : "erode") << " nn "
                                                  << int(nn) << " policy " << int(mode));
                TreeT threaded = scene, serial = scene;
                if (dilate) {
                    dilateActiveValues(threaded, 2, nn, mode, true);
                    dilateActiveValues(serial, 2, nn, mode, false);
                } else {
                    erodeActiveValues(threaded, 2, nn, mode, true);
                    erodeActiveValues(serial, 2, nn, mode, false);
                }
                ASSERT_TRUE(test::morph::identicalTrees(threaded, serial));
            }
}

TEST(Morphology, ThreadedEqualsSingleThreadedBitForBit) {
    checkThreadedEqualsSingleThreaded<FloatTree>(11u);
}

TEST(Morphology, ThreadedEqualsSingleThreadedBitForBitOnMaskTrees) {
    checkThreadedEqualsSingleThreaded<MaskTree>(12u);
}

}  // namespace
}  // namespace vdb::tools
