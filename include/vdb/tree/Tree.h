// SPDX-License-Identifier: Apache-2.0
/// @file
/// Tree: a VDB tree of fixed depth over a top node that is either a RootNode (unbounded
/// index space) or an InternalNode (a bounded, centered domain), with random access,
/// statistics and iterators (paper sections 2 and 3).
///
/// @code
/// vdb::FloatTree tree(/*background=*/0.0f);
/// tree.setValue(vdb::Coord(1, 2, 3), 1.0f);           // allocates nodes on demand
/// vdb::FloatTree::Accessor acc(tree);                  // cached access, one per thread
/// float v = acc.getValue(vdb::Coord(1, 2, 4));         // background: 0
/// for (auto it = tree.cbeginValueOn(); it; ++it) use(it.getCoord(), *it);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/InternalNode.h>
#include <vdb/tree/LeafIndex.h>
#include <vdb/tree/LeafNode.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/RootNode.h>
#include <vdb/tree/TopologyOps.h>

#include <atomic>
#include <memory>
#include <sstream>
#include <type_traits>
#include <utility>

namespace vdb::tree {

template <typename TreeT>
class ValueAccessor;
template <typename TreeT, ValueFilter Filter>
class TreeValueIterator;
template <typename TreeT>
class TreeLeafIterator;
template <typename TreeT>
class TreeNodeIterator;

/// A sparse volume: a tree of nodes under `TopT`, with a background value for everything that
/// is not stored.
///
/// With a RootNode on top the tree covers the whole signed 32-bit index space. With an
/// InternalNode on top it covers the fixed cube domain() centered on the origin; reads outside
/// it return the background and writes outside it throw IndexError.
///
/// Structural changes that free nodes (prune, clear, eraseValue, fill over children) advance
/// an epoch counter; every accessor of the tree compares it on each call and drops its cache
/// when it changed, so an accessor never follows a freed node, and readers never contend.
///
/// A tree can hold a leaf index (buildLeafIndex(): a hash table from leaf origin to leaf), with
/// which top-down reads and accessor misses reach a leaf in one probe instead of a walk through
/// every level. It is built on demand, not kept up to date by edits: it serves reads until the
/// epoch next advances, and leaves added after it was built are found by the walk.
///
/// Threads: concurrent const calls (and concurrent const accessors) are safe. Mutations need
/// exclusive access to the tree; threaded tools write disjoint leaves through LeafManager.
template <TopNodeType TopT>
class Tree {
public:
    using TopNodeType = TopT;
    using RootNodeType = TopT;
    using ValueType = typename TopT::ValueType;
    using BuildType = typename TopT::BuildType;
    using LeafNodeType = typename TopT::LeafNodeType;
    /// The tree of the same configuration with values of type `OtherValueT` (OpenVDB's
    /// ValueConverter): `FloatTree::ValueConverter<bool>::Type` is BoolTree.
    template <typename OtherValueT>
    struct ValueConverter {
        using Type = Tree<typename TopT::template ValueConverter<OtherValueT>::Type>;
    };

    static constexpr bool BOUNDED = !IS_ROOT_NODE<TopT>;
    static constexpr Index DEPTH = TopT::LEVEL + 1;  ///< number of levels, the top included

    using Accessor = ValueAccessor<Tree>;
    using ConstAccessor = ValueAccessor<const Tree>;
    using ValueOnIter = TreeValueIterator<Tree, ValueFilter::On>;
    using ValueOnCIter = TreeValueIterator<const Tree, ValueFilter::On>;
    using ValueOffIter = TreeValueIterator<Tree, ValueFilter::Off>;
    using ValueOffCIter = TreeValueIterator<const Tree, ValueFilter::Off>;
    using ValueAllIter = TreeValueIterator<Tree, ValueFilter::All>;
    using ValueAllCIter = TreeValueIterator<const Tree, ValueFilter::All>;
    using LeafIter = TreeLeafIterator<Tree>;
    using LeafCIter = TreeLeafIterator<const Tree>;
    using NodeIter = TreeNodeIterator<Tree>;
    using NodeCIter = TreeNodeIterator<const Tree>;

