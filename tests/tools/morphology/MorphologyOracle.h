// SPDX-License-Identifier: Apache-2.0
/// @file
/// Brute-force morphology on plain coordinate sets for the morphology tests: one neighbour
/// offset at a time over std::unordered_set<Coord>, with each tile policy written out as a
/// rule on sets (see tools/Morphology.h). Shares nothing with the library but Coord.
///
/// Also: snapshots of a tree's active voxels and tiles read through its public iterators,
/// and comparisons of a tree with an expected active set, expected values and the structural
/// promises of each policy.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tools/Morphology.h>

#include <Oracles.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <type_traits>
#include <unordered_set>
#include <utility>
#include <vector>

namespace vdb::test::morph {

using CoordSet = std::unordered_set<Coord, CoordHash, CoordEqual>;

/// The offsets of the neighbours of a voxel: 6 faces, then 12 edges, then 8 corners.
inline std::vector<Coord> neighbourOffsets(tools::NearestNeighbors nn) {
    std::vector<Coord> result;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) {
                const int nonzero = (x != 0) + (y != 0) + (z != 0);
                if (nonzero == 0)
                    continue;
                if (nonzero <= 1 || (nonzero == 2 && nn != tools::NN_FACE) ||
                    (nonzero == 3 && nn == tools::NN_FACE_EDGE_VERTEX))
                    result.emplace_back(x, y, z);
            }
    return result;
}

/// `ijk + d` when it stays inside `domain` (computed in 64 bits: no wrap-around).
inline bool stepInside(const Coord& ijk, const Coord& d, const CoordBBox& domain, Coord& out) {
    const Int64 x = Int64(ijk[0]) + d[0], y = Int64(ijk[1]) + d[1], z = Int64(ijk[2]) + d[2];
    if (x < domain.min()[0] || x > domain.max()[0] || y < domain.min()[1] || y > domain.max()[1] ||
        z < domain.min()[2] || z > domain.max()[2])
        return false;
    out = Coord(Int32(x), Int32(y), Int32(z));
    return true;
}

/// `iterations` steps of dilation: each step adds every neighbour (inside `domain`) of every
/// member. Only the members a step added can add new ones in the next step.
inline CoordSet dilateSet(CoordSet set, tools::NearestNeighbors nn, int iterations,
                          const CoordBBox& domain) {
    const std::vector<Coord> offsets = neighbourOffsets(nn);
    std::vector<Coord> frontier(set.begin(), set.end());
    for (int it = 0; it < iterations; ++it) {
        std::vector<Coord> added;
        for (const Coord& ijk : frontier) {
            for (const Coord& d : offsets) {
                Coord n;
                if (stepInside(ijk, d, domain, n) && set.insert(n).second)
                    added.push_back(n);
            }
        }
        frontier.swap(added);
    }
    return set;
}

/// `iterations` steps of erosion: each step removes every member with a neighbour that is
/// neither a member nor `alwaysOn(neighbour)` (voxels that never erode, e.g. ignored tiles).
/// Only the neighbours of what a step removed can be removed in the next step.
inline CoordSet erodeSet(CoordSet set, tools::NearestNeighbors nn, int iterations,
                         const std::function<bool(const Coord&)>& alwaysOn) {
    const std::vector<Coord> offsets = neighbourOffsets(nn);
    auto exposed = [&](const Coord& ijk) {
        for (const Coord& d : offsets) {
            Coord n;
            if (!stepInside(ijk, d, CoordBBox::inf(), n))
                return true;  // beyond the index space nothing is active
            if (!set.count(n) && !alwaysOn(n))
                return true;
        }
        return false;
    };
    std::vector<Coord> candidates(set.begin(), set.end());
    for (int it = 0; it < iterations; ++it) {
        std::vector<Coord> exposedMembers;
        for (const Coord& ijk : candidates)
            if (set.count(ijk) && exposed(ijk))
                exposedMembers.push_back(ijk);
        std::vector<Coord> removed;  // each once, though candidates repeat
        for (const Coord& ijk : exposedMembers)
            if (set.erase(ijk))
                removed.push_back(ijk);
        candidates.clear();
        for (const Coord& ijk : removed) {
            for (const Coord& d : offsets) {
                Coord n;
                if (stepInside(ijk, d, CoordBBox::inf(), n) && set.count(n))
                    candidates.push_back(n);
            }
        }
    }
    return set;
}

