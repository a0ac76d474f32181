// SPDX-License-Identifier: Apache-2.0
/// @file
/// Independent brute-force models that tests compare the library against.
///
/// SparseVolumeModel is a sparse volume kept as one hash-map entry per voxel: no nodes, no
/// tiles, no bit tricks. It shares nothing with the tree but Coord and CoordBBox, so a bug in
/// the tree's offset arithmetic, tile handling or node deletion cannot hide in the model too.
///
/// Below it: TreeShape (node sizes of a configuration, written out by hand), comparisons of a
/// tree with a model through the tree's public API, and TreeModelDriver, which applies one
/// seeded random workload to both. The tree tests share them.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/AccessOps.h>
#include <vdb/tree/InternalNode.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

namespace vdb::test {

/// Bitwise equality: -0 and 0 differ, and so do the payloads of NaNs.
template <typename T>
bool sameBits(const T& a, const T& b) {
    if constexpr (std::is_same_v<T, bool>) {
        return a == b;
    } else {
        return std::memcmp(&a, &b, sizeof(T)) == 0;
    }
}

/// A well-mixed hash of a Coord for the models' hash maps (splitmix64 finalizer over all 96
/// bits), independent of Coord::hash().
struct CoordHash {
    size_t operator()(const Coord& ijk) const noexcept {
        uint64_t h = (uint64_t(uint32_t(ijk[0])) << 32) ^ uint32_t(ijk[1]);
        h ^= uint64_t(uint32_t(ijk[2])) * 0x9e3779b97f4a7c15ull;
        h ^= h >> 30;
        h *= 0xbf58476d1ce4e5b9ull;
        h ^= h >> 27;
        h *= 0x94d049bb133111ebull;
        h ^= h >> 31;
        return size_t(h);
    }
};

/// Coord equality for the models' hash maps, component by component.
struct CoordEqual {
    bool operator()(const Coord& a, const Coord& b) const noexcept {
        return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
    }
};

/// A sparse volume: every voxel of Z^3 has a value and an active state, background and
/// inactive unless written.
///
/// Only voxels that differ from "inactive background" are stored, so two models are equal
/// exactly when they are observably equal. Every write mirrors the tree method of the same
/// name; eraseValue() makes one voxel inactive background, and fill() writes the box voxel by
/// voxel (keep boxes to a few hundred thousand voxels).
///
/// Given the log2 edges of a tree's node regions (`nodeLog2`, leaf first: {3, 7, 12} for the
/// standard 5-4-3 tree), the model also counts what each node region holds, so that tests can
/// tell which nodes the tree must have freed.
///
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <typename ValueT>
class SparseVolumeModel {
public:
    struct Voxel {
        ValueT value;
        bool active;
    };

    explicit SparseVolumeModel(const ValueT& background, std::vector<Index> nodeLog2 = {})
        : mBackground(background), mNodeLog2(std::move(nodeLog2)), mRegions(mNodeLog2.size()) {}

    const ValueT& background() const { return mBackground; }

    // ---- Reads
    ValueT getValue(const Coord& ijk) const {
        const auto it = mVoxels.find(ijk);
        return it == mVoxels.end() ? mBackground : it->second.value;
    }
    bool isValueOn(const Coord& ijk) const {
        const auto it = mVoxels.find(ijk);
        return it != mVoxels.end() && it->second.active;
    }
    bool probeValue(const Coord& ijk, ValueT& value) const {
        const auto it = mVoxels.find(ijk);
        if (it == mVoxels.end()) {
            value = mBackground;
            return false;
        }
        value = it->second.value;
        return it->second.active;
    }

    // ---- Writes, named after the tree's
    void setValue(const Coord& ijk, const ValueT& value) { store(ijk, value, true); }
    void setValueOn(const Coord& ijk) { store(ijk, getValue(ijk), true); }
    void setValueOn(const Coord& ijk, const ValueT& value) { store(ijk, value, true); }
    void setValueOff(const Coord& ijk) { store(ijk, getValue(ijk), false); }
    void setValueOff(const Coord& ijk, const ValueT& value) { store(ijk, value, false); }
    void setValueOnly(const Coord& ijk, const ValueT& value) { store(ijk, value, isValueOn(ijk)); }
    void setActiveState(const Coord& ijk, bool on) { store(ijk, getValue(ijk), on); }
    /// The voxel becomes inactive background; no other voxel changes.
    void eraseValue(const Coord& ijk) { store(ijk, mBackground, false); }

    /// Sets every voxel of `bbox` to `value` and `active`. Cost: one hash update per voxel.
    void fill(const CoordBBox& bbox, const ValueT& value, bool active) {
        if (bbox.empty())
            return;
        for (Int64 x = bbox.min()[0]; x <= bbox.max()[0]; ++x) {
            for (Int64 y = bbox.min()[1]; y <= bbox.max()[1]; ++y) {
                for (Int64 z = bbox.min()[2]; z <= bbox.max()[2]; ++z) {
                    store(Coord(Int32(x), Int32(y), Int32(z)), value, active);
                }
            }
        }
    }

    /// Pruning with tolerance zero replaces nodes by tiles of the same value and state: no
    /// voxel changes. (A nonzero tolerance has no voxel-exact model.)
    void prune() {}

    void clear() {
        mVoxels.clear();
        for (auto& level : mRegions)
            level.clear();
        mActiveCount = 0;
    }

    // ---- Whole-volume queries
    Index64 activeVoxelCount() const { return mActiveCount; }
    /// Number of stored voxels (those that are active or hold a non-background value).
    size_t size() const { return mVoxels.size(); }
    bool empty() const { return mVoxels.empty(); }

    /// Calls fn(ijk, value, active) for every stored voxel, in no particular order.
    template <typename Fn>
    void forEach(Fn&& fn) const {
        for (const auto& [ijk, voxel] : mVoxels)
            fn(ijk, voxel.value, voxel.active);
    }

    /// The coordinates of the active voxels in increasing Coord order.
    std::vector<Coord> sortedActiveVoxels() const {
        std::vector<Coord> result;
        result.reserve(size_t(mActiveCount));
        for (const auto& [ijk, voxel] : mVoxels) {
            if (voxel.active)
                result.push_back(ijk);
        }
        std::sort(result.begin(), result.end());
        return result;
    }

    /// The smallest box holding every active voxel; empty when there is none.
    CoordBBox activeBoundingBox() const {
        CoordBBox bbox;
        for (const auto& [ijk, voxel] : mVoxels) {
            if (voxel.active)
                bbox.expand(ijk);
        }
        return bbox;
    }