    Tree() : Tree(ValueType{}) {}
    explicit Tree(const ValueType& background)
        : mTop(makeTop(background)), mBackground(background) {}
    Tree(const Tree& other) : mTop(new TopT(*other.mTop)), mBackground(other.mBackground) {}
    Tree& operator=(const Tree& other);
    /// Takes `other`'s nodes without copying; `other` is left empty with its background.
    Tree(Tree&& other)
        : mTop(std::exchange(other.mTop, makeTop(other.mBackground))),
          mBackground(other.mBackground) {
        other.clearAllAccessors();
        other.mLeafIndex.reset();
    }
    Tree& operator=(Tree&& other) {
        if (this != &other) {
            mTop = std::exchange(other.mTop, makeTop(other.mBackground));
            mBackground = other.mBackground;
            clearAllAccessors();
            other.clearAllAccessors();
            mLeafIndex.reset();
            other.mLeafIndex.reset();
        }
        return *this;
    }
    ~Tree() = default;

    /// The index-space region the tree can store: the whole 32-bit space for a root top, else
    /// the cube [-2^(T-1), 2^(T-1) - 1]^3 where 2^T is the top node's edge in voxels.
    static constexpr CoordBBox domain() {
        if constexpr (BOUNDED) {
            return CoordBBox::createCube(Coord(-Int32(TopT::DIM >> 1)), Int32(TopT::DIM));
        } else {
            return CoordBBox::inf();
        }
    }
    static constexpr bool inDomain(const Coord& ijk) {
        if constexpr (BOUNDED) {
            constexpr uint32_t half = TopT::DIM >> 1;
            return uint32_t(ijk[0]) + half < TopT::DIM && uint32_t(ijk[1]) + half < TopT::DIM &&
                   uint32_t(ijk[2]) + half < TopT::DIM;
        } else {
            return true;
        }
    }

    const ValueType& background() const { return mBackground; }
    /// Replaces the background without touching any stored value: regions without a node or tile
    /// (and, in a bounded tree, reads outside the domain) return `value` from now on, while
    /// tiles and voxels that hold the old background keep it.
    void setBackground(const ValueType& value) {
        mBackground = value;
        if constexpr (!BOUNDED)
            mTop->setBackground(value);
    }
    TopT& topNode() { return *mTop; }
    const TopT& topNode() const { return *mTop; }
    TopT& root() { return *mTop; }
    const TopT& root() const { return *mTop; }

    // ---- Random access, top-down (an Accessor is faster for coherent access)
    ValueType getValue(const Coord& ijk) const { return get<ops::GetValue>(ijk); }
    bool isValueOn(const Coord& ijk) const { return get<ops::IsValueOn>(ijk); }
    /// Stores the value at `ijk` in `value` and returns its active state.
    bool probeValue(const Coord& ijk, ValueType& value) const {
        return get<ops::ProbeValue>(ijk, value);
    }
    /// Applies the read operation `OpT` (AccessOps.h) at the tile or the leaf (or, for an op
    /// that stops above the leaves, the node) holding `ijk`; outside a bounded tree's domain,
    /// at the background, inactive.
    template <typename OpT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> get(const Coord& ijk, ArgsT&&... args) const {
        if (!inDomain(ijk))
            return OpT::tile(mBackground, false, args...);
        if constexpr (STOP_LEVEL<OpT> == 0) {
            if (const LeafNodeType* leaf = indexedLeaf(ijk))
                return OpT::leaf(*leaf, LeafNodeType::coordToOffset(ijk), args...);
        }
        if constexpr (STOP_LEVEL<OpT> == TopT::LEVEL) {
            return applyAt<OpT>(*mTop, ijk, args...);
        } else {
            detail::NoCache none;
            return mTop->template getAndCache<OpT>(ijk, none, args...);
        }
    }
    /// Sets the value at `ijk` and activates it, allocating nodes as needed.
    void setValue(const Coord& ijk, const ValueType& value) { setValueOn(ijk, value); }
    void setValueOn(const Coord& ijk, const ValueType& value);
    void setValueOn(const Coord& ijk);
    void setValueOff(const Coord& ijk, const ValueType& value);
    void setValueOff(const Coord& ijk);
    /// Changes the value at `ijk` and keeps its active state.
    void setValueOnly(const Coord& ijk, const ValueType& value);
    void setActiveState(const Coord& ijk, bool on);
    /// Random deletion (paper 3.1): the voxel at `ijk` becomes inactive with the background
    /// value, and every node on its path left indistinguishable from the background (no child,
    /// no active value, all values background) is freed, bottom-up.
    void eraseValue(const Coord& ijk);
    /// Sets every voxel of `bbox` to `value` and `active`; where the box covers a whole child
    /// region of a node, that region becomes one tile.
    void fill(const CoordBBox& bbox, const ValueType& value, bool active = true);
    /// Replaces every node whose values lie within `tolerance` of its first value and share
    /// one active state with a tile, bottom-up (math::isApproxEqual(), exact for integers
    /// over their whole range); drops root tiles equal to the background. tools::prune() is
    /// the threaded form, which compares the spread of the values and keeps their median.
    void prune(const ValueType& tolerance = ValueType{});
    /// Frees every node: the tree holds only the background.
    void clear();
    /// True when the tree stores nothing but the background. For a bounded tree this reads the
    /// top node's whole table when it has no child and no active tile.
    bool empty() const;

