// SPDX-License-Identifier: Apache-2.0
/// @file
/// The bottom level of a VDB tree: a dense brick of voxel values and an activity mask
/// (paper section 2.3). Specialisations for `bool` (values stored as bits) and `ValueMask`
/// (no values at all) follow in LeafNodeBool.h and LeafNodeMask.h.

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/LeafIterators.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/util/Assert.h>
#include <vdb/util/BitMask.h>
#include <vdb/util/BlockPool.h>
#include <vdb/util/Prefetch.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <mutex>
#include <span>
#include <type_traits>
#include <utility>

namespace vdb::tree {

/// Tag of the leaf constructor that allocates no values (a reader fills them, or attaches
/// values that are still in a file).
struct PartialCreate {};

namespace detail {
/// The lock a leaf takes to load its values from a file: one of a few stripes chosen by the
/// leaf's address, so leaves need no mutex of their own and loads of different leaves rarely
/// wait for each other.
inline std::mutex& outOfCoreMutex(const void* leaf) {
    static std::array<std::mutex, 64> stripes;
    return stripes[(reinterpret_cast<std::uintptr_t>(leaf) >> 7) % stripes.size()];
}
}  // namespace detail

/// A dense cube of (2^Log2Dim)^3 voxels at level 0 of a VDB tree.
///
/// Every voxel holds a value and an active flag. Inactive voxels keep a value too (normally the
/// tree's background), so getValue() is defined everywhere in the brick; the flags alone decide
/// what iterators and tools visit.
///
/// Voxel (i, j, k), relative to origin(), lives at offset (i * DIM + j) * DIM + k: z varies
/// fastest, and in an 8^3 leaf each 64-bit mask word is one x-slice.
///
/// Values live in 0 to 3 temporal buffers of NUM_VALUES values each, allocated as one block
/// (paper 2.3). Buffer 0 holds the values every accessor sees; buffers 1 and 2 are scratch
/// space for time integration, exchanged with swapBuffers() in O(1).
///
/// Out-of-core values (delayed loading, paper 5.4): a leaf read from a file may hold, instead of
/// its buffer, an OutOfCore record that says where its values are (the paper's "0 buffers"
/// state: no value is in memory, only the record). The first read or write of a value, of a
/// buffer or of the whole leaf loads them, once, transparently: getValue(), setValue*(),
/// buffer(), fill(), copies and iterators all see the values as if they had always been in
/// memory. Such a leaf reports one buffer. The record is reached through the data pointer with
/// its lowest bit set, so delayed loading costs no bytes per leaf and the value read path one
/// predictable branch.
///
/// @tparam ValueT   voxel type; trivially copyable.
/// @tparam Log2Dim  log2 of the edge length: 3 gives the standard 8^3 leaf.
///
/// Invariant: each component of origin() is a multiple of DIM.
/// Threads: concurrent const calls are safe, including the ones that load out-of-core values
/// (one thread loads, under a striped lock, the others wait for it); any mutation needs
/// exclusive access.
template <typename ValueT, Index Log2Dim>
class LeafNode : public LeafIterators<LeafNode<ValueT, Log2Dim>> {
    static_assert(Log2Dim >= 2 && Log2Dim <= 7, "leaf edge must be 4 to 128 voxels");
    static_assert(std::is_trivially_copyable_v<ValueT>, "leaf values must be trivially copyable");

public:
    using ValueType = ValueT;
    using BuildType = ValueT;
    using LeafNodeType = LeafNode;
    /// The same node with values of type `OtherValueT` (OpenVDB's ValueConverter).
    template <typename OtherValueT>
    struct ValueConverter {
        using Type = LeafNode<OtherValueT, Log2Dim>;
    };

    static constexpr Index LOG2DIM = Log2Dim;
    static constexpr Index TOTAL = Log2Dim;  ///< log2 of the edge length in voxels
    static constexpr Index DIM = Index(1) << Log2Dim;
    static constexpr Index NUM_VALUES = Index(1) << (3 * Log2Dim);
    static constexpr Index NUM_VOXELS = NUM_VALUES;
    static constexpr Index LEVEL = 0;
    static constexpr Index MAX_BUFFERS = 3;

