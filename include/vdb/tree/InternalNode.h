// SPDX-License-Identifier: Apache-2.0
/// @file
/// The middle levels of a VDB tree: a dense table of child pointers or tile values with a
/// child mask and a value mask (paper section 2.2).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/AccessOps.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/util/Assert.h>
#include <vdb/util/BitMask.h>

#include <array>
#include <cstdlib>
#include <memory>
#include <new>

namespace vdb::tree {

namespace detail {

/// An accessor stand-in for calls that cache nothing.
struct NoCache {
    template <typename NodeT>
    void insert(const Coord&, NodeT*) {}
};

/// The table of an internal node. Tables up to 32 MiB live inside the node; larger ones (the
/// 2^30-entry top of a [10,3] tree) come from calloc, so that pages never written cost no memory
/// when the background is all zero bits.
template <typename EntryT, Index64 N, bool Huge = (N * sizeof(EntryT) > (Index64(32) << 20))>
class NodeTable {
public:
    static constexpr bool ZERO_INITIALIZED = false;
    EntryT& operator[](Index64 n) { return mData[n]; }
    const EntryT& operator[](Index64 n) const { return mData[n]; }
    static constexpr Index64 heapBytes() { return 0; }

private:
    std::array<EntryT, N> mData;
};
template <typename EntryT, Index64 N>
class NodeTable<EntryT, N, true> {
public:
    static constexpr bool ZERO_INITIALIZED = true;
    NodeTable() : mData(static_cast<EntryT*>(std::calloc(N, sizeof(EntryT)))) {
        if (!mData)
            throw std::bad_alloc();
    }
    NodeTable(const NodeTable&) = delete;
    NodeTable& operator=(const NodeTable&) = delete;
    ~NodeTable() { std::free(mData); }
    EntryT& operator[](Index64 n) { return mData[n]; }
    const EntryT& operator[](Index64 n) const { return mData[n]; }
    static constexpr Index64 heapBytes() { return N * sizeof(EntryT); }

private:
    EntryT* mData;
};

}  // namespace detail

/// Tag for the constructor of the top node of a bounded tree.
struct CenteredDomain {};

/// A node at level ChildT::LEVEL + 1: a (2^Log2Dim)^3 table whose entries are either a child
/// node or a tile, a constant value (active or inactive) standing for a whole child's region.
///
/// Every lookup maps a global coordinate to its table offset with shifts and masks, so the
/// node can be entered directly from an accessor at any level (paper 3.1).
///
/// Invariants: a child-mask bit is on exactly where the table holds a child, and the value-mask
/// bit of such an entry is off. The origin is a multiple of DIM, except for the top node of a
/// bounded tree, which covers the centered cube [-DIM/2, DIM/2) (offsets wrap modulo DIM).
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <typename ChildT, Index Log2Dim>
class InternalNode : public NodeCounters<InternalNode<ChildT, Log2Dim>> {
    static_assert(Log2Dim >= 1 && Log2Dim <= 10,
                  "an internal node has 2 to 1024 children per axis");
    static_assert(Log2Dim + ChildT::TOTAL <= 30, "a node may span at most 2^30 voxels per axis");

public:
    using ChildNodeType = ChildT;
    using LeafNodeType = typename ChildT::LeafNodeType;
    using ValueType = typename ChildT::ValueType;
    using BuildType = typename ChildT::BuildType;
    /// The same node configuration with values of type `OtherValueT`.
    template <typename OtherValueT>
    struct ValueConverter {
        using Type =
            InternalNode<typename ChildT::template ValueConverter<OtherValueT>::Type, Log2Dim>;
    };

    static constexpr Index LOG2DIM = Log2Dim;
    static constexpr Index TOTAL = Log2Dim + ChildT::TOTAL;         ///< log2 of the edge in voxels
    static constexpr Index DIM = Index(1) << TOTAL;                 ///< edge length in voxels
    static constexpr Index NUM_VALUES = Index(1) << (3 * Log2Dim);  ///< table size
    static constexpr Index LEVEL = ChildT::LEVEL + 1;
    /// Voxels in the node's region; 0 when that does not fit in 64 bits (only bounded tops).
    static constexpr Index64 NUM_VOXELS = 3 * TOTAL < 64 ? Index64(1) << (3 * TOTAL) : 0;