    /// Number of active voxels in the region of the level-`level` node holding `ijk`.
    /// @pre level < nodeLog2.size()
    Index64 activeVoxelsInNode(size_t level, const Coord& ijk) const {
        return regionStats(level, ijk).active;
    }
    /// Number of stored voxels (active, or inactive and not background) in that region.
    Index64 storedVoxelsInNode(size_t level, const Coord& ijk) const {
        const RegionStats stats = regionStats(level, ijk);
        return stats.active + stats.held;
    }

private:
    // What a voxel counts as in the per-region statistics.
    enum class Kind { Absent, Active, Held };

    struct RegionStats {
        Index64 active = 0;  // active voxels in the region
        Index64 held = 0;    // inactive voxels holding a non-background value
    };

    Kind kindOf(const ValueT& value, bool active) const {
        if (active)
            return Kind::Active;
        return value == mBackground ? Kind::Absent : Kind::Held;
    }

    RegionStats regionStats(size_t level, const Coord& ijk) const {
        const auto& map = mRegions[level];
        const auto it = map.find(ijk.alignedDown(mNodeLog2[level]));
        return it == map.end() ? RegionStats{} : it->second;
    }

    void count(const Coord& ijk, Kind kind, int delta) {
        if (kind == Kind::Absent)
            return;
        for (size_t level = 0; level < mNodeLog2.size(); ++level) {
            const Coord origin = ijk.alignedDown(mNodeLog2[level]);
            RegionStats& stats = mRegions[level][origin];
            Index64& n = kind == Kind::Active ? stats.active : stats.held;
            n = Index64(Int64(n) + delta);
            if (stats.active == 0 && stats.held == 0)
                mRegions[level].erase(origin);
        }
    }

    void store(const Coord& ijk, const ValueT& value, bool active) {
        const auto it = mVoxels.find(ijk);
        const Kind oldKind =
            it == mVoxels.end() ? Kind::Absent : kindOf(it->second.value, it->second.active);
        const Kind newKind = kindOf(value, active);
        if (oldKind == Kind::Active)
            --mActiveCount;
        if (newKind == Kind::Active)
            ++mActiveCount;
        if (oldKind != newKind) {
            count(ijk, oldKind, -1);
            count(ijk, newKind, +1);
        }
        if (newKind == Kind::Absent) {
            if (it != mVoxels.end())
                mVoxels.erase(it);
        } else if (it == mVoxels.end()) {
            mVoxels.emplace(ijk, Voxel{value, active});
        } else {
            it->second = Voxel{value, active};
        }
    }

    ValueT mBackground;
    std::vector<Index> mNodeLog2;
    std::unordered_map<Coord, Voxel, CoordHash, CoordEqual> mVoxels;
    // Per node level: region origin -> what the stored voxels inside it are.
    std::vector<std::unordered_map<Coord, RegionStats, CoordHash, CoordEqual>> mRegions;
    Index64 mActiveCount = 0;
};

// ---- Tree shapes ------------------------------------------------------------------------------

/// The node sizes of one tree configuration, written out from the paper's Table II rather than
/// read from the tree's templates, so that tests can check the tree against them.
struct TreeShape {
    std::vector<Index> log2Dims;  // nodes below any root, top first, leaf last: 5-4-3 is {5, 4, 3}
    bool bounded = false;         // the top is an InternalNode, so the domain is fixed

    Index nodeLevels() const { return Index(log2Dims.size()); }
    Index leafLog2() const { return log2Dims.back(); }
    /// log2 of the edge, in voxels, of the region a node at `level` covers (0 = leaf).
    Index regionLog2(Index level) const {
        Index sum = 0;
        for (Index l = 0; l <= level; ++l)
            sum += log2Dims[log2Dims.size() - 1 - l];
        return sum;
    }
    /// log2 of the edge of a tile held by a node at `level` (level 1 holds leaf-sized tiles).
    Index tileLog2(Index level) const { return regionLog2(level - 1); }
    /// The level of the top node: the root (unbounded) or the top InternalNode (bounded).
    Index topLevel() const { return bounded ? nodeLevels() - 1 : nodeLevels(); }
    /// The index-space domain: the centred cube [-2^(T-1), 2^(T-1) - 1]^3 of a bounded tree
    /// whose log2 edges sum to T, or every coordinate.
    CoordBBox domain() const {
        if (!bounded)
            return CoordBBox::inf();
        const Int64 half = Int64(1) << (regionLog2(nodeLevels() - 1) - 1);
        return CoordBBox(Coord(Int32(-half)), Coord(Int32(half - 1)));
    }
};

/// A tree type paired with its shape: `Bounded` and the log2 edges below any root, top first.
/// Tests derive one struct per configuration and add `static constexpr const char* NAME`.
template <typename TreeT, bool Bounded, Index... Log2Dims>
struct TreeConfig {
    using TreeType = TreeT;
    static TreeShape shape() { return {{Log2Dims...}, Bounded}; }
};

/// Names typed tests after the configuration's NAME.
struct ConfigName {
    template <typename ConfigT>
    static std::string GetName(int) {
        return ConfigT::NAME;
    }
};

// ---- Tree-versus-model comparisons ------------------------------------------------------------
//
// Each returns a gtest AssertionResult whose failure message names the first coordinate where
// the tree and the model disagree. They use only the tree's public API.

/// Walks the tree's ValueOn iterator, expanding tiles into voxels, and compares the active set,
/// the active values, the counts and the active bounding box with the model. Tiles must be
/// aligned cubes of the size their level implies.
template <typename TreeT, typename ValueT>
::testing::AssertionResult compareActiveValues(const TreeT& tree,
                                               const SparseVolumeModel<ValueT>& model,
                                               const TreeShape& shape) {
    constexpr Index64 kMaxTileVolume = Index64(1) << 21;
    std::vector<Coord> voxels;
    voxels.reserve(size_t(model.activeVoxelCount()));
    Index64 tileCount = 0, leafVoxelCount = 0;
    for (auto it = tree.cbeginValueOn(); it; ++it) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        const Index level = Index(it.getLevel());
        const ValueT value = it.getValue();
        const Coord ijk = it.getCoord();
        if (!it.isValueOn()) {
            return ::testing::AssertionFailure() << "ValueOn iterator at " << ijk << " is off";
        }
        if (it.isVoxelValue() == it.isTileValue()) {
            return ::testing::AssertionFailure()
                   << "ValueOn iterator at " << ijk << ": isVoxelValue() == isTileValue()";
        }
        if (it.isVoxelValue()) {
            if (level != 0 || bbox != CoordBBox(ijk, ijk)) {
                return ::testing::AssertionFailure() << "active voxel " << ijk << " reports level "
                                                     << level << " and box " << bbox;
            }
            ++leafVoxelCount;
            ValueT expected;
            if (!model.probeValue(ijk, expected) || !(value == expected)) {
                return ::testing::AssertionFailure()
                       << "active voxel " << ijk << " = " << value << "; model: " << expected
                       << (model.isValueOn(ijk) ? " on" : " off");
            }
            voxels.push_back(ijk);
            continue;
        }
        if (level < 1 || level > shape.topLevel()) {
            return ::testing::AssertionFailure()
                   << "active tile at " << ijk << " reports level " << level << " outside [1, "
                   << shape.topLevel() << "]";
        }
        const Index log2 = shape.tileLog2(level);
        const CoordBBox expectedBox =
            CoordBBox::createCube(bbox.min().alignedDown(log2), Int32(Index64(1) << log2));
        if (bbox != expectedBox || !bbox.isInside(ijk)) {
            return ::testing::AssertionFailure()
                   << "active tile at level " << level << " has box " << bbox << " and coord "
                   << ijk << "; a level-" << level << " tile is an aligned cube of edge 2^" << log2;
        }
        if (bbox.volume() > kMaxTileVolume) {
            return ::testing::AssertionFailure()
                   << "active tile " << bbox << " is larger than any the workload makes";
        }
        ++tileCount;
        for (Int64 x = bbox.min()[0]; x <= bbox.max()[0]; ++x) {
            for (Int64 y = bbox.min()[1]; y <= bbox.max()[1]; ++y) {
                for (Int64 z = bbox.min()[2]; z <= bbox.max()[2]; ++z) {
                    const Coord xyz{Int32(x), Int32(y), Int32(z)};
                    ValueT expected;
                    if (!model.probeValue(xyz, expected) || !(value == expected)) {
                        return ::testing::AssertionFailure()
                               << "voxel " << xyz << " of active tile " << bbox << " = " << value
                               << "; model: " << expected
                               << (model.isValueOn(xyz) ? " on" : " off");
                    }
                    voxels.push_back(xyz);
                }
            }
        }
    }