    // ---- Topology booleans (paper 4.4); `other` may hold another value type but must have the
    // same node layout. Whole nodes are handled by mask operations, never voxel by voxel.
    /// Activates every value that is active in `other`. Values keep their value; regions this
    /// tree did not store get the background (or the value of the tile they fall in). An active
    /// tile of this tree over a child of `other` becomes an active child of that topology unless
    /// `preserveTiles`, which keeps the tile. O(nodes of both trees where they overlap).
    template <typename OtherTreeT>
    void topologyUnion(const OtherTreeT& other, bool preserveTiles = false);
    /// Deactivates every value that is inactive in `other`; a branch under an inactive tile of
    /// `other` is freed. Follow with prune() to drop leaves left with no active value.
    template <typename OtherTreeT>
    void topologyIntersection(const OtherTreeT& other);
    /// Deactivates every value that is active in `other`; a branch under an active tile of
    /// `other` is freed. Follow with prune() to drop leaves left with no active value.
    template <typename OtherTreeT>
    void topologyDifference(const OtherTreeT& other);

    // ---- Leaves
    LeafNodeType* probeLeaf(const Coord& ijk) {
        return const_cast<LeafNodeType*>(get<ops::ProbeLeaf>(ijk));
    }
    const LeafNodeType* probeConstLeaf(const Coord& ijk) const { return get<ops::ProbeLeaf>(ijk); }
    const LeafNodeType* probeLeaf(const Coord& ijk) const { return probeConstLeaf(ijk); }
    /// Returns the leaf that holds `ijk`, creating it (and its parents) if needed.
    LeafNodeType* touchLeaf(const Coord& ijk);

    // ---- Editing nodes (the primitives tools use instead of raw node edits)
    /// Puts `leaf` (taking ownership) into the tree at its origin, replacing the leaf or the
    /// tile that held that region; internal nodes above it are created from the tiles they
    /// replace, with those tiles' value and state. OpenVDB's addLeaf.
    /// @throw IndexError when the leaf lies outside a bounded tree's domain.
    void addLeaf(std::unique_ptr<LeafNodeType> leaf);
    /// Makes the region of the node at `level` that holds `ijk` one tile of `value` and
    /// `active` (level 1: a leaf-sized tile, ...; the top level: a root tile), creating the
    /// nodes above it from the tiles they replace and freeing any node below. OpenVDB's
    /// addTile. @pre 1 <= level <= the top level
    /// @throw IndexError when `ijk` lies outside a bounded tree's domain.
    void addTile(Index level, const Coord& ijk, const ValueType& value, bool active);

    // ---- Statistics
    Index64 activeVoxelCount() const { return mTop->onVoxelCount(); }
    /// Inactive voxels in leaves, plus the voxels of inactive tiles other than root tiles
    /// equal to the background.
    Index64 inactiveVoxelCount() const { return mTop->offVoxelCount(); }
    Index64 activeLeafVoxelCount() const { return mTop->onLeafVoxelCount(); }
    Index64 inactiveLeafVoxelCount() const { return mTop->offLeafVoxelCount(); }
    Index64 activeTileCount() const { return mTop->onTileCount(); }
    Index32 leafCount() const { return mTop->leafCount(); }
    Index32 nonLeafCount() const { return mTop->nonLeafCount(); }
    /// Bytes allocated by the tree: every node, value buffer and table, and the leaf index if
    /// one is held. O(number of nodes).
    Index64 memUsage() const {
        return sizeof(Tree) + mTop->memUsage() + (mLeafIndex ? mLeafIndex->memUsage() : 0);
    }
    /// Sets `bbox` to the bounding box of the active voxels and tiles; false when there are none.
    bool evalActiveVoxelBoundingBox(CoordBBox& bbox) const {
        bbox.reset();
        mTop->evalActiveBoundingBox(bbox);
        return !bbox.empty();
    }