/// What a tree holds before an operation, read through its public iterators.
template <typename TreeT>
struct Snapshot {
    using ValueT = typename TreeT::ValueType;
    CoordSet leafVoxels;  // active voxels in leaves
    CoordSet tileVoxels;  // voxels of active tiles
    std::vector<std::pair<CoordBBox, ValueT>> tiles;

    explicit Snapshot(const TreeT& tree) {
        for (auto it = tree.cbeginValueOn(); it; ++it) {
            if (it.isVoxelValue()) {
                leafVoxels.insert(it.getCoord());
                continue;
            }
            CoordBBox box;
            it.getBoundingBox(box);
            tiles.emplace_back(box, it.getValue());
            for (Int32 x = box.min()[0]; x <= box.max()[0]; ++x)
                for (Int32 y = box.min()[1]; y <= box.max()[1]; ++y)
                    for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z)
                        tileVoxels.insert(Coord(x, y, z));
        }
    }
    CoordSet allActive() const {
        CoordSet all = leafVoxels;
        all.insert(tileVoxels.begin(), tileVoxels.end());
        return all;
    }
};

/// The active set the library must produce, by the rules of each tile policy.
template <typename TreeT>
CoordSet expectedActive(const Snapshot<TreeT>& before, bool dilate, tools::NearestNeighbors nn,
                        int iterations, tools::TilePolicy mode) {
    if (iterations <= 0)
        return before.allActive();
    const CoordBBox domain = TreeT::domain();
    if (dilate) {
        if (mode == tools::IGNORE_TILES) {
            CoordSet result = dilateSet(before.leafVoxels, nn, iterations, domain);
            result.insert(before.tileVoxels.begin(), before.tileVoxels.end());
            return result;
        }
        return dilateSet(before.allActive(), nn, iterations, domain);
    }
    if (mode == tools::IGNORE_TILES) {
        const CoordSet& tiles = before.tileVoxels;
        CoordSet result = erodeSet(before.leafVoxels, nn, iterations,
                                   [&](const Coord& ijk) { return tiles.count(ijk) > 0; });
        result.insert(tiles.begin(), tiles.end());
        return result;
    }
    return erodeSet(before.allActive(), nn, iterations, [](const Coord&) { return false; });
}

/// Compares the active voxels of `tree` (tiles expanded) with `expected`.
template <typename TreeT>
::testing::AssertionResult sameActiveSet(const TreeT& tree, const CoordSet& expected) {
    Index64 count = 0;
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        if (box.volume() > (Index64(1) << 22))
            return ::testing::AssertionFailure() << "unexpectedly large active tile " << box;
        for (Int32 x = box.min()[0]; x <= box.max()[0]; ++x)
            for (Int32 y = box.min()[1]; y <= box.max()[1]; ++y)
                for (Int32 z = box.min()[2]; z <= box.max()[2]; ++z) {
                    const Coord ijk(x, y, z);
                    if (!expected.count(ijk))
                        return ::testing::AssertionFailure()
                               << ijk << " is active but should not be"
                               << (it.isTileValue() ? " (in a tile)" : "");
                    ++count;
                }
    }
    if (count != expected.size()) {
        for (const Coord& ijk : expected)
            if (!tree.isValueOn(ijk))
                return ::testing::AssertionFailure()
                       << ijk << " should be active but is not (" << count << " active, "
                       << expected.size() << " expected)";
    }
    if (tree.activeVoxelCount() != expected.size())
        return ::testing::AssertionFailure() << "activeVoxelCount() " << tree.activeVoxelCount()
                                             << ", expected " << expected.size();
    return ::testing::AssertionSuccess();
}