    // The sorted lists differ exactly when some voxel is missing, extra or visited twice.
    std::sort(voxels.begin(), voxels.end());
    const std::vector<Coord> expected = model.sortedActiveVoxels();
    if (voxels != expected) {
        const auto [a, b] =
            std::mismatch(voxels.begin(), voxels.end(), expected.begin(), expected.end());
        ::testing::AssertionResult failure = ::testing::AssertionFailure();
        failure << "active sets differ (tree " << voxels.size() << ", model " << expected.size()
                << " voxels): ";
        if (b == expected.end() || (a != voxels.end() && *a < *b)) {
            const bool twice = (a != voxels.begin() && *(a - 1) == *a) ||
                               (a + 1 != voxels.end() && *(a + 1) == *a);
            failure << "tree has " << *a << (twice ? " twice" : ", which the model lacks");
        } else {
            failure << "model has " << *b << ", which the tree lacks";
        }
        return failure;
    }
    if (tree.activeVoxelCount() != model.activeVoxelCount()) {
        return ::testing::AssertionFailure() << "activeVoxelCount() = " << tree.activeVoxelCount()
                                             << "; model: " << model.activeVoxelCount();
    }
    if (tree.activeTileCount() != tileCount) {
        return ::testing::AssertionFailure() << "activeTileCount() = " << tree.activeTileCount()
                                             << "; ValueOn iterator visited " << tileCount;
    }
    if (tree.activeLeafVoxelCount() != leafVoxelCount) {
        return ::testing::AssertionFailure()
               << "activeLeafVoxelCount() = " << tree.activeLeafVoxelCount()
               << "; ValueOn iterator visited " << leafVoxelCount << " voxels in leaves";
    }
    CoordBBox bbox;
    const bool any = tree.evalActiveVoxelBoundingBox(bbox);
    const CoordBBox modelBox = model.activeBoundingBox();
    if (any != !expected.empty() || (any && bbox != modelBox)) {
        return ::testing::AssertionFailure() << "evalActiveVoxelBoundingBox() = " << any << ", "
                                             << bbox << "; model: " << modelBox;
    }
    return ::testing::AssertionSuccess();
}

/// Looks up the stored voxels of the model (every `stride`-th, from `first`) through
/// getValue(), isValueOn() and probeValue() of `reader`: a tree or an accessor.
template <typename ReaderT, typename ValueT>
::testing::AssertionResult compareStoredValues(ReaderT& reader,
                                               const SparseVolumeModel<ValueT>& model,
                                               size_t stride = 1, size_t first = 0,
                                               const char* readerName = "tree") {
    ::testing::AssertionResult result = ::testing::AssertionSuccess();
    size_t n = 0;
    bool failed = false;
    model.forEach([&](const Coord& ijk, const ValueT& value, bool active) {
        if (failed || (n++ % stride) != first % stride)
            return;
        ValueT probed;
        const bool probedOn = reader.probeValue(ijk, probed);
        const ValueT got = reader.getValue(ijk);
        const bool on = reader.isValueOn(ijk);
        if (!(got == value) || on != active || !(probed == value) || probedOn != active) {
            failed = true;
            result = ::testing::AssertionFailure()
                     << readerName << " at " << ijk << ": getValue " << got << ", isValueOn " << on
                     << ", probeValue " << probed << "/" << probedOn << "; model: " << value
                     << (active ? " on" : " off");
        }
    });
    return result;
}

/// Checks the leaf iterator: every leaf once, aligned, found again by probeConstLeaf(), and
/// as many as leafCount(); the leaves' active voxels sum to activeLeafVoxelCount().
template <typename TreeT>
::testing::AssertionResult compareLeaves(const TreeT& tree, const TreeShape& shape) {
    std::unordered_set<Coord, CoordHash, CoordEqual> origins;
    Index64 onVoxels = 0;
    for (auto it = tree.cbeginLeaf(); it; ++it) {
        const auto& leaf = *it;
        const Coord origin = leaf.origin();
        if (origin != origin.alignedDown(shape.leafLog2())) {
            return ::testing::AssertionFailure() << "leaf origin " << origin << " is not aligned";
        }
        if (!origins.insert(origin).second) {
            return ::testing::AssertionFailure() << "leaf " << origin << " visited twice";
        }
        if (tree.probeConstLeaf(origin) != &leaf) {
            return ::testing::AssertionFailure()
                   << "probeConstLeaf(" << origin << ") is not the iterated leaf";
        }
        onVoxels += leaf.onVoxelCount();
    }
    if (origins.size() != tree.leafCount()) {
        return ::testing::AssertionFailure() << "leaf iterator visited " << origins.size()
                                             << " leaves; leafCount() = " << tree.leafCount();
    }
    if (onVoxels != tree.activeLeafVoxelCount()) {
        return ::testing::AssertionFailure()
               << "leaves hold " << onVoxels
               << " active voxels; activeLeafVoxelCount() = " << tree.activeLeafVoxelCount();
    }
    return ::testing::AssertionSuccess();
}

