// SPDX-License-Identifier: Apache-2.0
/// @file
/// LeafIndex: a hash table from leaf origin to leaf, so that finding the leaf that holds a
/// voxel costs one probe instead of a walk through every level of the tree.
///
/// A Tree owns at most one (Tree::buildLeafIndex()); its top-down reads and its accessors'
/// misses use it while it is current. It is a snapshot of the leaves at the time it was built,
/// tied to the tree's epoch (the counter that advances whenever nodes are freed or taken out of
/// the tree): every leaf it lists is in the tree, at that origin, for as long as the epoch has
/// not moved, and leaves added since are simply not in it (a lookup there falls back to the
/// walk and finds them). So the index is never wrong, only sometimes incomplete.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>

#include <bit>
#include <cstdint>
#include <memory>

namespace vdb::tree {

/// Open-addressing hash table (linear probing, load at most 1/2) from the origin of each leaf
/// of type `LeafT` to the leaf. A slot holds the 64-bit hash of the origin and the leaf; a
/// lookup compares the hash, then the leaf's own origin, which lies in the cache line it reads
/// next anyway. 16 bytes per slot, 32 to 64 bytes per leaf.
///
/// Threads: concurrent const calls are safe; insert() and clear() need exclusive access.
template <typename LeafT>
class LeafIndex {
public:
    LeafIndex() = default;
    LeafIndex(const LeafIndex&) = delete;
    LeafIndex& operator=(const LeafIndex&) = delete;

    /// Empties the table and sizes it for `leafCount` leaves.
    void reset(size_t leafCount) {
        size_t capacity = 16;
        while (capacity < 2 * leafCount)
            capacity *= 2;
        mSlots = std::make_unique<Slot[]>(capacity);
        mMask = capacity - 1;
        mShift = 64 - unsigned(std::countr_zero(capacity));
        mCount = 0;
    }
    /// Adds `leaf`. @pre no leaf with its origin is in the table; size() < capacity() / 2.
    void insert(LeafT* leaf) {
        const uint64_t h = hash(leaf->origin());
        size_t i = size_t(h >> mShift);
        while (mSlots[i].leaf != nullptr)
            i = (i + 1) & mMask;
        mSlots[i] = Slot{h, leaf};
        ++mCount;
    }
    /// The leaf whose brick holds `ijk`, or null when no such leaf is in the table.
    [[gnu::always_inline]] LeafT* find(const Coord& ijk) const {
        const Coord origin = ijk.alignedDown(LeafT::LOG2DIM);
        const uint64_t h = hash(origin);
        for (size_t i = size_t(h >> mShift);; i = (i + 1) & mMask) {
            const Slot& slot = mSlots[i];
            if (slot.leaf == nullptr)
                return nullptr;
            if (slot.hash == h && slot.leaf->origin() == origin) [[likely]]
                return slot.leaf;
        }
    }

    /// Calls `fn(leaf)` for every leaf in the table, in slot order.
    template <typename FnT>
    void forEachLeaf(FnT&& fn) const {
        for (size_t i = 0; i < capacity(); ++i)
            if (mSlots[i].leaf != nullptr)
                fn(*mSlots[i].leaf);
    }

    size_t size() const { return mCount; }
    size_t capacity() const { return mSlots ? mMask + 1 : 0; }
    /// Bytes of the table and this object.
    Index64 memUsage() const { return sizeof(*this) + capacity() * sizeof(Slot); }

    /// The hash of a leaf origin: the three brick coordinates, each times its own odd
    /// constant, summed. The top bits choose the slot.
    static uint64_t hash(const Coord& origin) {
        constexpr unsigned s = LeafT::LOG2DIM;
        return uint64_t(uint32_t(origin[0]) >> s) * 0x9E3779B97F4A7C15ull +
               uint64_t(uint32_t(origin[1]) >> s) * 0xC2B2AE3D27D4EB4Full +
               uint64_t(uint32_t(origin[2]) >> s) * 0x165667B19E3779F9ull;
    }

private:
    struct Slot {
        uint64_t hash = 0;
        LeafT* leaf = nullptr;
    };
    std::unique_ptr<Slot[]> mSlots;
    size_t mMask = 0;
    unsigned mShift = 64;
    size_t mCount = 0;
};

}  // namespace vdb::tree