    using MaskType = util::BitMask<NUM_VALUES>;

    /// Creates the node whose region contains `ijk`, every entry a tile of `value`, `active`.
    explicit InternalNode(const Coord& ijk, const ValueType& value = ValueType{},
                          bool active = false);
    /// Creates the top node of a bounded tree, covering [-DIM/2, DIM/2) on each axis.
    InternalNode(CenteredDomain, const ValueType& value);
    InternalNode(const InternalNode& other);
    InternalNode& operator=(const InternalNode&) = delete;
    ~InternalNode() { deleteChildren(); }

    // ---- Geometry
    const Coord& origin() const { return mOrigin; }
    CoordBBox getNodeBoundingBox() const { return CoordBBox::createCube(mOrigin, Int32(DIM)); }
    bool contains(const Coord& ijk) const {
        return uint32_t(ijk[0]) - uint32_t(mOrigin[0]) < DIM &&
               uint32_t(ijk[1]) - uint32_t(mOrigin[1]) < DIM &&
               uint32_t(ijk[2]) - uint32_t(mOrigin[2]) < DIM;
    }
    /// Maps a global coordinate to the table offset of the child region holding it.
    static Index coordToOffset(const Coord& ijk) {
        constexpr Index low = DIM - 1;
        return (((Index(ijk[0]) & low) >> ChildT::TOTAL) << (2 * Log2Dim)) |
               (((Index(ijk[1]) & low) >> ChildT::TOTAL) << Log2Dim) |
               ((Index(ijk[2]) & low) >> ChildT::TOTAL);
    }
    /// Returns the global origin of the child region at table offset `n`.
    Coord offsetToGlobalCoord(Index n) const {
        constexpr Index m = (Index(1) << Log2Dim) - 1;
        return detail::localToGlobal(mOrigin, TOTAL, n >> (2 * Log2Dim), (n >> Log2Dim) & m, n & m,
                                     ChildT::TOTAL);
    }

    // ---- Random access (recursive; see AccessOps.h)
    ValueType getValue(const Coord& ijk) const { return get<ops::GetValue>(ijk); }
    bool isValueOn(const Coord& ijk) const { return get<ops::IsValueOn>(ijk); }
    bool probeValue(const Coord& ijk, ValueType& value) const {
        return get<ops::ProbeValue>(ijk, value);
    }
    /// Applies the read operation `OpT` (AccessOps.h) at the tile or the leaf holding `ijk`.
    template <typename OpT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> get(const Coord& ijk, ArgsT&&... args) const {
        detail::NoCache none;
        return getAndCache<OpT>(ijk, none, args...);
    }
    /// get() that records in `acc` each node it passes through below this one.
    template <typename OpT, typename AccT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> getAndCache(const Coord& ijk, AccT& acc,
                                                          ArgsT&&... args) const;

    /// Descends to the voxel at `ijk` and applies `op(leaf, offset)`. On the way, a tile for
    /// which `unchanged(tileValue, tileActive)` is true ends the walk (the operation would not
    /// change it); any other tile is split into a child of its value and state.
    template <typename UnchangedT, typename LeafOpT, typename AccT>
    void modifyValue(const Coord& ijk, const UnchangedT& unchanged, const LeafOpT& op, AccT& acc);

    /// Deactivates the voxel at `ijk`, sets its value to `background`, and deletes every child
    /// on the path that is left indistinguishable from background (no child, no active value,
    /// every value equal to `background`), bottom-up. `deleted` is set when any node was freed.
    void eraseValue(const Coord& ijk, const ValueType& background, bool& deleted);

    /// Sets every voxel of `bbox` (clipped to this node) to `value` and `active`, as tiles where
    /// the box covers a whole child region. `deleted` is set when any node was freed.
    void fill(const CoordBBox& bbox, const ValueType& value, bool active, bool& deleted);