/// Walks the ValueOff iterator: every item inactive, aligned and of the size its level implies,
/// and the voxels of the items that hold a non-background value exactly the model's inactive
/// non-background voxels, with their values. Then the ValueAll iterator must visit the ValueOn
/// and ValueOff items together, and they must tile the domain (bounded trees) or the regions
/// of the root's entries (unbounded trees) exactly once.
template <typename TreeT, typename ValueT>
::testing::AssertionResult compareInactiveValues(const TreeT& tree,
                                                 const SparseVolumeModel<ValueT>& model,
                                                 const TreeShape& shape) {
    constexpr Index64 kMaxTileVolume = Index64(1) << 21;
    __extension__ typedef unsigned __int128 Volume;
    const ValueT background = model.background();

    // Checks one item of a value iterator; counts its volume.
    auto checkItem = [&](const auto& it, bool on, Volume& volume) -> ::testing::AssertionResult {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        const Index level = Index(it.getLevel());
        const Coord ijk = it.getCoord();
        volume += bbox.volume();
        if (it.isValueOn() != on) {
            return ::testing::AssertionFailure()
                   << "Value" << (on ? "On" : "Off") << " iterator at " << ijk << " reports "
                   << (on ? "an inactive" : "an active") << " value";
        }
        if (level > shape.topLevel()) {
            return ::testing::AssertionFailure() << "item at " << ijk << " reports level " << level;
        }
        const Index log2 = level == 0 ? 0 : shape.tileLog2(level);
        if (bbox != CoordBBox::createCube(ijk.alignedDown(log2), Int32(Index64(1) << log2)) ||
            it.isVoxelValue() != (level == 0) || it.isTileValue() != (level != 0)) {
            return ::testing::AssertionFailure()
                   << "item at " << ijk << ", level " << level << " has box " << bbox
                   << "; expected an aligned cube of edge 2^" << log2;
        }
        return ::testing::AssertionSuccess();
    };

    // Inactive items: the non-background voxels they cover, with values checked on the way.
    std::vector<Coord> held;
    Volume offVolume = 0;
    Index64 offItems = 0;
    for (auto it = tree.cbeginValueOff(); it; ++it, ++offItems) {
        if (auto r = checkItem(it, false, offVolume); !r)
            return r;
        const ValueT value = it.getValue();
        if (value == background)
            continue;
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        if (bbox.volume() > kMaxTileVolume) {
            return ::testing::AssertionFailure() << "inactive tile " << bbox << " holds " << value
                                                 << ", and is larger than any the workload makes";
        }
        for (Int64 x = bbox.min()[0]; x <= bbox.max()[0]; ++x) {
            for (Int64 y = bbox.min()[1]; y <= bbox.max()[1]; ++y) {
                for (Int64 z = bbox.min()[2]; z <= bbox.max()[2]; ++z) {
                    const Coord xyz{Int32(x), Int32(y), Int32(z)};
                    ValueT expected;
                    const bool expectedOn = model.probeValue(xyz, expected);
                    if (!(expected == value) || expectedOn) {
                        return ::testing::AssertionFailure()
                               << "inactive " << (bbox.volume() > 1 ? "tile voxel " : "voxel ")
                               << xyz << " = " << value << "; model: " << expected
                               << (expectedOn ? " on" : " off");
                    }
                    held.push_back(xyz);
                }
            }
        }
    }
    std::vector<Coord> expected;
    model.forEach([&](const Coord& ijk, const ValueT& value, bool active) {
        if (!active && !(value == background))
            expected.push_back(ijk);
    });
    std::sort(held.begin(), held.end());
    std::sort(expected.begin(), expected.end());
    if (held != expected) {
        const auto [a, b] =
            std::mismatch(held.begin(), held.end(), expected.begin(), expected.end());
        if (b == expected.end() || (a != held.end() && *a < *b)) {
            return ::testing::AssertionFailure()
                   << "the ValueOff iterator visits " << *a << " twice";
        }
        return ::testing::AssertionFailure()
               << "inactive voxel " << *b << " = " << model.getValue(*b)
               << " (model) is not visited by the ValueOff iterator";
    }

    // ValueAll is the union of ValueOn and ValueOff, and covers whole regions exactly once.
    Volume onVolume = 0, allVolume = 0;
    Index64 onItems = 0, allItems = 0;
    for (auto it = tree.cbeginValueOn(); it; ++it, ++onItems) {
        if (auto r = checkItem(it, true, onVolume); !r)
            return r;
    }
    const Index regionLog2 = shape.regionLog2(shape.nodeLevels() - 1);
    std::vector<Coord> regions;  // root entries (unbounded), in visiting order
    for (auto it = tree.cbeginValueAll(); it; ++it, ++allItems) {
        CoordBBox bbox;
        it.getBoundingBox(bbox);
        allVolume += bbox.volume();
        const Coord region = bbox.min().alignedDown(regionLog2);
        if (regions.empty() || regions.back() != region)
            regions.push_back(region);
    }
    if (allItems != onItems + offItems || allVolume != onVolume + offVolume) {
        return ::testing::AssertionFailure()
               << "ValueAll visited " << allItems << " items; ValueOn " << onItems
               << " and ValueOff " << offItems << " (or their volumes differ)";
    }
    std::sort(regions.begin(), regions.end());
    regions.erase(std::unique(regions.begin(), regions.end()), regions.end());
    const Volume expectedVolume =
        shape.bounded ? Volume(1) << (3 * regionLog2) : Volume(regions.size()) << (3 * regionLog2);
    if (allVolume != expectedVolume) {
        return ::testing::AssertionFailure()
               << "the ValueAll items do not cover "
               << (shape.bounded ? "the domain" : "the regions of the root's entries")
               << " exactly once";
    }
    return ::testing::AssertionSuccess();
}

// ---- Random workloads -------------------------------------------------------------------------

/// The fraction of each random workload to run, from the environment variable
/// VDB_TEST_WORKLOAD (default 1). The sanitizer test preset sets it below 1: the same
/// operations, checks and seeds, fewer batches.
inline double workloadScale() {
    const char* text = std::getenv("VDB_TEST_WORKLOAD");
    if (!text)
        return 1.0;
    const double scale = std::strtod(text, nullptr);
    return scale > 0.0 && scale <= 1.0 ? scale : 1.0;
}
inline int scaledBatchCount(int batches) {
    return std::max(1, int(batches * workloadScale() + 0.5));
}

