// SPDX-License-Identifier: Apache-2.0
// Oracle: SparseVolumeModel (tests/support/Oracles.h), a hash map of voxels, and the tree's own
// uncached getValue(); the structural tests free the nodes an accessor has cached, so running
// them under AddressSanitizer shows whether an accessor ever follows a freed node.

#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <TableTwoConfigs.h>
#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <random>
#include <thread>
#include <utility>
#include <vector>

namespace vdb {
namespace {

using namespace test::configs;

template <typename C>
class ValueAccessorTyped : public ::testing::Test {
protected:
    using TreeT = typename C::TreeType;
    using Accessor = tree::ValueAccessor<TreeT>;
    using ConstAccessor = tree::ValueAccessor<const TreeT>;
    static constexpr float kBackground = 0.25f;

    ValueAccessorTyped() : tree(kBackground), acc(tree), cacc(tree) {}

    // The edge, in voxels, of the region of a node at `level` (0 = leaf).
    static Int32 regionDim(Index level) { return Int32(1) << C::shape().regionLog2(level); }

    TreeT tree;
    Accessor acc;
    ConstAccessor cacc;
    const Coord p{-3, 5, -7};
};
using Configs =
    ::testing::Types<HashTree543, MapTree543, FixedTree643, FixedTree6542, FixedTree3333>;
TYPED_TEST_SUITE(ValueAccessorTyped, Configs, test::ConfigName);

TYPED_TEST(ValueAccessorTyped, ClearOfTreeDropsCachedNodes) {
    auto& tree = this->tree;
    const Coord p = this->p;
    this->acc.setValue(p, 1.0f);
    EXPECT_EQ(this->cacc.getValue(p), 1.0f);
    EXPECT_TRUE(this->acc.isCached(p));
    EXPECT_TRUE(this->cacc.isCached(p));
    tree.clear();
    EXPECT_FALSE(this->acc.isCached(p));
    EXPECT_FALSE(this->cacc.isCached(p));
    EXPECT_EQ(this->acc.getValue(p), this->kBackground);
    EXPECT_FALSE(this->cacc.isValueOn(p));
    EXPECT_EQ(this->cacc.probeConstLeaf(p), nullptr);
    this->acc.setValue(p, 2.0f);
    EXPECT_EQ(tree.getValue(p), 2.0f);
    EXPECT_EQ(this->cacc.getValue(p), 2.0f);
    EXPECT_EQ(tree.activeVoxelCount(), 1u);
}

TYPED_TEST(ValueAccessorTyped, PruneOfCachedLeafLeavesAccessorCorrect) {
    auto& tree = this->tree;
    auto& acc = this->acc;
    const Int32 dim = this->regionDim(0);
    const Coord origin = this->p.alignedDown(TypeParam::shape().leafLog2());
    for (Int32 i = 0; i < dim; ++i)
        for (Int32 j = 0; j < dim; ++j)
            for (Int32 k = 0; k < dim; ++k)
                acc.setValue(origin.offsetBy(i, j, k), 3.0f);
    EXPECT_EQ(this->cacc.getValue(origin), 3.0f);
    ASSERT_NE(acc.probeLeaf(this->p), nullptr);
    tree.prune();
    EXPECT_EQ(tree.probeConstLeaf(this->p), nullptr);
    EXPECT_EQ(acc.probeLeaf(this->p), nullptr);
    EXPECT_EQ(acc.getValue(this->p), 3.0f);
    EXPECT_TRUE(this->cacc.isValueOn(origin.offsetBy(dim - 1)));
    // Writing into the tile splits it again.
    acc.setValue(this->p, 4.0f);
    EXPECT_EQ(tree.getValue(this->p), 4.0f);
    EXPECT_EQ(this->cacc.getValue(origin), 3.0f);
    EXPECT_EQ(tree.activeVoxelCount(), Index64(dim) * dim * dim);
}

// A lone voxel's whole branch is freed when it is erased, through the tree or the accessor.
TYPED_TEST(ValueAccessorTyped, EraseOfLastVoxelFreesCachedBranch) {
    auto& tree = this->tree;
    auto& acc = this->acc;
    auto& cacc = this->cacc;
    const Coord p = this->p;
    const Coord sibling = p.offsetBy(-this->regionDim(0), 0, 0);  // next leaf, same parent
    for (int round = 0; round < 2; ++round) {
        SCOPED_TRACE(round == 0 ? "tree.eraseValue" : "acc.eraseValue");
        acc.setValue(p, 1.0f);
        EXPECT_EQ(cacc.getValue(p), 1.0f);
        EXPECT_EQ(cacc.getValue(sibling), this->kBackground);
        if (round == 0) {
            tree.eraseValue(p);
        } else {
            acc.eraseValue(p);
        }
        EXPECT_EQ(tree.leafCount(), 0u);
        EXPECT_TRUE(tree.empty());
        EXPECT_EQ(acc.getValue(p), this->kBackground);
        EXPECT_FALSE(cacc.isValueOn(p));
        EXPECT_EQ(cacc.getValue(sibling), this->kBackground);
        EXPECT_EQ(cacc.probeConstLeaf(p), nullptr);
        acc.setValueOn(sibling);
        EXPECT_TRUE(tree.isValueOn(sibling));
        EXPECT_EQ(cacc.getValue(sibling), this->kBackground);
        acc.eraseValue(sibling);
        EXPECT_EQ(tree.activeVoxelCount(), 0u);
    }
}

TYPED_TEST(ValueAccessorTyped, FillOverCachedNodesLeavesAccessorCorrect) {
    auto& tree = this->tree;
    auto& acc = this->acc;
    const Coord p = this->p;
    for (Index level = 0; level < 2; ++level) {
        SCOPED_TRACE(::testing::Message() << "a tile the size of a level-" << level << " node");
        acc.setValue(p, 1.0f);
        EXPECT_TRUE(this->cacc.isValueOn(p));
        const Int32 dim = this->regionDim(level);
        const CoordBBox box =
            CoordBBox::createCube(p.alignedDown(TypeParam::shape().regionLog2(level)), dim);
        tree.fill(box, 5.0f + float(level), false);
        EXPECT_EQ(acc.getValue(p), 5.0f + float(level));
        EXPECT_FALSE(acc.isValueOn(p));
        EXPECT_EQ(this->cacc.getValue(box.max()), 5.0f + float(level));
        EXPECT_EQ(acc.probeLeaf(p), nullptr);
        EXPECT_EQ(tree.activeVoxelCount(), 0u);
    }
}

TYPED_TEST(ValueAccessorTyped, AssignmentOfTreeDropsCachedNodes) {
    using TreeT = typename TestFixture::TreeT;
    const Coord p = this->p;
    TreeT other(this->kBackground);
    other.setValue(p, 9.0f);
    this->acc.setValue(p, 1.0f);
    this->acc.setValue(p.offsetBy(1), 1.0f);
    EXPECT_EQ(this->cacc.getValue(p), 1.0f);
    this->tree = other;
    EXPECT_EQ(this->acc.getValue(p), 9.0f);
    EXPECT_EQ(this->cacc.getValue(p.offsetBy(1)), this->kBackground);
    this->acc.setValue(p, 4.0f);
    EXPECT_EQ(this->tree.getValue(p), 4.0f);
    EXPECT_EQ(other.getValue(p), 9.0f);  // the copy is deep
}

TYPED_TEST(ValueAccessorTyped, IsCachedHoldsForTheNodesOfTheLastAccess) {
    auto& acc = this->acc;
    const Coord p = this->p;
    EXPECT_FALSE(acc.isCached(p));
    acc.setValue(p, 1.0f);
    EXPECT_TRUE(acc.isCached(p));
    EXPECT_TRUE(acc.isCached(p.alignedDown(TypeParam::shape().leafLog2())));
    // A voxel of the next leaf shares the cached parent.
    EXPECT_TRUE(acc.isCached(p.offsetBy(-this->regionDim(0), 0, 0)));
    // A voxel in another branch below the top shares nothing.
    const Index top = TypeParam::shape().topLevel();
    const Coord far = p.offsetBy(this->regionDim(top - 1), 0, 0);
    EXPECT_FALSE(acc.isCached(far));
    acc.clear();
    EXPECT_FALSE(acc.isCached(p));
    EXPECT_EQ(acc.getValue(p), 1.0f);
    EXPECT_TRUE(acc.isCached(p));
}

// An empty cache must not match any coordinate, including those of the node at the INT32_MAX
// corner (outside a bounded tree's domain, inside an unbounded tree's).
TYPED_TEST(ValueAccessorTyped, EmptyCacheMatchesNoCoordinateNotEvenTheMaxCorner) {
    using TreeT = typename TestFixture::TreeT;
    constexpr Int32 hi = std::numeric_limits<Int32>::max();
    const float bg = this->kBackground;
    const Coord corner(hi), nearCorner(hi - 1, hi - 2, hi - 3);
    EXPECT_FALSE(this->acc.isCached(corner));
    EXPECT_FALSE(this->cacc.isCached(nearCorner));
    EXPECT_EQ(this->acc.getValue(corner), bg);
    EXPECT_FALSE(this->cacc.isValueOn(nearCorner));
    float value = 0;
    EXPECT_FALSE(this->cacc.probeValue(corner, value));
    EXPECT_EQ(value, bg);
    EXPECT_EQ(this->cacc.probeConstLeaf(corner), nullptr);
    if constexpr (!TreeT::BOUNDED) {
        this->acc.setValue(nearCorner, 1.0f);
        EXPECT_EQ(this->tree.getValue(nearCorner), 1.0f);
        this->acc.clear();
        EXPECT_EQ(this->acc.getValue(corner), bg);
        EXPECT_EQ(this->acc.getValue(nearCorner), 1.0f);
        this->tree.clear();
        EXPECT_EQ(this->cacc.getValue(nearCorner), bg);
        EXPECT_EQ(this->acc.getValue(corner), bg);
    }
}

// Every accessor stays correct while prune(), clear(), fill() and eraseValue() free nodes
// between its calls at a high rate.
TYPED_TEST(ValueAccessorTyped, StructuralChurnKeepsLongLivedAccessorsCorrect) {
    using TreeT = typename TestFixture::TreeT;
    test::WorkloadOptions options;
    options.seed = 4242;
    options.batches = 4;
    options.opsPerBatch = 5000;
    options.pruneOrClearRate = 0.02;
    options.clusterRadius = 6;
    options.checkInactiveValues = false;
    test::TreeModelDriver<TreeT, typename TestFixture::Accessor,
                          typename TestFixture::ConstAccessor>
        driver(this->tree, TypeParam::shape(), options, {this->kBackground, 1.0f, 2.0f});
    EXPECT_TRUE(driver.run());
}

TYPED_TEST(ValueAccessorTyped, ReadOnlyAccessorOffersNoWrites) {
    using ConstAccessor = typename TestFixture::ConstAccessor;
    using Accessor = typename TestFixture::Accessor;
    constexpr bool constWrites = requires(ConstAccessor a) {
        a.setValue(Coord(), 1.0f);
    };
    constexpr bool constTouch = requires(ConstAccessor a) {
        a.touchLeaf(Coord());
    };
    constexpr bool constErase = requires(ConstAccessor a) {
        a.eraseValue(Coord());
    };
    constexpr bool writes = requires(Accessor a) {
        a.setValue(Coord(), 1.0f);
    };
    EXPECT_FALSE(constWrites);
    EXPECT_FALSE(constTouch);
    EXPECT_FALSE(constErase);
    EXPECT_TRUE(writes);
    EXPECT_EQ(&this->cacc.tree(), &this->tree);
}

// Several threads, each with its own accessors, read one tree at the same time and all agree
// with the model; so do concurrent iterations.
TYPED_TEST(ValueAccessorTyped, ConcurrentReadersWithOwnAccessorsAgreeWithModel) {
    using TreeT = typename TestFixture::TreeT;
    test::WorkloadOptions options;
    options.seed = 99;
    options.batches = 2;
    options.opsPerBatch = 20000;
    options.checkInactiveValues = false;
    options.checkCopy = false;
    options.pruneOrClearRate = 1e-4;
    test::TreeModelDriver<TreeT, typename TestFixture::Accessor,
                          typename TestFixture::ConstAccessor>
        driver(this->tree, TypeParam::shape(), options, {this->kBackground, 1.0f, 2.0f, 3.0f});
    ASSERT_TRUE(driver.run());
    const test::SparseVolumeModel<float>& model = driver.model();
    std::vector<std::pair<Coord, std::pair<float, bool>>> voxels;
    model.forEach([&](const Coord& ijk, float value, bool active) {
        voxels.push_back({ijk, {value, active}});
    });
    // Untouched neighbours of stored voxels read as background.
    const size_t stored = voxels.size();
    for (size_t n = 0; n < stored; n += 3) {
        const Coord ijk = voxels[n].first.offsetBy(0, 0, 1);
        float value;
        const bool on = model.probeValue(ijk, value);
        voxels.push_back({ijk, {value, on}});
    }

    constexpr int kThreads = 4;
    std::atomic<int> mismatches{0};
    std::vector<Coord> firstMismatch(kThreads, Coord::max());
    std::vector<Index64> activeCounts(kThreads, 0);
    const TreeT& tree = this->tree;
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            typename TestFixture::ConstAccessor cacc(tree);
            typename TestFixture::Accessor acc(this->tree);  // used for reads only
            std::mt19937 rng(t);
            // Each thread walks the list from its own start, so caches differ between threads.
            const size_t start = rng() % voxels.size();
            for (size_t n = 0; n < voxels.size(); ++n) {
                const auto& [ijk, expected] = voxels[(start + n) % voxels.size()];
                float a, b;
                const bool aOn = cacc.probeValue(ijk, a);
                const bool bOn = acc.probeValue(ijk, b);
                if (a != expected.first || b != expected.first || aOn != expected.second ||
                    bOn != expected.second || acc.getValue(ijk) != expected.first) {
                    if (firstMismatch[t] == Coord::max())
                        firstMismatch[t] = ijk;
                    ++mismatches;
                }
            }
            for (auto it = tree.cbeginValueOn(); it; ++it) {
                CoordBBox bbox;
                it.getBoundingBox(bbox);
                activeCounts[t] += bbox.volume();
            }
        });
    }
    for (auto& thread : threads)
        thread.join();
    EXPECT_EQ(mismatches.load(), 0);
    for (int t = 0; t < kThreads; ++t) {
        EXPECT_EQ(activeCounts[t], model.activeVoxelCount()) << "thread " << t;
        EXPECT_EQ(firstMismatch[t], Coord::max()) << "thread " << t;
    }
}

}  // namespace
}  // namespace vdb