    using MaskType = util::BitMask<NUM_VALUES>;
    using Buffer = std::span<ValueT, NUM_VALUES>;
    using ConstBuffer = std::span<const ValueT, NUM_VALUES>;

    /// Where the values of an out-of-core leaf are, and how to decode them (implemented by the
    /// file reader). Records are immutable once attached.
    class OutOfCore {
    public:
        virtual ~OutOfCore() = default;
        /// Writes the leaf's NUM_VALUES values, as they were stored, to `values`. It must not
        /// depend on the leaf's current state: active states may change before the load.
        /// @throw IoError when the values cannot be read.
        virtual void load(ValueT* values) const = 0;
        virtual std::unique_ptr<OutOfCore> clone() const = 0;
        /// Bytes owned by the record.
        virtual Index64 memUsage() const = 0;
    };

    /// Creates the leaf whose brick contains `ijk`, every voxel `value` and `active`.
    explicit LeafNode(const Coord& ijk, const ValueT& value = ValueT{}, bool active = false);
    /// Creates the leaf whose brick contains `ijk`, inactive, with no value buffer.
    LeafNode(PartialCreate, const Coord& ijk) : mOrigin(ijk.alignedDown(LOG2DIM)) {}
    LeafNode(const LeafNode& other);
    LeafNode& operator=(const LeafNode& other);
    ~LeafNode() { freeBlock(); }

    // ---- Geometry
    /// Returns the smallest index-space coordinate of the brick.
    const Coord& origin() const { return mOrigin; }
    void setOrigin(const Coord& ijk) { mOrigin = ijk.alignedDown(LOG2DIM); }
    CoordBBox getNodeBoundingBox() const { return CoordBBox::createCube(mOrigin, DIM); }
    bool contains(const Coord& ijk) const { return ijk.alignedDown(LOG2DIM) == mOrigin; }

    /// Maps `ijk` to its offset within the leaf that contains it; only the low Log2Dim bits of
    /// each component matter, so any coordinate is accepted.
    static Index coordToOffset(const Coord& ijk) {
        constexpr Index low = DIM - 1;
        return (((Index(ijk[0]) & low) << (2 * Log2Dim)) | ((Index(ijk[1]) & low) << Log2Dim) |
                (Index(ijk[2]) & low));
    }
    /// Returns the local (i, j, k) of `offset`.
    static Coord offsetToLocalCoord(Index offset) {
        return Coord(Int32(offset >> (2 * Log2Dim)), Int32((offset >> Log2Dim) & (DIM - 1)),
                     Int32(offset & (DIM - 1)));
    }
    /// Returns the global coordinate of the voxel at `offset`.
    Coord offsetToGlobalCoord(Index offset) const { return mOrigin + offsetToLocalCoord(offset); }

    // ---- Values and states. Offsets are in [0, NUM_VALUES).
    const ValueT& getValue(Index offset) const {
        VDB_ASSERT(offset < NUM_VALUES);
        return values()[offset];
    }
    const ValueT& getValue(const Coord& ijk) const { return getValue(coordToOffset(ijk)); }
    bool isValueOn(Index offset) const { return mValueMask.isOn(offset); }
    bool isValueOn(const Coord& ijk) const { return isValueOn(coordToOffset(ijk)); }
    /// Stores the value at `ijk` in `value` and returns its active state.
    bool probeValue(const Coord& ijk, ValueT& value) const {
        const Index n = coordToOffset(ijk);
        value = getValue(n);
        return isValueOn(n);
    }