/// The size and mix of a random tree-versus-model workload.
struct WorkloadOptions {
    uint32_t seed = 20130601;
    int batches = 40;
    int opsPerBatch = 25000;
    int denseClusters = 6;     // cluster centres (the origin, domain corners or the +-2^31
                               // corners, and random far-apart places)
    Int32 clusterRadius = 12;  // a dense cluster is the cube of this radius around a centre
    int sparsePoints = 32;     // isolated points anywhere in the domain
    Index64 maxSmallFillVolume = 4096;
    Index64 maxAlignedFillVolume = Index64(1) << 18;  // node-aligned fills up to this volume
    Index64 alignedFillVoxelsPerBatch = 16384;        // expected node-aligned fill volume
    size_t maxModelSize = 150000;                     // clear() both beyond this many voxels
    size_t storedValuesCheckedPerBatch = 30000;
    double pruneOrClearRate = 1e-3;   // per operation; one in 20 of them is a clear()
    bool checkInactiveValues = true;  // walk ValueOff/ValueAll after the last batch
    bool checkCopy = true;            // deep-copy and move the tree after the last batch
    double leafIndexRate = 0;         // per operation: rebuild the tree's leaf index
};

/// Checks the tree's leaf index, when it has a current one, against the tree: every leaf it
/// lists is the leaf the walk from the top finds at that origin, and every leaf of the tree is
/// either in it or absent from it (added since it was built), never another leaf.
template <typename TreeT>
::testing::AssertionResult checkLeafIndex(const TreeT& tree) {
    const auto* index = tree.leafIndex();
    if (index == nullptr)
        return ::testing::AssertionSuccess();
    using LeafT = typename TreeT::LeafNodeType;
    const auto walk = [&tree](const Coord& ijk) -> const LeafT* {
        tree::detail::NoCache none;
        return tree.topNode().template getAndCache<tree::ops::ProbeLeaf>(ijk, none);
    };
    size_t listed = 0;
    ::testing::AssertionResult result = ::testing::AssertionSuccess();
    index->forEachLeaf([&](const LeafT& leaf) {
        ++listed;
        if (result && walk(leaf.origin()) != &leaf)
            result = ::testing::AssertionFailure()
                     << "the leaf index lists a leaf at " << leaf.origin()
                     << " that the tree does not hold there";
    });
    if (!result)
        return result;
    if (listed != index->size())
        return ::testing::AssertionFailure()
               << "the leaf index lists " << listed << " leaves, its size() says " << index->size();
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) {
        const LeafT* found = index->find(leaf->origin());
        if (found != nullptr && found != &*leaf)
            return ::testing::AssertionFailure()
                   << "the leaf index finds another leaf at " << leaf->origin();
    }
    return ::testing::AssertionSuccess();
}

/// Draws coordinates from dense clusters, isolated far-apart points and recently used
/// coordinates, all inside the domain. Unbounded domains get clusters at the +-2^31 corners.
class CoordSampler {
public:
    CoordSampler(const TreeShape& shape, const WorkloadOptions& options, std::mt19937& rng)
        : mDomain(shape.domain()), mRadius(options.clusterRadius) {
        constexpr Int32 lo = std::numeric_limits<Int32>::min();
        constexpr Int32 hi = std::numeric_limits<Int32>::max();
        mCenters.push_back(Coord(0));  // spans all eight octants
        if (shape.bounded) {
            mCenters.push_back(mDomain.min());
            mCenters.push_back(mDomain.max());
        } else {
            mCenters.push_back(Coord(lo));
            mCenters.push_back(Coord(hi));
            mCenters.push_back(Coord(lo, hi, -(1 << 20)));
            mSparse = {Coord(lo), Coord(hi), Coord(lo, hi, lo), Coord(hi, lo, hi)};
        }
        // Far-apart centres away from the extremes; isolated points anywhere.
        const CoordBBox inner =
            shape.bounded ? mDomain : CoordBBox(Coord(-(1 << 30)), Coord(1 << 30));
        while (int(mCenters.size()) < options.denseClusters)
            mCenters.push_back(uniform(inner, rng));
        while (int(mSparse.size()) < options.sparsePoints)
            mSparse.push_back(uniform(mDomain, rng));
        mRecent.reserve(kRecent);
    }

    const CoordBBox& domain() const { return mDomain; }

    /// A coordinate near a cluster centre (65%), near an isolated point (15%) or recently
    /// used (20%).
    Coord next(std::mt19937& rng) {
        const unsigned r = rng() % 100;
        if (r >= 80 && !mRecent.empty())
            return mRecent[rng() % mRecent.size()];
        if (r >= 65)
            return around(mSparse[rng() % mSparse.size()], 2, rng);
        return around(mCenters[rng() % mCenters.size()], mRadius, rng);
    }
    /// A recently used coordinate most of the time: reads and deletions should hit voxels.
    Coord nextUsed(std::mt19937& rng) {
        if (!mRecent.empty() && rng() % 4 != 0)
            return mRecent[rng() % mRecent.size()];
        return next(rng);
    }
    void remember(const Coord& ijk) {
        if (mRecent.size() < kRecent) {
            mRecent.push_back(ijk);
        } else {
            mRecent[mRecentNext++ % kRecent] = ijk;
        }
    }

    /// A box of at most `maxVolume` voxels with a corner at a sampled coordinate, clipped to
    /// the domain.
    CoordBBox box(std::mt19937& rng, Index64 maxVolume) {
        const Coord a = next(rng);
        Int64 e[3];
        do {
            for (Int64& n : e)
                n = 1 + Int64(rng() % 16);
        } while (Index64(e[0] * e[1] * e[2]) > maxVolume);
        CoordBBox result(
            a, clamp(Int64(a[0]) + e[0] - 1, Int64(a[1]) + e[1] - 1, Int64(a[2]) + e[2] - 1));
        result.intersect(mDomain);
        return result;
    }
    /// The aligned cube of edge 2^log2 holding a sampled coordinate: the region of one node.
    CoordBBox alignedCube(std::mt19937& rng, Index log2) {
        return CoordBBox::createCube(next(rng).alignedDown(log2), Int32(Index64(1) << log2));
    }
    /// A coordinate just outside a bounded domain, or far outside it.
    Coord outside(std::mt19937& rng) const {
        Coord ijk = mDomain.min().offsetBy(Int32(rng() % 64));
        const size_t axis = rng() % 3;
        switch (rng() % 4) {
            case 0:
                ijk[axis] = mDomain.min()[axis] - 1;
                break;
            case 1:
                ijk[axis] = mDomain.max()[axis] + 1;
                break;
            case 2:
                ijk[axis] = std::numeric_limits<Int32>::min();
                break;
            default:
                ijk[axis] = std::numeric_limits<Int32>::max();
                break;
        }
        return ijk;
    }

private:
    static constexpr size_t kRecent = 4096;

