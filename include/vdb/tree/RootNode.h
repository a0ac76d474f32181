// SPDX-License-Identifier: Apache-2.0
/// @file
/// The top of an unbounded VDB tree: a sparse table of child nodes and tiles keyed by the
/// child's origin, and the background value of everywhere else (paper section 2.1).

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/InternalNode.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/RootTable.h>
#include <vdb/util/Assert.h>

#include <algorithm>
#include <vector>

namespace vdb::tree {

/// The root of a tree over the whole signed 32-bit index space.
///
/// Each entry covers one child region, an aligned cube of ChildT::DIM voxels, and holds either
/// a child node or a tile (a value and an active state). Regions without an entry hold the
/// background, inactive. The table is a hash table (TableT = HashTable, the default) or an
/// ordered map (MapTable).
///
/// Invariant: an entry holds a child or a tile, never both; keys are child origins.
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <typename ChildT, typename TableT = HashTable>
class RootNode : public NodeCounters<RootNode<ChildT, TableT>> {
public:
    using ChildNodeType = ChildT;
    using LeafNodeType = typename ChildT::LeafNodeType;
    using ValueType = typename ChildT::ValueType;
    using BuildType = typename ChildT::BuildType;
    /// The same node configuration with values of type `OtherValueT`.
    template <typename OtherValueT>
    struct ValueConverter {
        using Type = RootNode<typename ChildT::template ValueConverter<OtherValueT>::Type, TableT>;
    };
    using TablePolicy = TableT;

    static constexpr Index LEVEL = ChildT::LEVEL + 1;
    static constexpr bool IS_ROOT = true;

    /// One table entry: a child (owned) or, when `child` is null, a tile.
    struct Entry {
        ChildT* child = nullptr;
        ValueType tile{};
        bool active = false;
    };
    using Table = detail::RootTable<Entry, ChildT::TOTAL, TableT>;
    using Cursor = typename Table::Cursor;

    explicit RootNode(const ValueType& background = ValueType{}) : mBackground(background) {}
    RootNode(const RootNode& other);
    RootNode& operator=(const RootNode&) = delete;
    ~RootNode() { clear(); }

    const ValueType& background() const { return mBackground; }
    /// Replaces the value of the regions without an entry. Stored tiles and nodes keep their
    /// values, so tiles equal to the old background stop reading as background.
    void setBackground(const ValueType& value) { mBackground = value; }
    /// Returns the key (child origin) of the entry whose region holds `ijk`.
    static Coord coordToKey(const Coord& ijk) { return ijk.alignedDown(ChildT::TOTAL); }
    static constexpr bool contains(const Coord&) { return true; }

    // ---- Random access (recursive; see AccessOps.h). Regions without an entry read as the
    // background, inactive.
    /// See InternalNode::getAndCache.
    template <typename OpT, typename AccT, typename... ArgsT>
    AccessResult<OpT, LeafNodeType, ArgsT...> getAndCache(const Coord& ijk, AccT& acc,
                                                          ArgsT&&... args) const;
    /// See InternalNode::modifyValue; regions without an entry are background tiles.
    template <typename UnchangedT, typename LeafOpT, typename AccT>
    void modifyValue(const Coord& ijk, const UnchangedT& unchanged, const LeafOpT& op, AccT& acc);

    /// See InternalNode::eraseValue; entries left as plain background are removed.
    void eraseValue(const Coord& ijk, bool& deleted);
    /// See InternalNode::fill.
    void fill(const CoordBBox& bbox, const ValueType& value, bool active, bool& deleted);
    /// Prunes every child (see InternalNode::prune), then removes inactive tiles equal to the
    /// background under math::isApproxEqual()'s default tolerance (as OpenVDB does). Returns
    /// true when any node was freed.
    bool prune(const ValueType& tolerance);
    /// Deletes every entry.
    void clear();
    bool empty() const { return mTable.size() == 0; }

    // ---- Statistics (the counters: NodeCounters, NodeEdit.h)
    Index64 memUsage() const;