    void setValueOn(Index offset, const ValueT& value) {
        mutableData()[offset] = value;
        mValueMask.setOn(offset);
    }
    void setValueOn(const Coord& ijk, const ValueT& value) {
        setValueOn(coordToOffset(ijk), value);
    }
    void setValueOn(Index offset) { mValueMask.setOn(offset); }
    void setValueOn(const Coord& ijk) { mValueMask.setOn(coordToOffset(ijk)); }
    void setValueOff(Index offset, const ValueT& value) {
        mutableData()[offset] = value;
        mValueMask.setOff(offset);
    }
    void setValueOff(const Coord& ijk, const ValueT& value) {
        setValueOff(coordToOffset(ijk), value);
    }
    void setValueOff(Index offset) { mValueMask.setOff(offset); }
    void setValueOff(const Coord& ijk) { mValueMask.setOff(coordToOffset(ijk)); }
    /// Changes the value and keeps the active state.
    void setValueOnly(Index offset, const ValueT& value) { mutableData()[offset] = value; }
    void setValueOnly(const Coord& ijk, const ValueT& value) {
        setValueOnly(coordToOffset(ijk), value);
    }
    void setActiveState(Index offset, bool on) { mValueMask.set(offset, on); }
    void setActiveState(const Coord& ijk, bool on) { mValueMask.set(coordToOffset(ijk), on); }

    /// Sets every voxel to `value` with state `active` (out-of-core values are dropped unread).
    void fill(const ValueT& value, bool active) {
        if (isOutOfCore()) {
            ValueT* block = allocateValues(1);
            freeBlock();
            mData = block;
        }
        std::fill_n(mutableData(), NUM_VALUES, value);
        mValueMask.set(active);
    }
    /// Sets the voxels of `bbox` (clipped to this leaf) to `value` with state `active`.
    void fill(const CoordBBox& bbox, const ValueT& value, bool active);

    // ---- Masks and statistics
    const MaskType& getValueMask() const { return mValueMask; }
    MaskType& getValueMask() { return mValueMask; }
    void setValueMask(const MaskType& mask) { mValueMask = mask; }
    Index64 onVoxelCount() const { return mValueMask.countOn(); }
    Index64 offVoxelCount() const { return mValueMask.countOff(); }
    /// True when no voxel is active.
    bool isEmpty() const { return mValueMask.isOff(); }
    /// True when every voxel is active.
    bool isDense() const { return mValueMask.isOn(); }
    /// True when the voxels share one active state and lie within `tolerance` of the first
    /// value; then `first` and `state` describe the tile that could replace this leaf.
    bool isConstant(ValueT& first, bool& state, const ValueT& tolerance) const;
    /// Grows `bbox` by the active voxels of this leaf.
    void evalActiveBoundingBox(CoordBBox& bbox) const;

    /// Bytes owned by this leaf: the node and its value buffers, or its out-of-core record.
    /// Does not load out-of-core values.
    Index64 memUsage() const;

    // ---- Temporal buffers (paper 2.3)
    Index bufferCount() const { return mBufferCount; }
    /// True when the leaf has values (at least one buffer, in memory or out of core).
    bool isAllocated() const { return mBufferCount > 0; }
    /// True when the values are still in a file (see OutOfCore); reading one loads them.
    bool isOutOfCore() const { return isRecord(loadData()); }
    /// Replaces the values by `record`, which will load them on first access.
    void setOutOfCore(std::unique_ptr<OutOfCore> record);
    /// Hints that buffer 0 will be read soon (util::prefetchRead); does nothing out of core.
    [[gnu::always_inline]] void prefetchValues() const {
        const ValueT* p = loadData();
        if (p != nullptr && !isRecord(p))
            util::prefetchRead(p, NUM_VALUES * sizeof(ValueT));
    }
    /// Loads out-of-core values now; does nothing for values in memory.
    void loadValues() const {
        if (isOutOfCore())
            (void)loadOutOfCore();
    }
    /// Returns buffer `i`; buffer 0 holds the values the tree reads. @pre i < bufferCount()
    Buffer buffer(Index i = 0) {
        VDB_ASSERT(i < mBufferCount);
        return Buffer(mutableData() + slotShift(i), NUM_VALUES);
    }
    ConstBuffer buffer(Index i = 0) const {
        VDB_ASSERT(i < mBufferCount);
        return ConstBuffer(values() + slotShift(i), NUM_VALUES);
    }
    /// Resizes to `count` buffers (0 to 3). Buffers that are kept keep their values; new ones
    /// start as copies of buffer 0; zero frees every value.
    void setBufferCount(Index count);
    /// Exchanges buffers `i` and `j` without copying values.
    void swapBuffers(Index i, Index j);