    // ---- Iterators
    ValueOnIter beginValueOn();
    ValueOnCIter beginValueOn() const;
    ValueOnCIter cbeginValueOn() const;
    ValueOffIter beginValueOff();
    ValueOffCIter beginValueOff() const;
    ValueOffCIter cbeginValueOff() const;
    ValueAllIter beginValueAll();
    ValueAllCIter beginValueAll() const;
    ValueAllCIter cbeginValueAll() const;
    LeafIter beginLeaf();
    LeafCIter beginLeaf() const;
    LeafCIter cbeginLeaf() const;
    /// Every node, top first, each before its children.
    NodeIter beginNode();
    NodeCIter cbeginNode() const;

    /// Range over the leaves: `for (auto& leaf : tree.leaves())`.
    template <typename IterT>
    struct Range {
        IterT first;
        IterT begin() const { return first; }
        std::default_sentinel_t end() const { return {}; }
    };
    Range<LeafIter> leaves() { return {beginLeaf()}; }
    Range<LeafCIter> leaves() const { return {cbeginLeaf()}; }

    // ---- Leaf index
    using LeafIndexType = LeafIndex<LeafNodeType>;
    /// Builds the leaf index from the leaves the tree has now (replacing any earlier one, and
    /// so advancing the epoch: accessors drop their caches): O(leaves), 32 to 64 bytes per leaf.
    /// From then on top-down reads and writes (getValue, isValueOn, probeValue, probeLeaf, get,
    /// setValue and its siblings) and accessor misses find a leaf with one hash probe, until the
    /// next change that frees or takes out nodes (the epoch: prune, clear, eraseValue, fill over
    /// children, CSG, erosion, ...) retires it; rebuild it then. Leaves added meanwhile are not in
    /// it and are found by the walk, so reads and writes are always right.
    void buildLeafIndex();
    /// Frees the leaf index.
    void releaseLeafIndex() {
        if (mLeafIndex) {
            mLeafIndex.reset();
            clearAllAccessors();
        }
    }
    /// The leaf index when it is current (built since the epoch last advanced), else null.
    const LeafIndexType* leafIndex() const {
        const LeafIndexType* index = mLeafIndex.get();
        return index != nullptr && mLeafIndexEpoch == mEpoch.load(std::memory_order_relaxed)
                   ? index
                   : nullptr;
    }
    bool hasLeafIndex() const { return leafIndex() != nullptr; }

    // ---- Accessor registry
    /// Makes every accessor of this tree drop its cache at its next call. Code that frees
    /// nodes through the node API (rather than through Tree methods) must call this.
    void clearAllAccessors() { mEpoch.fetch_add(1, std::memory_order_relaxed); }
    /// The structural-change counter that accessors compare against.
    uint64_t epoch() const { return mEpoch.load(std::memory_order_relaxed); }
    /// The counter itself, for accessors to read without going through the tree.
    const std::atomic<uint64_t>& epochCounter() const { return mEpoch; }

    /// Throws IndexError when `ijk` is outside domain().
    static void checkDomain(const Coord& ijk) {
        if (!inDomain(ijk))
            throwOutside(ijk);
    }

private:
    static std::unique_ptr<TopT> makeTop(const ValueType& background) {
        if constexpr (BOUNDED) {
            return std::make_unique<TopT>(CenteredDomain{}, background);
        } else {
            return std::make_unique<TopT>(background);
        }
    }
    [[noreturn]] static void throwOutside(const Coord& ijk) {
        std::ostringstream msg;
        msg << "coordinate " << ijk << " is outside the tree's fixed domain " << domain();
        throw IndexError(msg.str());
    }
    // The leaf holding `ijk` when the current leaf index lists it, else null (then the walk
    // decides).
    LeafNodeType* indexedLeaf(const Coord& ijk) const {
        const LeafIndexType* index = leafIndex();
        return index != nullptr ? index->find(ijk) : nullptr;
    }
    template <typename UnchangedT, typename LeafOpT>
    void modify(const Coord& ijk, const UnchangedT& unchanged, const LeafOpT& op) {
        checkDomain(ijk);
        if (LeafNodeType* leaf = indexedLeaf(ijk)) {
            op(*leaf, LeafNodeType::coordToOffset(ijk));
            return;
        }
        detail::NoCache none;
        mTop->modifyValue(ijk, unchanged, op, none);
    }

