// SPDX-License-Identifier: Apache-2.0
/// @file
/// The two tables a RootNode can keep its entries in: an open-addressing hash table keyed by
/// the child origin (the paper's hash root), or an ordered map.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>

#include <algorithm>
#include <bit>
#include <map>
#include <vector>

namespace vdb::tree {

/// Root table policy: open addressing with linear probing on the bit-and of a hash of the
/// child origin (paper 2.1). Expected O(1) lookups; iteration follows the table's slots.
struct HashTable {};
/// Root table policy: std::map ordered by (x, y, z). O(log n) lookups; sorted iteration.
struct MapTable {};

namespace detail {

/// One interface over both policies: find/insert/erase by key, and a cursor that walks every
/// entry. `KeyLog2` is log2 of the spacing of keys (the root's child edge), used by the hash.
template <typename EntryT, Index KeyLog2, typename PolicyT>
class RootTable;

template <typename EntryT, Index KeyLog2>
class RootTable<EntryT, KeyLog2, HashTable> {
public:
    using Cursor = size_t;

    EntryT* find(const Coord& key) {
        if (mCount == 0)
            return nullptr;
        // Most keys sit in their home slot, and most absent keys find it empty (the table is
        // at most half full): those tests are inlined, the rest of the probe run is not, which
        // keeps top-down lookups short.
        Slot& s = mSlots[home(key)];
        if (!s.used)
            return nullptr;
        if (s.key == key) [[likely]]
            return &s.entry;
        return findInProbeRun(key);
    }
    const EntryT* find(const Coord& key) const { return const_cast<RootTable*>(this)->find(key); }

    /// Returns the entry of `key`, default-constructed if it was absent. Pointers to other
    /// entries and cursors are invalidated when the table grows, which only adding a key does.
    EntryT& insert(const Coord& key) {
        if (EntryT* e = find(key))
            return *e;
        if (2 * (mCount + 1) > mSlots.size())
            grow();
        for (size_t i = home(key);; i = (i + 1) & mMask) {
            Slot& s = mSlots[i];
            if (!s.used) {
                s.used = true;
                s.key = key;
                s.entry = EntryT{};
                ++mCount;
                return s.entry;
            }
            if (s.key == key)
                return s.entry;
        }
    }

    /// Removes `key` if present, shifting later entries of its probe run back (no tombstones).
    void erase(const Coord& key) {
        if (mCount == 0)
            return;
        size_t i = home(key);
        while (true) {
            if (!mSlots[i].used)
                return;
            if (mSlots[i].key == key)
                break;
            i = (i + 1) & mMask;
        }
        size_t hole = i;
        for (size_t j = (hole + 1) & mMask; mSlots[j].used; j = (j + 1) & mMask) {
            const size_t h = home(mSlots[j].key);
            // Move j into the hole unless its home lies cyclically in (hole, j].
            const bool stays = hole <= j ? (hole < h && h <= j) : (hole < h || h <= j);
            if (!stays) {
                mSlots[hole] = mSlots[j];
                hole = j;
            }
        }
        mSlots[hole].used = false;
        --mCount;
    }

    size_t size() const { return mCount; }
    void clear() {
        mSlots.clear();
        mSlots.shrink_to_fit();
        mMask = 0;
        mCount = 0;
    }
    Index64 memUsage() const { return mSlots.capacity() * sizeof(Slot); }

    Cursor begin() const { return skip(0); }
    bool valid(Cursor c) const { return c < mSlots.size(); }
    void next(Cursor& c) const { c = skip(c + 1); }
    const Coord& key(Cursor c) const { return mSlots[c].key; }
    EntryT& entry(Cursor c) { return mSlots[c].entry; }
    const EntryT& entry(Cursor c) const { return mSlots[c].entry; }

private:
    struct Slot {
        Coord key;
        bool used = false;
        EntryT entry{};
    };
    size_t home(const Coord& key) const { return size_t((key >> KeyLog2).hash()) & mMask; }
    // find() when the home slot holds another key: the whole probe run.
    [[gnu::noinline]] EntryT* findInProbeRun(const Coord& key) {
        for (size_t i = home(key);; i = (i + 1) & mMask) {
            Slot& s = mSlots[i];
            if (!s.used)
                return nullptr;
            if (s.key == key)
                return &s.entry;
        }
    }
    Cursor skip(Cursor c) const {
        while (c < mSlots.size() && !mSlots[c].used)
            ++c;
        return c;
    }
    void grow() {
        std::vector<Slot> old;
        old.swap(mSlots);
        const size_t capacity = std::max<size_t>(8, 2 * old.size());
        mSlots.assign(capacity, Slot{});
        mMask = capacity - 1;
        mCount = 0;
        for (const Slot& s : old) {
            if (s.used)
                insert(s.key) = s.entry;
        }
    }

    std::vector<Slot> mSlots;  // capacity is zero or a power of two, at most half full
    size_t mMask = 0;
    size_t mCount = 0;
};

template <typename EntryT, Index KeyLog2>
class RootTable<EntryT, KeyLog2, MapTable> {
    using Map = std::map<Coord, EntryT>;

public:
    using Cursor = typename Map::iterator;

    EntryT* find(const Coord& key) {
        auto it = mMap.find(key);
        return it == mMap.end() ? nullptr : &it->second;
    }
    const EntryT* find(const Coord& key) const { return const_cast<RootTable*>(this)->find(key); }
    EntryT& insert(const Coord& key) { return mMap[key]; }
    void erase(const Coord& key) { mMap.erase(key); }
    size_t size() const { return mMap.size(); }
    void clear() { mMap.clear(); }
    /// The entries plus the red-black tree's per-node overhead (three pointers and a colour).
    Index64 memUsage() const {
        return mMap.size() * (sizeof(typename Map::value_type) + 4 * sizeof(void*));
    }

    Cursor begin() const { return const_cast<Map&>(mMap).begin(); }
    bool valid(Cursor c) const { return c != const_cast<Map&>(mMap).end(); }
    void next(Cursor& c) const { ++c; }
    const Coord& key(Cursor c) const { return c->first; }
    EntryT& entry(Cursor c) { return c->second; }
    const EntryT& entry(Cursor c) const { return c->second; }

private:
    Map mMap;
};

}  // namespace detail
}  // namespace vdb::tree