    // Value iterators (paper 3.3): LeafIterators, the base.

private:
    // mData is read with acquire and published with release, so a thread that sees values a
    // concurrent load stored also sees the values themselves.
    ValueT* loadData() const {
        return std::atomic_ref<ValueT*>(mData).load(std::memory_order_acquire);
    }
    static bool isRecord(const ValueT* p) { return reinterpret_cast<std::uintptr_t>(p) & 1u; }
    static const OutOfCore* recordOf(const ValueT* p) {
        return reinterpret_cast<const OutOfCore*>(reinterpret_cast<std::uintptr_t>(p) - 1u);
    }
    /// Buffer 0, loaded from the file first when the leaf is out of core.
    const ValueT* values() const {
        const ValueT* p = loadData();
        if (isRecord(p)) [[unlikely]]
            p = loadOutOfCore();
        VDB_ASSERT(p != nullptr);
        return p;
    }
    ValueT* mutableData() { return const_cast<ValueT*>(values()); }
    ValueT* loadOutOfCore() const;
    // Buffer i lives at block slot (mSlots >> 2i) & 3; mData points at buffer 0's slot.
    Index slotOf(Index i) const { return (mSlots >> (2 * i)) & 3u; }
    std::ptrdiff_t slotShift(Index i) const {
        return (std::ptrdiff_t(slotOf(i)) - std::ptrdiff_t(slotOf(0))) * NUM_VALUES;
    }
    ValueT* blockStart() const { return mData - std::ptrdiff_t(slotOf(0)) * NUM_VALUES; }
    // Value blocks come from the leaf pool (util/BlockPool.h), `count` buffers each.
    static constexpr std::size_t blockBytes(Index count) {
        return std::size_t(count) * NUM_VALUES * sizeof(ValueT);
    }
    static ValueT* allocateValues(Index count) {
        // Raw memory holds the values: they must be trivially copyable and destructible.
        static_assert(std::is_trivially_copyable_v<ValueT> &&
                      std::is_trivially_destructible_v<ValueT> && alignof(ValueT) <= 64);
        return static_cast<ValueT*>(util::allocateValueBlock(blockBytes(count)));
    }
    void freeBlock() {
        if (isRecord(mData))
            delete recordOf(mData);
        else if (mData)
            util::freeValueBlock(blockStart(), blockBytes(mBufferCount));
        mData = nullptr;
    }

