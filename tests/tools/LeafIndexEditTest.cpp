// SPDX-License-Identifier: Apache-2.0
// The leaf index under the tools' edits: each tool runs, threaded, on a grid whose tree has a
// current leaf index and on an index-free copy of the same grid. The oracle is that copy:
// afterwards every read of the indexed tree (top-down, accessor, leaf probe) must equal the
// copy's, and whatever index the tree still has must list only leaves it holds at their
// origins (test::checkLeafIndex). Edits that free or move nodes must retire the index.

#include <vdb/Grid.h>
#include <vdb/tools/ChangeBackground.h>
#include <vdb/tools/Composite.h>
#include <vdb/tools/Filter.h>
#include <vdb/tools/LevelSetFilter.h>
#include <vdb/tools/LevelSetSphere.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/SignedFloodFill.h>
#include <vdb/tree/ValueAccessor.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <string>
#include <vector>

namespace vdb {
namespace {

FloatGrid::Ptr sphere(float radius, const Vec3f& centre) {
    return tools::createLevelSetSphere<FloatGrid>(radius, centre, 1.0f, 3.0f);
}

// Every read of `indexed` equals the same read of `plain`: all voxels of both trees' leaves and
// their neighbours, and random coordinates around them.
::testing::AssertionResult sameReads(const FloatTree& indexed, const FloatTree& plain) {
    if (auto r = test::checkLeafIndex(indexed); !r)
        return r;
    if (indexed.activeVoxelCount() != plain.activeVoxelCount() ||
        indexed.leafCount() != plain.leafCount())
        return ::testing::AssertionFailure()
               << indexed.activeVoxelCount() << " active voxels in " << indexed.leafCount()
               << " leaves, expected " << plain.activeVoxelCount() << " in " << plain.leafCount();
    FloatTree::ConstAccessor acc(indexed);
    const auto check = [&](const Coord& ijk) -> ::testing::AssertionResult {
        float a, b;
        const bool onA = indexed.probeValue(ijk, a), onB = plain.probeValue(ijk, b);
        if (!test::sameBits(a, b) || onA != onB || !test::sameBits(acc.getValue(ijk), b) ||
            acc.isValueOn(ijk) != onB ||
            (indexed.probeConstLeaf(ijk) != nullptr) != (plain.probeConstLeaf(ijk) != nullptr))
            return ::testing::AssertionFailure() << "reads differ at " << ijk;
        return ::testing::AssertionSuccess();
    };
    for (const FloatTree* tree : {&indexed, &plain})
        for (auto leaf = tree->cbeginLeaf(); leaf; ++leaf)
            for (Index n = 0; n < FloatTree::LeafNodeType::NUM_VALUES; n += 3)
                if (auto r = check(leaf->offsetToGlobalCoord(n).offsetBy(n % 2 ? 8 : 0, 0, 0)); !r)
                    return r;
    std::mt19937 rng(5);
    for (int n = 0; n < 20000; ++n)
        if (auto r = check(
                Coord(Int32(rng() % 120) - 60, Int32(rng() % 120) - 60, Int32(rng() % 120) - 60));
            !r)
            return r;
    return ::testing::AssertionSuccess();
}

struct Edit {
    std::string name;
    bool frees;  // the edit frees or takes out nodes, so the index must be retired
    std::function<void(FloatGrid&)> apply;
};

std::vector<Edit> edits() {
    const auto other = [] { return sphere(15.0f, Vec3f(12.0f, 3.0f, -4.0f)); };
    return {
        {"csgUnion", true, [other](FloatGrid& g) { tools::csgUnion(g, *other()); }},
        {"csgIntersection", true, [other](FloatGrid& g) { tools::csgIntersection(g, *other()); }},
        {"csgDifference", true, [other](FloatGrid& g) { tools::csgDifference(g, *other()); }},
        {"csgUnionCopy (inputs untouched)", false,
         [other](FloatGrid& g) { (void)tools::csgUnionCopy(g, *other()); }},
        {"csgDifferenceCopy (inputs untouched)", false,
         [other](FloatGrid& g) { (void)tools::csgDifferenceCopy(g, *other()); }},
        {"dilateActiveValues", false,
         [](FloatGrid& g) { tools::dilateActiveValues(g.tree(), 2, tools::NN_FACE_EDGE); }},
        {"erodeActiveValues", false,
         [](FloatGrid& g) { tools::erodeActiveValues(g.tree(), 2, tools::NN_FACE); }},
        {"prune (every leaf active and within the tolerance)", true,
         [](FloatGrid& g) {
             for (auto& leaf : g.tree().leaves())
                 leaf.getValueMask().set(true);
             tools::prune(g.tree(), 100.0f);
         }},
        {"pruneLevelSet", false,
         [](FloatGrid& g) {
             tools::erodeActiveValues(g.tree(), 1);
             tools::pruneLevelSet(g.tree());
         }},
        {"signedFloodFill", false, [](FloatGrid& g) { tools::signedFloodFill(g.tree()); }},
        {"changeLevelSetBackground", false,
         [](FloatGrid& g) { tools::changeLevelSetBackground(g.tree(), 2.5f); }},
        {"Filter::gaussian", false, [](FloatGrid& g) { tools::Filter<FloatGrid>(g).gaussian(1); }},
        {"LevelSetFilter::offset", false,
         [](FloatGrid& g) { tools::LevelSetFilter<FloatGrid>(g).offset(1.5f); }},
    };
}

TEST(LeafIndexEdits, EveryToolLeavesReadsRightAndRetiresTheIndexWhenItFreesNodes) {
    for (const Edit& edit : edits()) {
        SCOPED_TRACE(edit.name);
        const auto original = sphere(20.0f, Vec3f(0.0f));
        FloatGrid::Ptr indexed = original->deepCopy();
        FloatGrid::Ptr plain = original->deepCopy();
        indexed->tree().buildLeafIndex();
        FloatTree::Accessor acc(indexed->tree());  // lives across the edit
        (void)acc.getValue(Coord(20, 0, 0));
        edit.apply(*indexed);
        edit.apply(*plain);
        ASSERT_FALSE(plain->tree().hasLeafIndex());
        if (edit.frees) {
            EXPECT_FALSE(indexed->tree().hasLeafIndex());
        }
        EXPECT_TRUE(
            test::sameBits(acc.getValue(Coord(20, 0, 0)), plain->tree().getValue(Coord(20, 0, 0))));
        EXPECT_TRUE(sameReads(indexed->tree(), plain->tree()));
        // Rebuilt after the edit, it serves the result.
        indexed->tree().buildLeafIndex();
        EXPECT_TRUE(sameReads(indexed->tree(), plain->tree()));
    }
}

// Iterated edits with the index rebuilt between some of them and not others, so that each
// edit meets a current index, a retired one, or one that misses leaves added since.
TEST(LeafIndexEdits, AlternatingEditsAndRebuilds) {
    const auto all = edits();
    std::mt19937 rng(12);
    FloatGrid::Ptr indexed = sphere(18.0f, Vec3f(1.0f, 2.0f, 3.0f));
    FloatGrid::Ptr plain = indexed->deepCopy();
    for (int step = 0; step < 24; ++step) {
        const Edit& edit = all[rng() % all.size()];
        SCOPED_TRACE(std::to_string(step) + ": " + edit.name);
        if (rng() % 3 != 0)
            indexed->tree().buildLeafIndex();
        edit.apply(*indexed);
        edit.apply(*plain);
        ASSERT_TRUE(sameReads(indexed->tree(), plain->tree()));
    }
}

}  // namespace
}  // namespace vdb
