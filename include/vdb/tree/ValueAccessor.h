// SPDX-License-Identifier: Apache-2.0
/// @file
/// ValueAccessor: random access to a tree through a cache of the last node visited at each
/// level, searched bottom-up (paper section 3.2).
///
/// @code
/// vdb::FloatTree::Accessor acc(tree);      // or ValueAccessor<const FloatTree> to read only
/// for (const vdb::Coord& ijk : coords) acc.setValue(ijk, 1.0f);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/Tree.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <tuple>
#include <type_traits>

namespace vdb::tree {

/// Random access to one tree, caching the node path of the last access.
///
/// Each level below the top keeps one node and its origin key. A lookup tries the cached leaf,
/// then the cached node above it, then the tree's leaf index when it has a current one
/// (Tree::buildLeafIndex(): one hash probe to any leaf), then the cached internal nodes
/// upwards, and only on a miss everywhere starts at the top, so spatially coherent access
/// costs a key comparison and an array read. `TreeT` may be const: such an accessor only reads.
///
/// Never dangles: every call first compares the tree's epoch with the one the cache was
/// filled under and drops the cache when they differ (the tree advances its epoch whenever
/// it frees nodes). The check reads one counter that only structural changes write, so
/// accessors on different threads never contend.
///
/// Threads: an accessor is not thread-safe; use one per thread. Any number of accessors may
/// read one tree concurrently. An accessor must not outlive its tree.
template <typename TreeT>
class ValueAccessor {
public:
    using TreeType = std::remove_const_t<TreeT>;
    using ValueType = typename TreeType::ValueType;
    using LeafNodeType = typename TreeType::LeafNodeType;
    using TopT = typename TreeType::TopNodeType;
    static constexpr bool IS_CONST = std::is_const_v<TreeT>;
    static constexpr Index TOP = TopT::LEVEL;  ///< levels 0 .. TOP-1 are cached

    explicit ValueAccessor(TreeT& tree)
        : mEpochSource(&tree.epochCounter()),
          mTree(&tree),
          mEpoch(tree.epoch()),
          mLeafIndex(tree.leafIndex()) {
        clear();
    }

    TreeT& tree() const { return *mTree; }
    /// Drops every cached node.
    void clear() const {
        mKeys.fill(Key{EMPTY_KEY, EMPTY_KEY, EMPTY_KEY});
        mNodes = {};
    }
    /// True when `ijk` lies in a cached node below the top.
    bool isCached(const Coord& ijk) const {
        sync();
        return isCachedAt<0>(ijk);
    }

    // ---- Reads
    ValueType getValue(const Coord& ijk) const { return get<ops::GetValue>(ijk); }
    bool isValueOn(const Coord& ijk) const { return get<ops::IsValueOn>(ijk); }
    /// Stores the value at `ijk` in `value` and returns its active state.
    bool probeValue(const Coord& ijk, ValueType& value) const {
        return get<ops::ProbeValue>(ijk, value);
    }
    const LeafNodeType* probeConstLeaf(const Coord& ijk) const { return get<ops::ProbeLeaf>(ijk); }
    /// Applies the read operation `OpT` (AccessOps.h) at the tile or the leaf holding `ijk`,
    /// starting at the lowest cached node that contains it.
    template <typename OpT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> get(const Coord& ijk, ArgsT&&... args) const {
        sync();
        if constexpr (STOP_LEVEL < OpT >> 0) {
            return getFrom<STOP_LEVEL<OpT>, OpT>(ijk, args...);
        } else {
            Index n;
            if (leafHit(ijk, n)) [[likely]]
                return OpT::leaf(*std::get<0>(mNodes), n, args...);
            return getMiss<OpT>(ijk[0], ijk[1], ijk[2], args...);
        }
    }