    // Buffer 0; null when no buffer is allocated; an OutOfCore record + 1 when out of core.
    mutable ValueT* mData = nullptr;
    Coord mOrigin;              // a multiple of DIM in each component
    uint8_t mBufferCount = 0;   // 0 to MAX_BUFFERS
    uint8_t mSlots = 0b100100;  // 2 bits per buffer: its slot in the block
    MaskType mValueMask;        // bit n set <=> voxel at offset n is active
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename ValueT, Index Log2Dim>
LeafNode<ValueT, Log2Dim>::LeafNode(const Coord& ijk, const ValueT& value, bool active)
    : mData(allocateValues(1)),
      mOrigin(ijk.alignedDown(LOG2DIM)),
      mBufferCount(1),
      mValueMask(active) {
    std::fill_n(mData, NUM_VALUES, value);
}

template <typename ValueT, Index Log2Dim>
LeafNode<ValueT, Log2Dim>::LeafNode(const LeafNode& other)
    : mOrigin(other.mOrigin), mBufferCount(other.mBufferCount), mValueMask(other.mValueMask) {
    if (isRecord(other.loadData())) {
        // Copy the record, unless another thread loads the values meanwhile.
        std::lock_guard lock(detail::outOfCoreMutex(&other));
        const ValueT* p = other.mData;
        if (isRecord(p)) {
            const auto* copy = recordOf(p)->clone().release();
            mData = reinterpret_cast<ValueT*>(reinterpret_cast<std::uintptr_t>(copy) | 1u);
            return;
        }
    }
    if (mBufferCount > 0) {
        mData = allocateValues(mBufferCount);
        for (Index i = 0; i < mBufferCount; ++i) {
            std::copy_n(other.mData + other.slotShift(i), NUM_VALUES, mData + i * NUM_VALUES);
        }
    }
}

template <typename ValueT, Index Log2Dim>
LeafNode<ValueT, Log2Dim>& LeafNode<ValueT, Log2Dim>::operator=(const LeafNode& other) {
    if (this != &other) {
        LeafNode copy(other);
        std::swap(mData, copy.mData);
        std::swap(mBufferCount, copy.mBufferCount);
        std::swap(mSlots, copy.mSlots);
        mOrigin = other.mOrigin;
        mValueMask = other.mValueMask;
    }
    return *this;
}

template <typename ValueT, Index Log2Dim>
void LeafNode<ValueT, Log2Dim>::fill(const CoordBBox& bbox, const ValueT& value, bool active) {
    CoordBBox clip = getNodeBoundingBox();
    clip.intersect(bbox);
    if (clip.empty())
        return;
    const Coord lo = clip.min() - mOrigin, hi = clip.max() - mOrigin;
    ValueT* data = mutableData();
    for (Int32 i = lo[0]; i <= hi[0]; ++i) {
        for (Int32 j = lo[1]; j <= hi[1]; ++j) {
            const Index row = (Index(i) << (2 * Log2Dim)) | (Index(j) << Log2Dim);
            for (Int32 k = lo[2]; k <= hi[2]; ++k) {
                data[row | Index(k)] = value;
                mValueMask.set(row | Index(k), active);
            }
        }
    }
}

template <typename ValueT, Index Log2Dim>
bool LeafNode<ValueT, Log2Dim>::isConstant(ValueT& first, bool& state,
                                           const ValueT& tolerance) const {
    state = mValueMask.isOn(0);
    if (state ? !mValueMask.isOn() : !mValueMask.isOff())
        return false;
    const ValueT* data = values();
    first = data[0];
    if constexpr (std::is_floating_point_v<ValueT>) {
        // Rows of 64 without branches, which the compiler vectorises.
        const ValueT f = first, tol = tolerance;
        for (Index w = 0; w < NUM_VALUES; w += 64) {
            int differs = 0;
            for (Index n = w; n < w + 64; ++n)
                differs |= int(!math::isApproxEqual(data[n], f, tol));
            if (differs)
                return false;
        }
        return true;
    }
    for (Index n = 1; n < NUM_VALUES; ++n) {
        if (!math::isApproxEqual(data[n], first, tolerance))
            return false;
    }
    return true;
}

template <typename ValueT, Index Log2Dim>
void LeafNode<ValueT, Log2Dim>::evalActiveBoundingBox(CoordBBox& bbox) const {
    if (mValueMask.isOff())
        return;
    if (bbox.isInside(getNodeBoundingBox()))
        return;
    if (mValueMask.isOn()) {
        bbox.expand(getNodeBoundingBox());
        return;
    }
    // Each 64-bit word covers whole (x, y) rows of z; bound x and y from the words, z from bits.
    Coord lo{Int32(DIM)}, hi{-1};
    const auto* words = mValueMask.words();
    for (Index w = 0; w < MaskType::WORD_COUNT; ++w) {
        uint64_t bits = words[w];
        if (!bits)
            continue;
        while (bits) {
            const Index n = (w << 6) + Index(std::countr_zero(bits));
            bits &= bits - 1;
            const Coord l = offsetToLocalCoord(n);
            lo = Coord::minComponent(lo, l);
            hi = Coord::maxComponent(hi, l);
        }
    }
    bbox.expand(CoordBBox(mOrigin + lo, mOrigin + hi));
}

template <typename ValueT, Index Log2Dim>
Index64 LeafNode<ValueT, Log2Dim>::memUsage() const {
    const ValueT* p = loadData();
    if (isRecord(p)) {
        std::lock_guard lock(detail::outOfCoreMutex(this));
        p = mData;  // a concurrent load may have replaced the record
        if (isRecord(p))
            return sizeof(LeafNode) + recordOf(p)->memUsage();
    }
    return sizeof(LeafNode) + Index64(mBufferCount) * NUM_VALUES * sizeof(ValueT);
}

template <typename ValueT, Index Log2Dim>
void LeafNode<ValueT, Log2Dim>::setOutOfCore(std::unique_ptr<OutOfCore> record) {
    VDB_ASSERT(record != nullptr);
    static_assert(alignof(OutOfCore) >= 2, "the record pointer's lowest bit is the tag");
    freeBlock();
    mData = reinterpret_cast<ValueT*>(reinterpret_cast<std::uintptr_t>(record.release()) | 1u);
    mBufferCount = 1;
    mSlots = 0b100100;
}

template <typename ValueT, Index Log2Dim>
ValueT* LeafNode<ValueT, Log2Dim>::loadOutOfCore() const {
    std::lock_guard lock(detail::outOfCoreMutex(this));
    ValueT* p = mData;  // under the lock, only a loader writes mData
    if (!isRecord(p))
        return p;  // another thread loaded the values first
    const OutOfCore* record = recordOf(p);
    ValueT* loaded = allocateValues(1);
    try {
        record->load(loaded);
    } catch (...) {
        util::freeValueBlock(loaded, blockBytes(1));  // the leaf stays out of core
        throw;
    }
    std::atomic_ref<ValueT*>(mData).store(loaded, std::memory_order_release);
    delete record;
    return loaded;
}

template <typename ValueT, Index Log2Dim>
void LeafNode<ValueT, Log2Dim>::setBufferCount(Index count) {
    if (count > MAX_BUFFERS)
        throw ValueError("a leaf holds at most 3 value buffers");
    if (count == mBufferCount)
        return;
    if (count > 0 && isOutOfCore())
        loadValues();  // the kept buffer 0 must be in memory
    if (count == 0) {
        freeBlock();
        mBufferCount = 0;
        mSlots = 0b100100;
        return;
    }
    ValueT* block = allocateValues(count);
    const Index keep = std::min<Index>(count, mBufferCount);
    for (Index i = 0; i < keep; ++i) {
        std::copy_n(mData + slotShift(i), NUM_VALUES, block + i * NUM_VALUES);
    }
    // New buffers start as copies of buffer 0 (or undefined values when there was none).
    for (Index i = keep; i < count && keep > 0; ++i) {
        std::copy_n(block, NUM_VALUES, block + i * NUM_VALUES);
    }
    freeBlock();
    mData = block;
    mBufferCount = uint8_t(count);
    mSlots = 0b100100;
}

template <typename ValueT, Index Log2Dim>
void LeafNode<ValueT, Log2Dim>::swapBuffers(Index i, Index j) {
    VDB_ASSERT(i < mBufferCount && j < mBufferCount);
    if (i == j)
        return;
    ValueT* start = blockStart();
    const Index si = slotOf(i), sj = slotOf(j);
    mSlots = uint8_t((mSlots & ~((3u << (2 * i)) | (3u << (2 * j)))) | (sj << (2 * i)) |
                     (si << (2 * j)));
    mData = start + std::ptrdiff_t(slotOf(0)) * NUM_VALUES;
}

// Every leaf class keeps the one interface of LeafIterators.h (the bool and mask leaves check
// it at the end of their headers).
static_assert(LeafNodeConcept<LeafNode<float, 3>>);

}  // namespace vdb::tree

#include <vdb/tree/LeafNodeBool.h>
#include <vdb/tree/LeafNodeMask.h>