    // ---- Entries
    size_t entryCount() const { return mTable.size(); }
    Entry* findEntry(const Coord& key) { return mTable.find(key); }
    const Entry* findEntry(const Coord& key) const { return mTable.find(key); }
    /// Makes the region of `ijk` a tile, deleting any child there.
    void setTile(const Coord& ijk, const ValueType& value, bool active);
    /// Makes `child` (owned from now on) the entry of its region, deleting any child there.
    void setChild(ChildT* child);
    /// Releases the child of the region of `ijk` (null if none) and removes the entry.
    ChildT* stealChild(const Coord& ijk);
    /// Removes the entry of the region of `ijk`, deleting any child there; the region then reads
    /// as the background, inactive.
    void eraseEntry(const Coord& ijk) {
        const Coord key = coordToKey(ijk);
        if (Entry* e = mTable.find(key)) {
            delete e->child;
            mTable.erase(key);
        }
    }
    /// The entry keys in (x, y, z) order.
    std::vector<Coord> sortedKeys() const;

    // Cursor over all entries, in table order: for (auto c = cbegin(); valid(c); next(c)).
    Cursor cbegin() const { return mTable.begin(); }
    bool valid(Cursor c) const { return mTable.valid(c); }
    void next(Cursor& c) const { mTable.next(c); }
    const Coord& key(Cursor c) const { return mTable.key(c); }
    Entry& entry(Cursor c) { return mTable.entry(c); }
    const Entry& entry(Cursor c) const { return mTable.entry(c); }

private:
    Table mTable;
    ValueType mBackground;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename ChildT, typename TableT>
RootNode<ChildT, TableT>::RootNode(const RootNode& other) : mBackground(other.mBackground) {
    try {
        for (auto c = other.cbegin(); other.valid(c); other.next(c)) {
            const Entry& src = other.entry(c);
            Entry& dst = mTable.insert(other.key(c));
            dst.tile = src.tile;
            dst.active = src.active;
            if (src.child)
                dst.child = new ChildT(*src.child);
        }
    } catch (...) {
        clear();
        throw;
    }
}

template <typename ChildT, typename TableT>
void RootNode<ChildT, TableT>::clear() {
    for (auto c = cbegin(); valid(c); next(c))
        delete entry(c).child;
    mTable.clear();
}

template <typename ChildT, typename TableT>
template <typename OpT, typename AccT, typename... ArgsT>
auto RootNode<ChildT, TableT>::getAndCache(const Coord& ijk, AccT& acc, ArgsT&&... args) const
    -> AccessResult<OpT, LeafNodeType, ArgsT...> {
    const Entry* e = mTable.find(coordToKey(ijk));
    if (!e)
        return OpT::tile(mBackground, false, args...);
    if (!e->child)
        return OpT::tile(e->tile, e->active, args...);
    return descend<OpT>(*e->child, ijk, acc, args...);
}

template <typename ChildT, typename TableT>
template <typename UnchangedT, typename LeafOpT, typename AccT>
void RootNode<ChildT, TableT>::modifyValue(const Coord& ijk, const UnchangedT& unchanged,
                                           const LeafOpT& op, AccT& acc) {
    const Coord key = coordToKey(ijk);
    Entry* e = mTable.find(key);
    ChildT* child;
    if (e && e->child) {
        child = e->child;
    } else {
        const ValueType tile = e ? e->tile : mBackground;
        const bool active = e ? e->active : false;
        if (unchanged(tile, active))
            return;
        child = new ChildT(key, tile, active);
        Entry& entry = mTable.insert(key);
        entry.child = child;
        entry.active = false;
    }
    acc.insert(ijk, child);
    child->modifyValue(ijk, unchanged, op, acc);
}

template <typename ChildT, typename TableT>
void RootNode<ChildT, TableT>::eraseValue(const Coord& ijk, bool& deleted) {
    const Coord key = coordToKey(ijk);
    Entry* e = mTable.find(key);
    if (!e)
        return;
    if (!e->child) {
        if (!e->active && e->tile == mBackground)
            return;
        e->child = new ChildT(key, e->tile, e->active);
    }
    e->child->eraseValue(ijk, mBackground, deleted);
    if (e->child->isBackground(mBackground)) {
        delete e->child;
        mTable.erase(key);
        deleted = true;
    }
}

template <typename ChildT, typename TableT>
void RootNode<ChildT, TableT>::fill(const CoordBBox& bbox, const ValueType& value, bool active,
                                    bool& deleted) {
    if (bbox.empty())
        return;
    const Coord lo = coordToKey(bbox.min()), hi = coordToKey(bbox.max());
    // 64-bit loop counters: keys near INT32_MAX must not overflow.
    for (Int64 x = lo[0]; x <= hi[0]; x += ChildT::DIM) {
        for (Int64 y = lo[1]; y <= hi[1]; y += ChildT::DIM) {
            for (Int64 z = lo[2]; z <= hi[2]; z += ChildT::DIM) {
                const Coord key{Int32(x), Int32(y), Int32(z)};
                const CoordBBox childBox = CoordBBox::createCube(key, Int32(ChildT::DIM));
                if (bbox.isInside(childBox)) {
                    Entry& e = mTable.insert(key);
                    if (e.child) {
                        delete e.child;
                        e.child = nullptr;
                        deleted = true;
                    }
                    e.tile = value;
                    e.active = active;
                    continue;
                }
                Entry* e = mTable.find(key);
                if (!e || !e->child) {
                    const ValueType tile = e ? e->tile : mBackground;
                    const bool on = e ? e->active : false;
                    e = &mTable.insert(key);
                    e->child = new ChildT(key, tile, on);
                    e->active = false;
                }
                e->child->fill(bbox, value, active, deleted);
            }
        }
    }
}

template <typename ChildT, typename TableT>
bool RootNode<ChildT, TableT>::prune(const ValueType& tolerance) {
    bool deleted = false;
    std::vector<Coord> background;
    for (auto c = cbegin(); valid(c); next(c)) {
        Entry& e = entry(c);
        if (e.child) {
            deleted |= e.child->prune(tolerance);
            ValueType value;
            bool state;
            if (e.child->isConstant(value, state, tolerance)) {
                delete e.child;
                e.child = nullptr;
                e.tile = value;
                e.active = state;
                deleted = true;
            }
        }
        if (!e.child && !e.active && math::isApproxEqual(e.tile, mBackground)) {
            background.push_back(key(c));
        }
    }
    for (const Coord& k : background)
        mTable.erase(k);
    return deleted;
}

template <typename ChildT, typename TableT>
void RootNode<ChildT, TableT>::setTile(const Coord& ijk, const ValueType& value, bool active) {
    Entry& e = mTable.insert(coordToKey(ijk));
    delete e.child;
    e.child = nullptr;
    e.tile = value;
    e.active = active;
}

template <typename ChildT, typename TableT>
void RootNode<ChildT, TableT>::setChild(ChildT* child) {
    VDB_ASSERT(child != nullptr);
    Entry& e = mTable.insert(child->origin());
    if (e.child != child)
        delete e.child;
    e.child = child;
    e.active = false;
}

template <typename ChildT, typename TableT>
ChildT* RootNode<ChildT, TableT>::stealChild(const Coord& ijk) {
    const Coord key = coordToKey(ijk);
    Entry* e = mTable.find(key);
    if (!e || !e->child)
        return nullptr;
    ChildT* child = e->child;
    mTable.erase(key);
    return child;
}

template <typename ChildT, typename TableT>
std::vector<Coord> RootNode<ChildT, TableT>::sortedKeys() const {
    std::vector<Coord> keys;
    keys.reserve(mTable.size());
    for (auto c = cbegin(); valid(c); next(c))
        keys.push_back(key(c));
    std::sort(keys.begin(), keys.end());
    return keys;
}

template <typename ChildT, typename TableT>
Index64 RootNode<ChildT, TableT>::memUsage() const {
    Index64 bytes = sizeof(RootNode) + mTable.memUsage();
    forEachChild(*this, [&bytes](const ChildT& child) { bytes += child.memUsage(); });
    return bytes;
}

}  // namespace vdb::tree