    /// Replaces with tiles the children whose values are constant within `tolerance` and share
    /// one active state, bottom-up. Returns true when any node was freed.
    bool prune(const ValueType& tolerance);
    /// True when the node has no children, its tiles share one active state and lie within
    /// `tolerance` of the first; then `first` and `state` describe the replacing tile.
    bool isConstant(ValueType& first, bool& state, const ValueType& tolerance) const;
    /// True when the node has no children and no active tile, and every tile is `background`.
    bool isBackground(const ValueType& background) const;

    // ---- Statistics (the counters: NodeCounters, NodeEdit.h)
    Index64 memUsage() const;

    // ---- Table entries (offsets are in [0, NUM_VALUES))
    const MaskType& getChildMask() const { return mChildMask; }
    const MaskType& getValueMask() const { return mValueMask; }
    bool isChild(Index n) const { return mChildMask.isOn(n); }
    bool isTileOn(Index n) const { return mValueMask.isOn(n); }
    ChildT* getChild(Index n) { return mChildMask.isOn(n) ? mTable[n].child : nullptr; }
    const ChildT* getChild(Index n) const { return mChildMask.isOn(n) ? mTable[n].child : nullptr; }
    /// The tile value at `n`. @pre !isChild(n)
    const ValueType& getTileValue(Index n) const {
        VDB_ASSERT(!isChild(n));
        return mTable[n].value;
    }
    /// Changes the value of the tile at `n`, keeping its state. @pre !isChild(n)
    void setTileValueOnly(Index n, const ValueType& value) {
        VDB_ASSERT(!isChild(n));
        mTable[n].value = value;
    }
    /// Makes entry `n` a tile, deleting any child there.
    void setTile(Index n, const ValueType& value, bool active);
    /// Sets the active states of the tiles a mask word at a time: word w of the value mask
    /// becomes `op(w, word)`, with the bits at children cleared (a child's bit stays off).
    /// Values are kept. O(NUM_VALUES / 64).
    template <typename WordOpT>
    void updateTileStates(const WordOpT& op) {
        for (Index w = 0; w < MaskType::WORD_COUNT; ++w) {
            auto& word = mValueMask.getWord(w);
            word = op(w, word) & ~mChildMask.getWord(w);
        }
    }
    /// Makes entry `n` the child `child` (taking ownership), deleting any child there.
    void setChild(Index n, ChildT* child);
    /// Releases the child at `n` to the caller and leaves a tile in its place. @pre isChild(n)
    ChildT* stealChild(Index n, const ValueType& value, bool active);
    /// Deletes every child, leaving tiles of `value`, inactive.
    void clear(const ValueType& value);

private:
    union Entry {
        ChildT* child;
        ValueType value;
        Entry() : child(nullptr) {}
    };

    void deleteChildren();
    // Makes entry n a child without touching an existing one. @pre !isChild(n)
    void attachChild(Index n, ChildT* child) {
        mTable[n].child = child;
        mChildMask.setOn(n);
        mValueMask.setOff(n);
    }