/// The log2 edge and origin of every node below the top of `tree` (leaves included).
template <typename TreeT>
std::vector<std::pair<Index, Coord>> branchRegions(const TreeT& tree) {
    std::vector<std::pair<Index, Coord>> result;
    for (auto it = tree.cbeginNode(); it; ++it) {
        if (it.getLevel() + 1 == TreeT::DEPTH)
            continue;  // the top node
        CoordBBox box;
        it.getBoundingBox(box);
        Index log2 = 0;
        while ((Int64(1) << log2) < Int64(box.dim()[0]))
            ++log2;
        result.emplace_back(log2, box.min());
    }
    return result;
}

/// Checks values after an operation: every voxel of `before`'s and `after`'s leaves and every
/// voxel of `expected` holds the value `before` held, except inside the nodes of `before`
/// listed in `dead` (log2 edge, origin), which must hold the background.
template <typename TreeT>
::testing::AssertionResult valuesKept(const TreeT& before, const TreeT& after,
                                      const CoordSet& expected,
                                      const std::set<std::pair<Index, Coord>>& dead = {}) {
    using ValueT = typename TreeT::ValueType;
    typename TreeT::ConstAccessor was(before), now(after);
    std::set<Index> deadLevels;
    for (const auto& d : dead)
        deadLevels.insert(d.first);
    // Dead nodes are never smaller than a leaf, so a whole leaf region shares one answer.
    auto isDead = [&](const Coord& ijk) {
        for (Index log2 : deadLevels)
            if (dead.count({log2, ijk.alignedDown(log2)}))
                return true;
        return false;
    };
    auto fail = [&](const Coord& ijk, const ValueT& got, const ValueT& want, bool deadRegion) {
        return ::testing::AssertionFailure()
               << "value at " << ijk << " is " << got << ", expected " << want
               << (deadRegion ? " (background of a removed node)" : "");
    };
    const ValueT background = before.background();
    // Leaves of `after`: against `before`'s leaf there, or the one value `before` held there.
    for (auto leaf = after.cbeginLeaf(); leaf; ++leaf) {
        const bool deadLeaf = isDead(leaf->origin());
        const auto* old = was.probeConstLeaf(leaf->origin());
        const ValueT uniform = deadLeaf ? background : was.getValue(leaf->origin());
        for (Index n = 0; n < leaf->NUM_VALUES; ++n) {
            const ValueT want = deadLeaf || !old ? uniform : ValueT(old->getValue(n));
            if (!(leaf->getValue(n) == want))
                return fail(leaf->offsetToGlobalCoord(n), leaf->getValue(n), want, deadLeaf);
        }
    }
    // Leaves `after` no longer has: the one value `after` holds there.
    for (auto leaf = before.cbeginLeaf(); leaf; ++leaf) {
        if (now.probeConstLeaf(leaf->origin()))
            continue;
        const bool deadLeaf = isDead(leaf->origin());
        const ValueT got = now.getValue(leaf->origin());
        for (Index n = 0; n < leaf->NUM_VALUES; ++n) {
            const ValueT want = deadLeaf ? background : ValueT(leaf->getValue(n));
            if (!(got == want))
                return fail(leaf->offsetToGlobalCoord(n), got, want, deadLeaf);
        }
    }
    // Active voxels in tiles.
    for (const Coord& ijk : expected) {
        if (now.probeConstLeaf(ijk))
            continue;
        const bool deadVoxel = isDead(ijk);
        const ValueT want = deadVoxel ? background : was.getValue(ijk);
        if (!(now.getValue(ijk) == want))
            return fail(ijk, now.getValue(ijk), want, deadVoxel);
    }
    return ::testing::AssertionSuccess();
}

/// The nodes of `before` (below the top) that hold no voxel of `active`: PRESERVE_TILES
/// erosion replaces them by background.
template <typename TreeT>
std::set<std::pair<Index, Coord>> deadBranches(const TreeT& before, const CoordSet& active) {
    const auto regions = branchRegions(before);
    std::set<Index> levels;
    for (const auto& r : regions)
        levels.insert(r.first);
    std::set<std::pair<Index, Coord>> live;
    for (const Coord& ijk : active)
        for (Index log2 : levels)
            live.insert({log2, ijk.alignedDown(log2)});
    std::set<std::pair<Index, Coord>> dead;
    for (const auto& r : regions)
        if (!live.count(r))
            dead.insert(r);
    return dead;
}