    std::unique_ptr<TopT> mTop;
    ValueType mBackground;
    std::atomic<uint64_t> mEpoch{0};
    std::unique_ptr<LeafIndexType> mLeafIndex;  // see buildLeafIndex()
    uint64_t mLeafIndexEpoch = 0;               // the epoch it was built under
};

// ---- Implementation ---------------------------------------------------------------------------

template <TopNodeType TopT>
inline Tree<TopT>& Tree<TopT>::operator=(const Tree& other) {
    if (this != &other) {
        mTop = std::make_unique<TopT>(*other.mTop);
        mBackground = other.mBackground;
        clearAllAccessors();
        mLeafIndex.reset();
    }
    return *this;
}

template <TopNodeType TopT>
inline void Tree<TopT>::buildLeafIndex() {
    auto index = std::make_unique<LeafIndexType>();
    index->reset(leafCount());
    for (auto leaf = beginLeaf(); leaf; ++leaf)
        index->insert(&*leaf);
    // Accessors hold the index they saw at their last sync: retire them before the old index
    // is freed.
    clearAllAccessors();
    mLeafIndex = std::move(index);
    mLeafIndexEpoch = epoch();
}

template <TopNodeType TopT>
inline void Tree<TopT>::setValueOn(const Coord& ijk, const ValueType& value) {
    modify(
        ijk, [&](const ValueType& tile, bool on) { return on && tile == value; },
        [&](LeafNodeType& leaf, Index n) { leaf.setValueOn(n, value); });
}

template <TopNodeType TopT>
inline void Tree<TopT>::setValueOn(const Coord& ijk) {
    modify(
        ijk, [](const ValueType&, bool on) { return on; },
        [](LeafNodeType& leaf, Index n) { leaf.setValueOn(n); });
}

template <TopNodeType TopT>
inline void Tree<TopT>::setValueOff(const Coord& ijk, const ValueType& value) {
    modify(
        ijk, [&](const ValueType& tile, bool on) { return !on && tile == value; },
        [&](LeafNodeType& leaf, Index n) { leaf.setValueOff(n, value); });
}

template <TopNodeType TopT>
inline void Tree<TopT>::setValueOff(const Coord& ijk) {
    modify(
        ijk, [](const ValueType&, bool on) { return !on; },
        [](LeafNodeType& leaf, Index n) { leaf.setValueOff(n); });
}

template <TopNodeType TopT>
inline void Tree<TopT>::setValueOnly(const Coord& ijk, const ValueType& value) {
    modify(
        ijk, [&](const ValueType& tile, bool) { return tile == value; },
        [&](LeafNodeType& leaf, Index n) { leaf.setValueOnly(n, value); });
}

template <TopNodeType TopT>
inline void Tree<TopT>::setActiveState(const Coord& ijk, bool on) {
    modify(
        ijk, [on](const ValueType&, bool tileOn) { return tileOn == on; },
        [on](LeafNodeType& leaf, Index n) { leaf.setActiveState(n, on); });
}

template <TopNodeType TopT>
inline auto Tree<TopT>::touchLeaf(const Coord& ijk) -> LeafNodeType* {
    LeafNodeType* result = nullptr;
    modify(
        ijk, [](const ValueType&, bool) { return false; },
        [&](LeafNodeType& leaf, Index) { result = &leaf; });
    return result;
}

template <TopNodeType TopT>
inline void Tree<TopT>::addLeaf(std::unique_ptr<LeafNodeType> leaf) {
    VDB_ASSERT(leaf != nullptr);
    checkDomain(leaf->origin());
    bool replaced = false;
    tree::addLeaf(*mTop, std::move(leaf), &replaced);
    if (replaced)
        clearAllAccessors();
}

template <TopNodeType TopT>
inline void Tree<TopT>::addTile(Index level, const Coord& ijk, const ValueType& value,
                                bool active) {
    VDB_ASSERT(level >= 1 && level <= TopT::LEVEL);
    checkDomain(ijk);
    bool freed = false;
    // Dispatch the run-time level to the compile-time descent: the node at `level` is the
    // parent of the new tile's region, one level up from the tile's own level.
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        ((level == L + 1
              ? void(freed = tree::setTile(tree::touchNode<L + 1>(*mTop, ijk), ijk, value, active))
              : void()),
         ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL>{});
    if (freed)
        clearAllAccessors();
}

template <TopNodeType TopT>
inline void Tree<TopT>::eraseValue(const Coord& ijk) {
    if (!inDomain(ijk))
        return;
    bool deleted = false;
    if constexpr (BOUNDED) {
        mTop->eraseValue(ijk, mBackground, deleted);
    } else {
        mTop->eraseValue(ijk, deleted);
    }
    if (deleted)
        clearAllAccessors();
}

template <TopNodeType TopT>
inline void Tree<TopT>::fill(const CoordBBox& bbox, const ValueType& value, bool active) {
    if constexpr (IS_MASK_NODE<LeafNodeType>) {
        // In a mask tree a voxel's value is its state; tiles keep the two equal too.
        if (value != active) {
            fill(bbox, true, true);
            return;
        }
    }
    if (bbox.empty())
        return;
    if (!domain().isInside(bbox)) {
        std::ostringstream msg;
        msg << "fill box " << bbox << " extends outside the tree's fixed domain " << domain();
        throw IndexError(msg.str());
    }
    bool deleted = false;
    mTop->fill(bbox, value, active, deleted);
    if (deleted)
        clearAllAccessors();
}

template <TopNodeType TopT>
inline void Tree<TopT>::prune(const ValueType& tolerance) {
    if (mTop->prune(tolerance))
        clearAllAccessors();
}

template <TopNodeType TopT>
template <typename OtherTreeT>
inline void Tree<TopT>::topologyUnion(const OtherTreeT& other, bool preserveTiles) {
    using OtherTopT = typename OtherTreeT::TopNodeType;
    static_assert(detail::sameNodeLayout<TopT, OtherTopT>(),
                  "topologyUnion needs two trees with the same levels and node sizes");
    if constexpr (std::is_same_v<OtherTreeT, Tree>) {
        if (&other == this)
            return;
    }
    detail::topTopologyUnion(*mTop, other.topNode(), mBackground, preserveTiles);
    clearAllAccessors();
}

template <TopNodeType TopT>
template <typename OtherTreeT>
inline void Tree<TopT>::topologyIntersection(const OtherTreeT& other) {
    using OtherTopT = typename OtherTreeT::TopNodeType;
    static_assert(detail::sameNodeLayout<TopT, OtherTopT>(),
                  "topologyIntersection needs two trees with the same levels and node sizes");
    if constexpr (std::is_same_v<OtherTreeT, Tree>) {
        if (&other == this)
            return;
    }
    detail::topTopologyIntersection(*mTop, other.topNode(), mBackground);
    clearAllAccessors();
}

template <TopNodeType TopT>
template <typename OtherTreeT>
inline void Tree<TopT>::topologyDifference(const OtherTreeT& other) {
    using OtherTopT = typename OtherTreeT::TopNodeType;
    static_assert(detail::sameNodeLayout<TopT, OtherTopT>(),
                  "topologyDifference needs two trees with the same levels and node sizes");
    if constexpr (std::is_same_v<OtherTreeT, Tree>) {
        if (&other == this) {
            // The walk reads `other` while it frees nodes of this tree: work from a copy.
            const Tree copy(other);
            topologyDifference(copy);
            return;
        }
    }
    detail::topTopologyDifference(*mTop, other.topNode(), mBackground);
    clearAllAccessors();
}

template <TopNodeType TopT>
inline void Tree<TopT>::clear() {
    if constexpr (BOUNDED) {
        mTop = makeTop(mBackground);
    } else {
        mTop->clear();
    }
    clearAllAccessors();
}

template <TopNodeType TopT>
inline bool Tree<TopT>::empty() const {
    if constexpr (BOUNDED) {
        return mTop->isBackground(mBackground);
    } else {
        return mTop->empty();
    }
}

}  // namespace vdb::tree

#include <vdb/tree/TreeIterator.h>
#include <vdb/tree/ValueAccessor.h>