    // ---- Writes (not on a const tree); writes outside a bounded tree's domain throw IndexError
    void setValue(const Coord& ijk, const ValueType& value) requires(!IS_CONST) {
        setValueOn(ijk, value);
    }
    void setValueOn(const Coord& ijk, const ValueType& value) requires(!IS_CONST) {
        modify(
            ijk, [&](const ValueType& tile, bool on) { return on && tile == value; },
            [&](LeafNodeType& leaf, Index n) { leaf.setValueOn(n, value); });
    }
    void setValueOn(const Coord& ijk) requires(!IS_CONST) {
        modify(
            ijk, [](const ValueType&, bool on) { return on; },
            [](LeafNodeType& leaf, Index n) { leaf.setValueOn(n); });
    }
    void setValueOff(const Coord& ijk, const ValueType& value) requires(!IS_CONST) {
        modify(
            ijk, [&](const ValueType& tile, bool on) { return !on && tile == value; },
            [&](LeafNodeType& leaf, Index n) { leaf.setValueOff(n, value); });
    }
    void setValueOff(const Coord& ijk) requires(!IS_CONST) {
        modify(
            ijk, [](const ValueType&, bool on) { return !on; },
            [](LeafNodeType& leaf, Index n) { leaf.setValueOff(n); });
    }
    void setValueOnly(const Coord& ijk, const ValueType& value) requires(!IS_CONST) {
        modify(
            ijk, [&](const ValueType& tile, bool) { return tile == value; },
            [&](LeafNodeType& leaf, Index n) { leaf.setValueOnly(n, value); });
    }
    void setActiveState(const Coord& ijk, bool on) requires(!IS_CONST) {
        modify(
            ijk, [on](const ValueType&, bool tileOn) { return tileOn == on; },
            [on](LeafNodeType& leaf, Index n) { leaf.setActiveState(n, on); });
    }
    /// Random deletion; see Tree::eraseValue.
    void eraseValue(const Coord& ijk) requires(!IS_CONST) { mTree->eraseValue(ijk); }
    LeafNodeType* probeLeaf(const Coord& ijk) requires(!IS_CONST) {
        return const_cast<LeafNodeType*>(get<ops::ProbeLeaf>(ijk));
    }
    /// Returns the leaf holding `ijk`, creating it and its parents if needed.
    LeafNodeType* touchLeaf(const Coord& ijk) requires(!IS_CONST) {
        LeafNodeType* result = nullptr;
        modify(
            ijk, [](const ValueType&, bool) { return false; },
            [&](LeafNodeType& leaf, Index) { result = &leaf; });
        return result;
    }

    /// Records `node` as the cached node of its level (called by the nodes on the way down).
    template <typename NodeT>
    void insert(const Coord& ijk, NodeT* node) const {
        constexpr Index L = NodeT::LEVEL;
        std::get<L>(mNodes) = const_cast<CachedNode<L>*>(node);
        const Coord origin = ijk.alignedDown(NodeT::TOTAL);
        mKeys[L] = Key{origin[0], origin[1], origin[2]};
    }

private:
    template <Index L>
    using CachedNode =
        std::conditional_t<IS_CONST, const NodeAtLevelT<TopT, L>, NodeAtLevelT<TopT, L>>;
    template <typename Seq>
    struct CacheTuple;
    template <size_t... L>
    struct CacheTuple<std::index_sequence<L...>> {
        using Type = std::tuple<CachedNode<Index(L)>*...>;
    };
    using Nodes = typename CacheTuple<std::make_index_sequence<TOP>>::Type;

    void sync() const {
        if (mEpochSource->load(std::memory_order_relaxed) != mEpoch) [[unlikely]]
            resync();
    }
    [[gnu::noinline, gnu::cold]] void resync() const {
        clear();
        mEpoch = mTree->epoch();
        mLeafIndex = mTree->leafIndex();
    }
    // A cached node's origin, each component sign-extended to 64 bits. EMPTY_KEY marks an
    // empty level: it differs from every sign-extended 32-bit coordinate in bits 32 to 40, so
    // no coordinate hits it.
    using Key = std::array<int64_t, 3>;
    static constexpr int64_t EMPTY_KEY = int64_t(1) << 40;

    // The components of `ijk` xor the key of level L: all three are below the node's edge
    // exactly when `ijk` lies in the cached node, and then they are its local coordinates.
    template <Index L>
    [[gnu::always_inline]] std::array<uint64_t, 3> localBits(const Coord& ijk) const {
        const Key& key = mKeys[L];
        return {uint64_t(int64_t(ijk[0]) ^ key[0]), uint64_t(int64_t(ijk[1]) ^ key[1]),
                uint64_t(int64_t(ijk[2]) ^ key[2])};
    }
    // True when `ijk` lies in the cached node of level L. One branch for the three components.
    template <Index L>
    [[gnu::always_inline]] bool hit(const Coord& ijk) const {
        const auto d = localBits<L>(ijk);
        return (d[0] | d[1] | d[2]) < (uint64_t(1) << NodeAtLevelT<TopT, L>::TOTAL);
    }
    // True when `ijk` lies in the cached leaf, whose value offset is then stored in `n`: the
    // local coordinates that the key test leaves behind, so a hit costs no other arithmetic.
    [[gnu::always_inline]] bool leafHit(const Coord& ijk, Index& n) const {
        constexpr Index log2 = LeafNodeType::LOG2DIM;
        const auto d = localBits<0>(ijk);
        n = Index(d[2] + (d[1] << log2) + (d[0] << (2 * log2)));
        return (d[0] | d[1] | d[2]) < LeafNodeType::DIM;
    }
    template <Index L>
    bool isCachedAt(const Coord& ijk) const {
        if constexpr (L == TOP) {
            return false;
        } else {
            return hit<L>(ijk) || isCachedAt<L + 1>(ijk);
        }
    }