/// The active tiles of a tree as (box, value) pairs, in iteration order.
template <typename TreeT>
std::vector<std::pair<CoordBBox, typename TreeT::ValueType>> activeTiles(const TreeT& tree) {
    std::vector<std::pair<CoordBBox, typename TreeT::ValueType>> tiles;
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        if (it.isVoxelValue())
            continue;
        CoordBBox box;
        it.getBoundingBox(box);
        tiles.emplace_back(box, it.getValue());
    }
    std::sort(tiles.begin(), tiles.end(), [](const auto& a, const auto& b) {
        return a.first.min() < b.first.min() ||
               (a.first.min() == b.first.min() && a.first.max() < b.first.max());
    });
    return tiles;
}

/// True when pruning `tree` would change nothing: no node is uniform.
template <typename TreeT>
::testing::AssertionResult isPruned(const TreeT& tree) {
    TreeT copy = tree;
    copy.prune();
    if (copy.leafCount() != tree.leafCount() || copy.nonLeafCount() != tree.nonLeafCount() ||
        copy.activeTileCount() != tree.activeTileCount())
        return ::testing::AssertionFailure()
               << "not pruned: " << tree.leafCount() << " leaves, " << tree.nonLeafCount()
               << " internal nodes, " << tree.activeTileCount()
               << " active tiles; pruned: " << copy.leafCount() << ", " << copy.nonLeafCount()
               << ", " << copy.activeTileCount();
    return ::testing::AssertionSuccess();
}

/// True when every node below the top holds an active value (so no leaf is empty).
template <typename TreeT>
::testing::AssertionResult noInactiveBranches(const TreeT& tree) {
    const auto regions = branchRegions(tree);
    std::set<Index> levels;
    for (const auto& r : regions)
        levels.insert(r.first);
    std::set<std::pair<Index, Coord>> live;
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        CoordBBox box;
        it.getBoundingBox(box);
        for (Index log2 : levels)
            if ((Int64(1) << log2) >= Int64(box.dim()[0]))
                live.insert({log2, box.min().alignedDown(log2)});
    }
    for (const auto& r : regions)
        if (!live.count(r))
            return ::testing::AssertionFailure() << "the node of edge 2^" << r.first << " at "
                                                 << r.second << " holds no active value";
    return ::testing::AssertionSuccess();
}

/// Compares two trees node for node: leaf origins, masks and values in iteration order,
/// active tiles, node and inactive-voxel counts.
template <typename TreeT>
::testing::AssertionResult identicalTrees(const TreeT& a, const TreeT& b) {
    if (a.leafCount() != b.leafCount() || a.nonLeafCount() != b.nonLeafCount())
        return ::testing::AssertionFailure()
               << "node counts differ: " << a.leafCount() << "/" << a.nonLeafCount() << " vs "
               << b.leafCount() << "/" << b.nonLeafCount();
    auto la = a.cbeginLeaf();
    auto lb = b.cbeginLeaf();
    for (; la && lb; ++la, ++lb) {
        if (la->origin() != lb->origin())
            return ::testing::AssertionFailure()
                   << "leaf " << la->origin() << " vs " << lb->origin();
        if (!(la->getValueMask() == lb->getValueMask()))
            return ::testing::AssertionFailure() << "masks differ in leaf " << la->origin();
        for (Index n = 0; n < la->NUM_VALUES; ++n)
            if (!(la->getValue(n) == lb->getValue(n)))
                return ::testing::AssertionFailure() << "values differ in leaf " << la->origin();
    }
    if (activeTiles(a) != activeTiles(b))
        return ::testing::AssertionFailure() << "active tiles differ";
    if (a.inactiveVoxelCount() != b.inactiveVoxelCount() ||
        a.activeVoxelCount() != b.activeVoxelCount())
        return ::testing::AssertionFailure() << "voxel counts differ";
    return ::testing::AssertionSuccess();
}

}  // namespace vdb::test::morph
