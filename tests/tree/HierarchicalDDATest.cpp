// SPDX-License-Identifier: Apache-2.0
// Oracle: every leaf and every active tile of the tree slab-tested against the ray one by one
// (no walk, RayOracle.h), and top-down tree lookups at the middle of each reported span.

#include <vdb/tree/HierarchicalDDA.h>
#include <vdb/tree/TreeConfigs.h>
#include <vdb/vdb.h>

#include <Oracles.h>
#include <RayOracle.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <vector>

namespace vdb::tree {
namespace {

using RayD = math::Ray<double>;
using test::rayCubeOverlap;

// ---- Hierarchical DDA over trees

// A scene with leaves in clusters (some at negative coordinates), active and inactive tiles at
// several levels, and isolated voxels.
template <typename TreeT>
void buildScene(TreeT& tree, uint32_t seed) {
    std::mt19937 rng(seed);
    const Coord centers[] = {Coord(0), Coord(-300, -260, -310), Coord(200, -90, 40),
                             Coord(-37, 150, 260)};
    std::uniform_int_distribution<int> off(-20, 20);
    for (const Coord& c : centers)
        for (int n = 0; n < 600; ++n)
            tree.setValue(c.offsetBy(off(rng), off(rng), off(rng)), float(n % 7) - 3.0f);
    // Node-aligned fills become tiles at various levels; a partial fill makes leaves too.
    tree.fill(CoordBBox(Coord(-256), Coord(-129)), 2.0f, true);
    tree.fill(CoordBBox(Coord(64, 64, -64), Coord(71, 71, -57)), 4.0f, true);
    tree.fill(CoordBBox(Coord(128, 0, 0), Coord(255, 127, 127)), -1.0f, false);
    tree.fill(CoordBBox(Coord(-100, 90, 90), Coord(-61, 140, 101)), 5.0f, true);
}

template <typename TreeT>
class HierarchicalDDATest : public ::testing::Test {};
using DDATrees = ::testing::Types<tree::HashTree543<float>, tree::MapTree432<float>,
                                  tree::FixedTree6543<float>, tree::FixedTree643<float>,
                                  tree::FixedTree6545<float>, tree::FixedTree3333<float>>;
TYPED_TEST_SUITE(HierarchicalDDATest, DDATrees);

// With `merged`, the walker merges runs of equal tiles: a tile span then covers one or more
// cells, so instead of its cube the value is checked at several points along it.
template <typename TreeT>
::testing::AssertionResult checkWalk(const TreeT& tree, const RayD& ray, double t0, double t1,
                                     bool merged = false, size_t* spanCount = nullptr) {
    using LeafT = typename TreeT::LeafNodeType;
    HierarchicalDDA<TreeT> hdda(tree, merged);
    std::vector<typename HierarchicalDDA<TreeT>::Span> spans;
    if (hdda.init(ray, t0, t1)) {
        typename HierarchicalDDA<TreeT>::Span s;
        while (hdda.next(s))
            spans.push_back(s);
    }
    // Spans are contiguous, ordered and inside [t0, t1].
    for (size_t i = 0; i < spans.size(); ++i) {
        const auto& s = spans[i];
        if (!(s.t0 <= s.t1) || s.t0 < t0 - 1e-9 || s.t1 > t1 + 1e-9)
            return ::testing::AssertionFailure()
                   << "span " << i << " times " << s.t0 << ' ' << s.t1;
        if (i > 0 && s.t0 != spans[i - 1].t1)
            return ::testing::AssertionFailure() << "gap before span " << i;
    }
    if (spanCount)
        *spanCount = spans.size();
    // Each span agrees with a top-down lookup at its middle.
    std::set<const LeafT*> visited;
    for (const auto& s : spans) {
        if (s.leaf)
            visited.insert(s.leaf);
        if (s.t1 - s.t0 < 1e-6)
            continue;
        if (merged && !s.leaf) {
            for (double f : {0.01, 0.25, 0.5, 0.75, 0.99}) {
                const Coord ijk = floorToCoord(ray(s.t0 + f * (s.t1 - s.t0)));
                if (tree.probeConstLeaf(ijk) || s.value != tree.getValue(ijk) ||
                    s.active != tree.isValueOn(ijk))
                    return ::testing::AssertionFailure() << "merged tile span wrong at " << ijk;
            }
            continue;
        }
        const Coord ijk = floorToCoord(ray(0.5 * (s.t0 + s.t1)));
        if (!CoordBBox::createCube(s.origin, Int32(1) << s.log2Dim).isInside(ijk))
            return ::testing::AssertionFailure() << "span cube " << s.origin << " misses " << ijk;
        if (s.leaf != tree.probeConstLeaf(ijk))
            return ::testing::AssertionFailure() << "wrong leaf at " << ijk;
        if (!s.leaf && (s.value != tree.getValue(ijk) || s.active != tree.isValueOn(ijk)))
            return ::testing::AssertionFailure() << "wrong tile value or state at " << ijk;
        if (s.leaf && s.log2Dim != LeafT::LOG2DIM)
            return ::testing::AssertionFailure() << "a leaf span of the wrong size";
    }
    // Oracle: every leaf crossed for a positive length is visited; every visited leaf is at
    // least touched.
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        double a, b;
        const bool hit = rayCubeOverlap(ray, t0, t1, it->origin(), LeafT::DIM, a, b);
        const bool inside = rayCubeOverlap(ray, t0, t1, it->origin(), LeafT::DIM, a, b, 1e-7);
        if (inside && b - a > 1e-7 && !visited.count(&*it))
            return ::testing::AssertionFailure() << "skipped leaf " << it->origin();
        if (!hit && visited.count(&*it))
            return ::testing::AssertionFailure()
                   << "visited leaf " << it->origin() << " off the ray";
    }
    // Oracle: every active tile crossed is reported as that tile's value, active.
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        if (!it.isTileValue())
            continue;
        CoordBBox box;
        it.getBoundingBox(box);
        double a, b;
        if (!rayCubeOverlap(ray, t0, t1, box.min(), box.dim()[0], a, b, 1e-7) || b - a < 1e-6)
            continue;
        const double tm = 0.5 * (a + b);
        const auto s = std::find_if(spans.begin(), spans.end(),
                                    [&](const auto& sp) { return sp.t0 <= tm && tm <= sp.t1; });
        if (s == spans.end() || s->leaf || !s->active || s->value != *it)
            return ::testing::AssertionFailure() << "active tile " << box << " not reported";
    }
    return ::testing::AssertionSuccess();
}