    // A miss of the cached leaf: the cached parent, then the tree's leaf index, then the walk
    // from the lowest cached node above that holds `ijk`, else from the top. Out of line, so
    // that the hit path above stays small where it is inlined; the coordinates come in three
    // registers (a Coord argument was spilled to the stack on the hit path, before the branch).
    template <typename OpT, typename... ArgsT>
    [[gnu::noinline, gnu::flatten]] AccessResult<OpT, LeafNodeType, ArgsT...> getMiss(
        Int32 x, Int32 y, Int32 z, ArgsT&... args) const {
        const Coord ijk(x, y, z);
        if constexpr (TOP > 1) {
            if (hit<1>(ijk))
                return std::get<1>(mNodes)->template getAndCache<OpT>(ijk, *this, args...);
        }
        if (CachedNode<0>* leaf = indexedLeaf(ijk)) {
            insert(ijk, leaf);
            return OpT::leaf(*leaf, LeafNodeType::coordToOffset(ijk), args...);
        }
        return getFrom<std::min<Index>(2, TOP), OpT>(ijk, args...);
    }
    template <Index L, typename OpT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> getFrom(const Coord& ijk, ArgsT&... args) const {
        if constexpr (L == TOP) {
            if (!TreeType::inDomain(ijk))
                return OpT::tile(mTree->background(), false, args...);
            if constexpr (STOP_LEVEL<OpT> == TOP) {
                return applyAt<OpT>(mTree->topNode(), ijk, args...);
            } else {
                return mTree->topNode().template getAndCache<OpT>(ijk, *this, args...);
            }
        } else {
            if (!hit<L>(ijk))
                return getFrom<L + 1, OpT>(ijk, args...);
            if constexpr (L == STOP_LEVEL<OpT>) {
                return applyAt<OpT>(*std::get<L>(mNodes), ijk, args...);
            } else {
                return std::get<L>(mNodes)->template getAndCache<OpT>(ijk, *this, args...);
            }
        }
    }

    template <typename UnchangedT, typename LeafOpT>
    void modify(const Coord& ijk, const UnchangedT& unchanged, const LeafOpT& op) {
        sync();
        modifyAt<0>(ijk, unchanged, op);
    }
    template <Index L, typename UnchangedT, typename LeafOpT>
    void modifyAt(const Coord& ijk, const UnchangedT& unchanged, const LeafOpT& op) {
        if constexpr (L == TOP) {
            TreeType::checkDomain(ijk);
            mTree->topNode().modifyValue(ijk, unchanged, op, *this);
        } else if constexpr (L == 0) {
            Index n;
            if (!leafHit(ijk, n))
                return modifyAt<1>(ijk, unchanged, op);
            op(*std::get<0>(mNodes), n);
        } else {
            if (!hit<L>(ijk)) {
                if constexpr (L == 1) {
                    if (LeafNodeType* leaf = indexedLeaf(ijk)) {
                        insert(ijk, leaf);
                        return op(*leaf, LeafNodeType::coordToOffset(ijk));
                    }
                }
                return modifyAt<L + 1>(ijk, unchanged, op);
            }
            std::get<L>(mNodes)->modifyValue(ijk, unchanged, op, *this);
        }
    }

    // The leaf holding `ijk` from the tree's leaf index, when it has a current one that lists
    // that leaf; else null.
    CachedNode<0>* indexedLeaf(const Coord& ijk) const {
        return mLeafIndex != nullptr ? mLeafIndex->find(ijk) : nullptr;
    }

    const std::atomic<uint64_t>* mEpochSource;  // the tree's epoch counter
    TreeT* mTree;
    mutable uint64_t mEpoch;
    mutable std::array<Key, TOP> mKeys;
    // The tree's leaf index when it was current at the last sync (building or releasing one
    // advances the epoch).
    mutable const typename TreeType::LeafIndexType* mLeafIndex;
    mutable Nodes mNodes;
};

}  // namespace vdb::tree
