// SPDX-License-Identifier: Apache-2.0
/// @file
/// LeafNode<bool>: a leaf whose values are bits, one 64-bit word per 64 voxels.
/// Included by LeafNode.h; include that header instead.

#pragma once

#include <vdb/tree/LeafNode.h>

namespace vdb::tree {

/// A leaf of boolean voxels: a value mask and an activity mask, NUM_VALUES / 8 bytes each.
///
/// Same interface as the generic LeafNode except that values are returned by value and the
/// leaf has exactly one buffer (a BitMask) that is always allocated.
/// Threads: concurrent const calls are safe; any mutation needs exclusive access.
template <Index Log2Dim>
class LeafNode<bool, Log2Dim> : public LeafIterators<LeafNode<bool, Log2Dim>> {
    static_assert(Log2Dim >= 2 && Log2Dim <= 7, "leaf edge must be 4 to 128 voxels");

public:
    using ValueType = bool;
    using BuildType = bool;
    using LeafNodeType = LeafNode;
    /// The same node with values of type `OtherValueT` (OpenVDB's ValueConverter).
    template <typename OtherValueT>
    struct ValueConverter {
        using Type = LeafNode<OtherValueT, Log2Dim>;
    };

    static constexpr Index LOG2DIM = Log2Dim;
    static constexpr Index TOTAL = Log2Dim;
    static constexpr Index DIM = Index(1) << Log2Dim;
    static constexpr Index NUM_VALUES = Index(1) << (3 * Log2Dim);
    static constexpr Index NUM_VOXELS = NUM_VALUES;
    static constexpr Index LEVEL = 0;

    using MaskType = util::BitMask<NUM_VALUES>;

    explicit LeafNode(const Coord& ijk, bool value = false, bool active = false)
        : mOrigin(ijk.alignedDown(LOG2DIM)), mValueMask(active), mBuffer(value) {}

    const Coord& origin() const { return mOrigin; }
    void setOrigin(const Coord& ijk) { mOrigin = ijk.alignedDown(LOG2DIM); }
    CoordBBox getNodeBoundingBox() const { return CoordBBox::createCube(mOrigin, DIM); }
    bool contains(const Coord& ijk) const { return ijk.alignedDown(LOG2DIM) == mOrigin; }
    static Index coordToOffset(const Coord& ijk) {
        return LeafNode<float, Log2Dim>::coordToOffset(ijk);
    }
    static Coord offsetToLocalCoord(Index n) {
        return LeafNode<float, Log2Dim>::offsetToLocalCoord(n);
    }
    Coord offsetToGlobalCoord(Index n) const { return mOrigin + offsetToLocalCoord(n); }

    bool getValue(Index offset) const { return mBuffer.isOn(offset); }
    bool getValue(const Coord& ijk) const { return getValue(coordToOffset(ijk)); }
    bool isValueOn(Index offset) const { return mValueMask.isOn(offset); }
    bool isValueOn(const Coord& ijk) const { return isValueOn(coordToOffset(ijk)); }
    bool probeValue(const Coord& ijk, bool& value) const {
        const Index n = coordToOffset(ijk);
        value = mBuffer.isOn(n);
        return mValueMask.isOn(n);
    }
    void setValueOn(Index n, bool value) {
        mBuffer.set(n, value);
        mValueMask.setOn(n);
    }
    void setValueOn(const Coord& ijk, bool value) { setValueOn(coordToOffset(ijk), value); }
    void setValueOn(Index n) { mValueMask.setOn(n); }
    void setValueOn(const Coord& ijk) { mValueMask.setOn(coordToOffset(ijk)); }
    void setValueOff(Index n, bool value) {
        mBuffer.set(n, value);
        mValueMask.setOff(n);
    }
    void setValueOff(const Coord& ijk, bool value) { setValueOff(coordToOffset(ijk), value); }
    void setValueOff(Index n) { mValueMask.setOff(n); }
    void setValueOff(const Coord& ijk) { mValueMask.setOff(coordToOffset(ijk)); }
    void setValueOnly(Index n, bool value) { mBuffer.set(n, value); }
    void setValueOnly(const Coord& ijk, bool value) { setValueOnly(coordToOffset(ijk), value); }
    void setActiveState(Index n, bool on) { mValueMask.set(n, on); }
    void setActiveState(const Coord& ijk, bool on) { mValueMask.set(coordToOffset(ijk), on); }

    void fill(bool value, bool active) {
        mBuffer.set(value);
        mValueMask.set(active);
    }
    void fill(const CoordBBox& bbox, bool value, bool active) {
        CoordBBox clip = getNodeBoundingBox();
        clip.intersect(bbox);
        if (clip.empty())
            return;
        // Loop over local offsets: global coordinates may end at INT32_MAX.
        const Coord lo = clip.min() - mOrigin, hi = clip.max() - mOrigin;
        for (Int32 i = lo[0]; i <= hi[0]; ++i)
            for (Int32 j = lo[1]; j <= hi[1]; ++j)
                for (Int32 k = lo[2]; k <= hi[2]; ++k) {
                    const Index n = (Index(i) << (2 * Log2Dim)) | (Index(j) << Log2Dim) | Index(k);
                    mBuffer.set(n, value);
                    mValueMask.set(n, active);
                }
    }

    const MaskType& getValueMask() const { return mValueMask; }
    MaskType& getValueMask() { return mValueMask; }
    void setValueMask(const MaskType& mask) { mValueMask = mask; }
    Index64 onVoxelCount() const { return mValueMask.countOn(); }
    Index64 offVoxelCount() const { return mValueMask.countOff(); }
    bool isEmpty() const { return mValueMask.isOff(); }
    bool isDense() const { return mValueMask.isOn(); }
    bool isConstant(bool& first, bool& state, bool /*tolerance*/) const {
        state = mValueMask.isOn(0);
        first = mBuffer.isOn(0);
        return (state ? mValueMask.isOn() : mValueMask.isOff()) &&
               (first ? mBuffer.isOn() : mBuffer.isOff());
    }
    void evalActiveBoundingBox(CoordBBox& bbox) const {
        for (Index n : mValueMask.onBits())
            bbox.expand(offsetToGlobalCoord(n));
    }
    Index64 memUsage() const { return sizeof(LeafNode); }

    /// The value bits; one buffer, always allocated.
    Index bufferCount() const { return 1; }
    bool isAllocated() const { return true; }
    MaskType& buffer(Index = 0) { return mBuffer; }
    const MaskType& buffer(Index = 0) const { return mBuffer; }

    // Value iterators (paper 3.3): LeafIterators, the base.

private:
    Coord mOrigin;
    MaskType mValueMask;  // bit n set <=> voxel n is active
    MaskType mBuffer;     // bit n = value of voxel n
};

static_assert(LeafNodeConcept<LeafNode<bool, 3>>);

}  // namespace vdb::tree