TYPED_TEST(HierarchicalDDATest, VisitsEveryLeafAndTileTheRayCrosses) {
    using TreeT = TypeParam;
    TreeT tree(0.0f);
    buildScene(tree, 2013);
    const Vec3d targets[] = {
        Vec3d(0.5),    Vec3d(-300.2, -260.7, -310.1), Vec3d(200, -90, 40), Vec3d(-37, 150, 260),
        Vec3d(-190.0), Vec3d(67.5, 67.5, -60.5),      Vec3d(190, 60, 60),  Vec3d(-80, 115, 95)};
    std::vector<std::pair<RayD, double>> rays;  // ray, length
    // Along each axis, both ways, through every target, on voxel centres and on voxel faces.
    for (const Vec3d& t : targets)
        for (int axis = 0; axis < 3; ++axis)
            for (double sign : {1.0, -1.0})
                for (double shift : {0.0, 0.5}) {
                    Vec3d d(0.0);
                    d[axis] = sign;
                    Vec3d p = t + Vec3d(shift);
                    p[axis] = t[axis];
                    rays.emplace_back(RayD(p - d * 400.0, d), 800.0);
                }
    // Parallel to a pair of faces, and diagonal, negative directions included.
    for (const Vec3d& t : targets)
        for (const Vec3d& d : {Vec3d(1, 0.37, 0), Vec3d(0, -1, -1), Vec3d(-0.2, 0, 1),
                               Vec3d(-1, -1, -1), Vec3d(1, -1, 0.5)}) {
            rays.emplace_back(RayD(t - d.unit() * 300.0, d.unit()), 600.0);
        }
    // Starting inside the scene (inside leaves and tiles), and random rays aimed at targets.
    std::mt19937 rng(99);
    std::uniform_real_distribution<double> u(-1.0, 1.0), far(-700.0, 700.0), jitter(-15.0, 15.0);
    const int n = test::scaledBatchCount(60);
    for (int i = 0; i < n; ++i) {
        const Vec3d t = targets[size_t(i) % std::size(targets)];
        Vec3d d(u(rng), u(rng), u(rng));
        if (d.length() < 1e-3)
            continue;
        d = d.unit();
        rays.emplace_back(RayD(t + Vec3d(jitter(rng), jitter(rng), jitter(rng)), d), 500.0);
        const Vec3d eye(far(rng), far(rng), far(rng));
        const Vec3d aim = t + Vec3d(jitter(rng), jitter(rng), jitter(rng)) - eye;
        rays.emplace_back(RayD(eye, aim.unit()), 2.0 * aim.length());
    }
    size_t each = 0, merged = 0;
    for (const auto& [ray, length] : rays) {
        size_t n = 0, m = 0;
        ASSERT_TRUE(checkWalk(tree, ray, 0.0, length, false, &n)) << ray;
        ASSERT_TRUE(checkWalk(tree, ray, 0.0, length, true, &m)) << ray << " (tiles merged)";
        EXPECT_LE(m, n) << ray;
        each += n;
        merged += m;
    }
    // The scene's large constant regions are crossed in fewer spans when tiles are merged.
    EXPECT_LT(merged, each);
}