    Coord clamp(Int64 x, Int64 y, Int64 z) const {
        auto c = [&](Int64 v, size_t axis) {
            return Int32(std::clamp<Int64>(v, mDomain.min()[axis], mDomain.max()[axis]));
        };
        return Coord(c(x, 0), c(y, 1), c(z, 2));
    }
    Coord around(const Coord& center, Int32 radius, std::mt19937& rng) const {
        std::uniform_int_distribution<Int64> d(-radius, radius);
        return clamp(center[0] + d(rng), center[1] + d(rng), center[2] + d(rng));
    }
    static Coord uniform(const CoordBBox& box, std::mt19937& rng) {
        Int32 v[3];
        for (size_t axis = 0; axis < 3; ++axis) {
            v[axis] =
                Int32(std::uniform_int_distribution<Int64>(box.min()[axis], box.max()[axis])(rng));
        }
        return Coord(v[0], v[1], v[2]);
    }

    CoordBBox mDomain;
    Int32 mRadius;
    std::vector<Coord> mCenters, mSparse, mRecent;
    size_t mRecentNext = 0;
};

/// Applies one seeded random sequence of operations to a tree and to a SparseVolumeModel in
/// lockstep, reading back after every write and comparing everything after every batch.
///
/// Writes go through the tree or through a ValueAccessor, reads through the tree, the
/// accessor and a read-only accessor; both accessors live for the whole run, across prune(),
/// clear(), fill() and eraseValue(). Mask trees (BuildType ValueMask) are driven with mask
/// semantics: a voxel's value is its active state.
template <typename TreeT, typename AccessorT, typename ConstAccessorT>
class TreeModelDriver {
public:
    using ValueT = typename TreeT::ValueType;
    static constexpr bool IS_MASK = std::is_same_v<typename TreeT::BuildType, ValueMask>;

    /// @param palette  the values writes draw from; include the background.
    TreeModelDriver(TreeT& tree, const TreeShape& shape, const WorkloadOptions& options,
                    std::vector<ValueT> palette)
        : mTree(tree),
          mAcc(tree),
          mConstAcc(std::as_const(tree)),
          mShape(shape),
          mOptions(options),
          mRng(options.seed),
          mSampler(shape, options, mRng),
          mModel(tree.background(), {shape.leafLog2()}),
          mPalette(std::move(palette)) {}

    const SparseVolumeModel<ValueT>& model() const { return mModel; }
    Index64 opCount() const { return mOpCount; }
    /// How often the leaf index was built, and how many operations ran with a current one.
    Index64 leafIndexBuilds() const { return mLeafIndexBuilds; }
    Index64 opsWithLeafIndex() const { return mOpsWithLeafIndex; }

    /// Runs every batch, then the final whole-tree checks.
    ::testing::AssertionResult run() {
        const int batches = scaledBatchCount(mOptions.batches);
        for (int batch = 0; batch < batches; ++batch) {
            for (int n = 0; n < mOptions.opsPerBatch; ++n) {
                if (auto r = step(); !r)
                    return r;
            }
            const bool last = batch + 1 == batches;
            if (auto r = verify(last); !r) {
                return r << " (after batch " << batch << ", op #" << mOpCount << ", seed "
                         << mOptions.seed << ")";
            }
            if (!last && mModel.size() > mOptions.maxModelSize)
                clearBoth();
        }
        if (mOptions.checkInactiveValues) {
            if (auto r = compareInactiveValues(mTree, mModel, mShape); !r)
                return r;
        }
        if (mOptions.checkCopy) {
            TreeT copy(mTree);
            if (auto r = compareActiveValues(copy, mModel, mShape); !r)
                return r << " (copy)";
            if (auto r = compareStoredValues(copy, mModel, 1, 0, "copy"); !r)
                return r;
            mTree.setValue(mSampler.next(mRng), mPalette.back());  // the copy is deep
            TreeT moved(std::move(copy));
            if (auto r = compareActiveValues(moved, mModel, mShape); !r)
                return r << " (moved)";
        }
        return ::testing::AssertionSuccess();
    }

    /// Performs one random operation on both and checks what it touched.
    ::testing::AssertionResult step() {
        ++mOpCount;
        if (mOptions.leafIndexRate > 0 &&
            std::uniform_real_distribution<double>(0, 1)(mRng) < mOptions.leafIndexRate) {
            mTree.buildLeafIndex();
            ++mLeafIndexBuilds;
            if (!mTree.hasLeafIndex())
                return fail("buildLeafIndex", Coord()) << "no current index after the build";
        }
        if (mTree.hasLeafIndex())
            ++mOpsWithLeafIndex;
        if (std::uniform_real_distribution<double>(0, 1)(mRng) < mOptions.pruneOrClearRate) {
            return pruneOrClear();
        }
        const unsigned r = mRng() % 1000;
        const ValueT v = mPalette[mRng() % mPalette.size()];
        if (r < 200)
            return write(Op::SetValue, v);
        if (r < 240)
            return write(Op::SetValueOn, v);
        if (r < 290)
            return write(Op::SetValueOnWith, v);
        if (r < 350)
            return write(Op::SetValueOff, v);
        if (r < 400)
            return write(Op::SetValueOffWith, v);
        if (r < 460)
            return write(Op::SetValueOnly, v);
        if (r < 520)
            return write(Op::SetActiveState, v);
        if (r < 670)
            return erase();
        if (r < 965)
            return read();
        if (r < 970)
            return touchLeaf();
        if (r < 980)
            return probeLeaf();
        if (r < 985)
            return fillSmall(v);
        if (r < 990)
            return outsideDomain(v);
        if (r < 998)
            return maybeFillAligned(v);
        return paintLeaf(v);
    }

    /// Compares everything: the active set through the ValueOn iterator, the leaves, and the
    /// stored values through the tree and both accessors (all of them when `full`).
    ::testing::AssertionResult verify(bool full) {
        if (auto r = checkLeafIndex(mTree); !r)
            return r;
        if (auto r = compareActiveValues(mTree, mModel, mShape); !r)
            return r;
        if (auto r = compareLeaves(mTree, mShape); !r)
            return r;
        const size_t limit = mOptions.storedValuesCheckedPerBatch;
        const size_t stride = full || mModel.size() <= limit ? 1 : mModel.size() / limit + 1;
        const size_t first = size_t(mRng() % stride);
        if (auto r = compareStoredValues(mTree, mModel, stride, first, "tree"); !r)
            return r;
        if (auto r = compareStoredValues(mAcc, mModel, stride, first, "accessor"); !r)
            return r;
        if (auto r = compareStoredValues(mConstAcc, mModel, stride, first, "const accessor"); !r) {
            return r;
        }
        // Coordinates the model does not store read as inactive background.
        for (int n = 0; n < 2000; ++n) {
            if (auto r = checkVoxel(mSampler.next(mRng), "probe"); !r)
                return r;
        }
        return ::testing::AssertionSuccess();
    }

private:
    enum class Op {
        SetValue,
        SetValueOn,
        SetValueOnWith,
        SetValueOff,
        SetValueOffWith,
        SetValueOnly,
        SetActiveState
    };
    static const char* name(Op op) {
        switch (op) {
            case Op::SetValue:
                return "setValue";
            case Op::SetValueOn:
                return "setValueOn(ijk)";
            case Op::SetValueOnWith:
                return "setValueOn(ijk, v)";
            case Op::SetValueOff:
                return "setValueOff(ijk)";
            case Op::SetValueOffWith:
                return "setValueOff(ijk, v)";
            case Op::SetValueOnly:
                return "setValueOnly";
            default:
                return "setActiveState";
        }
    }