    Coord mOrigin;
    MaskType mChildMask;  // bit n on <=> mTable[n] is a child
    MaskType mValueMask;  // bit n on <=> mTable[n] is an active tile
    detail::NodeTable<Entry, NUM_VALUES> mTable;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename ChildT, Index Log2Dim>
InternalNode<ChildT, Log2Dim>::InternalNode(const Coord& ijk, const ValueType& value, bool active)
    : mOrigin(ijk.alignedDown(TOTAL)), mValueMask(active) {
    for (Index n = 0; n < NUM_VALUES; ++n)
        mTable[n].value = value;
}

template <typename ChildT, Index Log2Dim>
InternalNode<ChildT, Log2Dim>::InternalNode(CenteredDomain, const ValueType& value)
    : mOrigin(-Int32(DIM >> 1)) {
    if constexpr (decltype(mTable)::ZERO_INITIALIZED) {
        if (detail::isZeroBits(value))
            return;  // calloc'd memory already holds it
    }
    for (Index64 n = 0; n < NUM_VALUES; ++n)
        mTable[n].value = value;
}

template <typename ChildT, Index Log2Dim>
InternalNode<ChildT, Log2Dim>::InternalNode(const InternalNode& other)
    : mOrigin(other.mOrigin), mChildMask(other.mChildMask), mValueMask(other.mValueMask) {
    for (Index n = 0; n < NUM_VALUES; ++n) {
        if (mChildMask.isOn(n)) {
            mTable[n].child = nullptr;
        } else {
            mTable[n].value = other.mTable[n].value;
        }
    }
    try {
        for (Index n : mChildMask.onBits())
            mTable[n].child = new ChildT(*other.mTable[n].child);
    } catch (...) {
        deleteChildren();
        throw;
    }
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::deleteChildren() {
    for (Index n : mChildMask.onBits())
        delete mTable[n].child;
    mChildMask.setOff();
}

template <typename ChildT, Index Log2Dim>
template <typename OpT, typename AccT, typename... ArgsT>
auto InternalNode<ChildT, Log2Dim>::getAndCache(const Coord& ijk, AccT& acc, ArgsT&&... args) const
    -> AccessResult<OpT, LeafNodeType, ArgsT...> {
    const Index n = coordToOffset(ijk);
    if (!mChildMask.isOn(n))
        return OpT::tile(mTable[n].value, mValueMask.isOn(n), args...);
    return descend<OpT>(*mTable[n].child, ijk, acc, args...);
}

template <typename ChildT, Index Log2Dim>
template <typename UnchangedT, typename LeafOpT, typename AccT>
void InternalNode<ChildT, Log2Dim>::modifyValue(const Coord& ijk, const UnchangedT& unchanged,
                                                const LeafOpT& op, AccT& acc) {
    const Index n = coordToOffset(ijk);
    ChildT* child;
    if (mChildMask.isOn(n)) {
        child = mTable[n].child;
    } else {
        const bool active = mValueMask.isOn(n);
        if (unchanged(mTable[n].value, active))
            return;
        child = new ChildT(ijk, mTable[n].value, active);
        attachChild(n, child);
    }
    acc.insert(ijk, child);
    if constexpr (ChildT::LEVEL == 0) {
        op(*child, ChildT::coordToOffset(ijk));
    } else {
        child->modifyValue(ijk, unchanged, op, acc);
    }
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::eraseValue(const Coord& ijk, const ValueType& background,
                                               bool& deleted) {
    const Index n = coordToOffset(ijk);
    if (!mChildMask.isOn(n)) {
        const bool active = mValueMask.isOn(n);
        if (!active && mTable[n].value == background)
            return;
        // Split the tile so that the one voxel can change.
        attachChild(n, new ChildT(ijk, mTable[n].value, active));
    }
    ChildT* child = mTable[n].child;
    bool childIsBackground;
    if constexpr (ChildT::LEVEL == 0) {
        const Index m = ChildT::coordToOffset(ijk);
        child->setValueOff(m, background);
        childIsBackground = false;
        if (child->isEmpty()) {
            ValueType first;
            bool state;
            childIsBackground = child->isConstant(first, state, ValueType{}) && first == background;
        }
    } else {
        child->eraseValue(ijk, background, deleted);
        childIsBackground = child->isBackground(background);
    }
    if (childIsBackground) {
        delete child;
        mChildMask.setOff(n);
        mTable[n].value = background;
        deleted = true;
    }
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::fill(const CoordBBox& bbox, const ValueType& value, bool active,
                                         bool& deleted) {
    CoordBBox clip = getNodeBoundingBox();
    clip.intersect(bbox);
    if (clip.empty())
        return;
    // Child index ranges covered by the clipped box, relative to the origin. (For the centered
    // top of a bounded tree these differ from table offsets, so each child's offset is
    // computed from its global origin.)
    Index lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = (uint32_t(clip.min()[a]) - uint32_t(mOrigin[a])) >> ChildT::TOTAL;
        hi[a] = (uint32_t(clip.max()[a]) - uint32_t(mOrigin[a])) >> ChildT::TOTAL;
    }
    for (Index i = lo[0]; i <= hi[0]; ++i) {
        for (Index j = lo[1]; j <= hi[1]; ++j) {
            for (Index k = lo[2]; k <= hi[2]; ++k) {
                const Coord childOrigin =
                    mOrigin + Coord(Int32(i << ChildT::TOTAL), Int32(j << ChildT::TOTAL),
                                    Int32(k << ChildT::TOTAL));
                const Index n = coordToOffset(childOrigin);
                const CoordBBox childBox = CoordBBox::createCube(childOrigin, Int32(ChildT::DIM));
                if (clip.isInside(childBox)) {
                    if (mChildMask.isOn(n))
                        deleted = true;
                    setTile(n, value, active);
                    continue;
                }
                if (!mChildMask.isOn(n)) {
                    attachChild(n, new ChildT(childBox.min(), mTable[n].value, mValueMask.isOn(n)));
                }
                if constexpr (ChildT::LEVEL == 0) {
                    mTable[n].child->fill(clip, value, active);
                } else {
                    mTable[n].child->fill(clip, value, active, deleted);
                }
            }
        }
    }
}

template <typename ChildT, Index Log2Dim>
bool InternalNode<ChildT, Log2Dim>::prune(const ValueType& tolerance) {
    bool deleted = false;
    for (Index n : mChildMask.onBits()) {
        ChildT* child = mTable[n].child;
        if constexpr (ChildT::LEVEL > 0)
            deleted |= child->prune(tolerance);
        ValueType value;
        bool state;
        if (child->isConstant(value, state, tolerance)) {
            setTile(n, value, state);
            deleted = true;
        }
    }
    return deleted;
}

template <typename ChildT, Index Log2Dim>
bool InternalNode<ChildT, Log2Dim>::isConstant(ValueType& first, bool& state,
                                               const ValueType& tolerance) const {
    if (!mChildMask.isOff())
        return false;
    state = mValueMask.isOn(0);
    if (state ? !mValueMask.isOn() : !mValueMask.isOff())
        return false;
    first = mTable[0].value;
    for (Index n = 1; n < NUM_VALUES; ++n) {
        if (!math::isApproxEqual(mTable[n].value, first, tolerance))
            return false;
    }
    return true;
}

template <typename ChildT, Index Log2Dim>
bool InternalNode<ChildT, Log2Dim>::isBackground(const ValueType& background) const {
    if (!mChildMask.isOff() || !mValueMask.isOff())
        return false;
    for (Index n = 0; n < NUM_VALUES; ++n) {
        if (!(mTable[n].value == background))
            return false;
    }
    return true;
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::setTile(Index n, const ValueType& value, bool active) {
    if (mChildMask.isOn(n)) {
        delete mTable[n].child;
        mChildMask.setOff(n);
    }
    mTable[n].value = value;
    mValueMask.set(n, active);
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::setChild(Index n, ChildT* child) {
    VDB_ASSERT(child != nullptr);
    if (mChildMask.isOn(n)) {
        if (mTable[n].child == child)
            return;
        delete mTable[n].child;
    }
    attachChild(n, child);
}

template <typename ChildT, Index Log2Dim>
ChildT* InternalNode<ChildT, Log2Dim>::stealChild(Index n, const ValueType& value, bool active) {
    VDB_ASSERT(isChild(n));
    ChildT* child = mTable[n].child;
    mChildMask.setOff(n);
    mTable[n].value = value;
    mValueMask.set(n, active);
    return child;
}

template <typename ChildT, Index Log2Dim>
void InternalNode<ChildT, Log2Dim>::clear(const ValueType& value) {
    deleteChildren();
    mValueMask.setOff();
    for (Index n = 0; n < NUM_VALUES; ++n)
        mTable[n].value = value;
}

template <typename ChildT, Index Log2Dim>
Index64 InternalNode<ChildT, Log2Dim>::memUsage() const {
    Index64 bytes = sizeof(InternalNode) + decltype(mTable)::heapBytes();
    forEachChild(*this, [&bytes](const ChildT& child) { bytes += child.memUsage(); });
    return bytes;
}

}  // namespace vdb::tree