TYPED_TEST(HierarchicalDDATest, LeapsOverEmptySpaceInFewSteps) {
    using TreeT = TypeParam;
    TreeT tree(0.0f);
    tree.setValue(Coord(-1000, 3, 3), 1.0f);
    tree.setValue(Coord(1000, 3, 3), 1.0f);
    HierarchicalDDA<TreeT> hdda(tree);
    const RayD ray(Vec3d(-1100, 3.5, 3.5), Vec3d(1, 0, 0));
    ASSERT_TRUE(hdda.init(ray, 0.0, 2200.0));
    typename HierarchicalDDA<TreeT>::Span s;
    int spans = 0, leaves = 0;
    while (hdda.next(s)) {
        ++spans;
        leaves += s.leaf != nullptr;
    }
    EXPECT_EQ(leaves, 2);
    // 2000 voxels of empty space: a voxel walk would take 2000 steps.
    EXPECT_LT(spans, 100);
}

TEST(HierarchicalDDA, EmptyTreeAndMissingRaysGiveNoSpans) {
    FloatTree tree(0.0f);
    HierarchicalDDA<FloatTree> empty(tree);
    EXPECT_FALSE(empty.init(RayD(Vec3d(0.0), Vec3d(1, 0, 0)), 0.0, 100.0));
    tree.setValue(Coord(5, 5, 5), 1.0f);
    HierarchicalDDA<FloatTree> hdda(tree);
    EXPECT_FALSE(hdda.init(RayD(Vec3d(0, 10000, 0), Vec3d(1, 0, 0)), 0.0, 100.0));
    EXPECT_FALSE(hdda.init(RayD(Vec3d(-10000, 5, 5), Vec3d(-1, 0, 0)), 0.0, 1e6));
    ASSERT_TRUE(hdda.init(RayD(Vec3d(-10000, 5.5, 5.5), Vec3d(1, 0, 0)), 0.0, 1e6));
}

}  // namespace
}  // namespace vdb::tree