    ::testing::AssertionResult fail(const char* what, const Coord& ijk) {
        return ::testing::AssertionFailure() << what << " at " << ijk << " (op #" << mOpCount
                                             << ", seed " << mOptions.seed << "): ";
    }

    /// Reads `ijk` through the tree and both accessors and compares with the model.
    ::testing::AssertionResult checkVoxel(const Coord& ijk, const char* after) {
        ValueT expected;
        const bool expectedOn = mModel.probeValue(ijk, expected);
        ValueT a, b;
        const bool aOn = mTree.probeValue(ijk, a);
        const bool bOn = mConstAcc.probeValue(ijk, b);
        const ValueT c = mTree.getValue(ijk), d = mAcc.getValue(ijk), e = mConstAcc.getValue(ijk);
        const bool cOn = mTree.isValueOn(ijk), dOn = mAcc.isValueOn(ijk);
        if (!(a == expected) || !(b == expected) || !(c == expected) || !(d == expected) ||
            !(e == expected) || aOn != expectedOn || bOn != expectedOn || cOn != expectedOn ||
            dOn != expectedOn) {
            return fail(after, ijk)
                   << "tree probeValue " << a << "/" << aOn << ", getValue " << c << ", isValueOn "
                   << cOn << "; accessor " << d << "/" << dOn << "; const accessor " << b << "/"
                   << bOn << ", " << e << "; model: " << expected << (expectedOn ? " on" : " off");
        }
        return ::testing::AssertionSuccess();
    }

    // ---- Operations
    ::testing::AssertionResult write(Op op, const ValueT& v) {
        const Coord ijk = mSampler.next(mRng);
        const bool on = mRng() % 2 == 0;
        auto apply = [&](auto& target) {
            switch (op) {
                case Op::SetValue:
                    target.setValue(ijk, v);
                    break;
                case Op::SetValueOn:
                    target.setValueOn(ijk);
                    break;
                case Op::SetValueOnWith:
                    target.setValueOn(ijk, v);
                    break;
                case Op::SetValueOff:
                    target.setValueOff(ijk);
                    break;
                case Op::SetValueOffWith:
                    target.setValueOff(ijk, v);
                    break;
                case Op::SetValueOnly:
                    target.setValueOnly(ijk, v);
                    break;
                case Op::SetActiveState:
                    target.setActiveState(ijk, on);
                    break;
            }
        };
        if (mRng() % 2) {
            apply(mTree);
        } else {
            apply(mAcc);
        }
        if constexpr (IS_MASK) {
            // The value of a mask voxel is its state: writing true activates, false deactivates.
            bool state = mModel.isValueOn(ijk);
            switch (op) {
                case Op::SetValueOn:
                    state = true;
                    break;
                case Op::SetValueOff:
                    state = false;
                    break;
                case Op::SetActiveState:
                    state = on;
                    break;
                default:
                    state = v;
                    break;
            }
            mModel.setActiveState(ijk, state);
            mModel.setValueOnly(ijk, state);
        } else {
            apply(mModel);
        }
        mSampler.remember(ijk);
        return checkVoxel(ijk, name(op));
    }

    ::testing::AssertionResult erase() {
        const Coord ijk = mSampler.nextUsed(mRng);
        if (mRng() % 2) {
            mTree.eraseValue(ijk);
        } else {
            mAcc.eraseValue(ijk);
        }
        mModel.eraseValue(ijk);
        // A leaf left with nothing but inactive background is freed.
        if (mModel.storedVoxelsInNode(0, ijk) == 0 && mTree.probeConstLeaf(ijk) != nullptr) {
            return fail("eraseValue", ijk) << "the leaf holds only inactive background but "
                                           << "still exists";
        }
        return checkVoxel(ijk, "eraseValue");
    }

    ::testing::AssertionResult read() {
        const Coord ijk = mSampler.nextUsed(mRng);
        return checkVoxel(ijk, "read");
    }

    /// Checks the corners of the leaf region holding `ijk` and a few random voxels inside.
    ::testing::AssertionResult checkLeafRegion(const Coord& ijk, const char* after) {
        const Index log2 = mShape.leafLog2();
        const Coord origin = ijk.alignedDown(log2);
        const Int32 dim = Int32(1) << log2;
        for (int n = 0; n < 24; ++n) {
            const Coord xyz = n < 8 ? origin.offsetBy(n & 1 ? dim - 1 : 0, n & 2 ? dim - 1 : 0,
                                                      n & 4 ? dim - 1 : 0)
                                    : origin.offsetBy(Int32(mRng() % dim), Int32(mRng() % dim),
                                                      Int32(mRng() % dim));
            if (auto r = checkVoxel(xyz, after); !r)
                return r;
        }
        return ::testing::AssertionSuccess();
    }

    ::testing::AssertionResult touchLeaf() {
        const Coord ijk = mSampler.next(mRng);
        auto* leaf = mRng() % 2 ? mTree.touchLeaf(ijk) : mAcc.touchLeaf(ijk);
        if (leaf == nullptr || leaf->origin() != ijk.alignedDown(mShape.leafLog2()) ||
            mTree.probeConstLeaf(ijk) != leaf) {
            return fail("touchLeaf", ijk) << "no leaf, a misplaced leaf, or probeConstLeaf "
                                          << "finds another";
        }
        // Splitting a tile into a leaf keeps every value and state.
        return checkLeafRegion(ijk, "touchLeaf");
    }

    ::testing::AssertionResult probeLeaf() {
        const Coord ijk = mSampler.nextUsed(mRng);
        const auto* leaf = mRng() % 2 ? mTree.probeConstLeaf(ijk) : mConstAcc.probeConstLeaf(ijk);
        if (leaf == nullptr)
            return ::testing::AssertionSuccess();  // absent or in a tile
        if (leaf->origin() != ijk.alignedDown(mShape.leafLog2()) ||
            !(leaf->getValue(ijk) == mModel.getValue(ijk)) ||
            leaf->isValueOn(ijk) != mModel.isValueOn(ijk)) {
            return fail("probeConstLeaf", ijk)
                   << "leaf " << leaf->origin() << " holds " << leaf->getValue(ijk)
                   << (leaf->isValueOn(ijk) ? " on" : " off") << "; model: " << mModel.getValue(ijk)
                   << (mModel.isValueOn(ijk) ? " on" : " off");
        }
        return ::testing::AssertionSuccess();
    }

    ::testing::AssertionResult fillBox(const CoordBBox& bbox, const ValueT& v, bool active,
                                       const char* what) {
        mTree.fill(bbox, v, active);
        if constexpr (IS_MASK) {
            mModel.fill(bbox, v || active, v || active);
        } else {
            mModel.fill(bbox, v, active);
        }
        mSampler.remember(bbox.min());
        // Corners inside, and the voxels just outside two of them.
        for (const Coord& ijk :
             {bbox.min(), bbox.max(), Coord(bbox.min()[0], bbox.max()[1], bbox.min()[2])}) {
            if (auto r = checkVoxel(ijk, what); !r)
                return r << " (box " << bbox << ")";
        }
        for (const Coord& ijk : {bbox.min().offsetBy(-1, 0, 0), bbox.max().offsetBy(0, 0, 1)}) {
            if (!mSampler.domain().isInside(ijk))
                continue;
            if (auto r = checkVoxel(ijk, what); !r)
                return r << " (box " << bbox << ")";
        }
        return ::testing::AssertionSuccess();
    }

    ::testing::AssertionResult fillSmall(const ValueT& v) {
        const CoordBBox bbox = mSampler.box(mRng, mOptions.maxSmallFillVolume);
        // Inactive background fills erase, and keep the model small.
        if (mRng() % 3 == 0)
            return fillBox(bbox, mTree.background(), false, "fill(erase)");
        return fillBox(bbox, v, mRng() % 4 != 0, "fill");
    }

    /// Fills the whole region of a leaf or of a level-1 node, so that the tree makes a tile;
    /// as often as keeps the expected aligned volume per batch near the option's budget.
    ::testing::AssertionResult maybeFillAligned(const ValueT& v) {
        const Index log2 = mShape.tileLog2(mRng() % 4 == 0 ? 2 : 1);
        const Index64 volume = Index64(1) << (3 * log2);
        if (volume > mOptions.maxAlignedFillVolume)
            return ::testing::AssertionSuccess();
        // This op is drawn 8 times per 1000 ops.
        const double perBatch = double(mOptions.opsPerBatch) * 8e-3;
        const double p = double(mOptions.alignedFillVoxelsPerBatch) / (double(volume) * perBatch);
        if (std::uniform_real_distribution<double>(0, 1)(mRng) >= p) {
            return ::testing::AssertionSuccess();
        }
        const CoordBBox bbox = mSampler.alignedCube(mRng, log2);
        const bool active = mRng() % 4 != 0;
        if (auto r = fillBox(bbox, v, active, "fill(aligned)"); !r)
            return r;
        // A box that covers whole child nodes becomes tiles: no leaf remains inside.
        if (mTree.probeConstLeaf(bbox.min()) != nullptr ||
            mTree.probeConstLeaf(bbox.max()) != nullptr) {
            return fail("fill(aligned)", bbox.min())
                   << "a leaf remains inside the node-aligned box " << bbox;
        }
        return ::testing::AssertionSuccess();
    }

    /// Writes one value into every voxel of a leaf region, one setValue at a time, then often
    /// prunes: the leaf must become a tile. Leaves above 8^3 are painted proportionally less.
    ::testing::AssertionResult paintLeaf(const ValueT& v) {
        // As often as an 8^3 leaf would be painted: larger leaves cost more.
        const Index log2 = mShape.leafLog2();
        if (3 * log2 > 9 && mRng() % (Index64(1) << (3 * log2 - 9)) != 0) {
            return ::testing::AssertionSuccess();
        }
        const CoordBBox bbox = mSampler.alignedCube(mRng, log2);
        const ValueT value = IS_MASK ? ValueT(true) : v;
        for (Int64 x = bbox.min()[0]; x <= bbox.max()[0]; ++x)
            for (Int64 y = bbox.min()[1]; y <= bbox.max()[1]; ++y)
                for (Int64 z = bbox.min()[2]; z <= bbox.max()[2]; ++z)
                    mAcc.setValue(Coord(Int32(x), Int32(y), Int32(z)), value);
        mModel.fill(bbox, value, true);
        mSampler.remember(bbox.min());
        // Half the time with the default rate of structural operations.
        if (std::uniform_real_distribution<double>(0, 1)(mRng) < 500 * mOptions.pruneOrClearRate) {
            mTree.prune();
            if (mTree.probeConstLeaf(bbox.min()) != nullptr) {
                return fail("prune", bbox.min()) << "a leaf of one active value remains";
            }
        }
        return checkLeafRegion(bbox.min(), "paintLeaf");
    }

    ::testing::AssertionResult outsideDomain(const ValueT& v) {
        if (!mShape.bounded)
            return ::testing::AssertionSuccess();
        const Coord ijk = mSampler.outside(mRng);
        bool threw = false;
        try {
            if (mRng() % 2) {
                mTree.setValue(ijk, v);
            } else {
                mAcc.setValue(ijk, v);
            }
        } catch (const IndexError&) {
            threw = true;
        }
        if (!threw)
            return fail("setValue outside the domain", ijk) << "no IndexError";
        const ValueT bg = mTree.background();
        if (!(mTree.getValue(ijk) == bg) || mTree.isValueOn(ijk) || !(mAcc.getValue(ijk) == bg) ||
            !(mConstAcc.getValue(ijk) == bg) || mConstAcc.isValueOn(ijk)) {
            return fail("read outside the domain", ijk) << "not inactive background";
        }
        return ::testing::AssertionSuccess();
    }

    void clearBoth() {
        mTree.clear();
        mModel.clear();
    }

    ::testing::AssertionResult pruneOrClear() {
        if (mRng() % 20 != 0) {
            mTree.prune();
            mModel.prune();
            return ::testing::AssertionSuccess();
        }
        clearBoth();
        if (!mTree.empty() || mTree.activeVoxelCount() != 0 || mTree.leafCount() != 0) {
            return fail("clear", Coord()) << "the tree is not empty";
        }
        return ::testing::AssertionSuccess();
    }

    TreeT& mTree;
    AccessorT mAcc;
    ConstAccessorT mConstAcc;
    TreeShape mShape;
    WorkloadOptions mOptions;
    std::mt19937 mRng;
    CoordSampler mSampler;
    SparseVolumeModel<ValueT> mModel;
    std::vector<ValueT> mPalette;
    Index64 mOpCount = 0;
    Index64 mLeafIndexBuilds = 0;
    Index64 mOpsWithLeafIndex = 0;
};

}  // namespace vdb::test
