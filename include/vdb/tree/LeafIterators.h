// SPDX-License-Identifier: Apache-2.0
/// @file
/// The value iterators of a leaf (paper section 3.3), written once for the three leaf classes
/// (values in an array, bools as bits, masks): LeafValueIter walks the voxels that a filter
/// selects from the leaf's value mask, and LeafIterators is the base that gives each leaf the
/// full set of begin functions. LeafNodeConcept (below) checks that a leaf class has them.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>

#include <concepts>
#include <iterator>
#include <type_traits>

namespace vdb::tree {

/// Visits the voxels of one leaf that `Filter` selects, in offset order; `pos()` is the offset.
/// The leaf class `LeafT` provides getValueMask(), getValue(Index), isValueOn(Index) and
/// offsetToGlobalCoord(Index); setValue() also needs setValueOnly(Index, value).
///
/// The On and Off iterators step through the value mask as BitMask's iterators do: each 64-bit
/// word is read once, when reached, so changing the current voxel's state is safe and changes
/// to the rest of its word are not seen.
template <typename LeafT, ValueFilter Filter, bool IsConst>
class LeafValueIter {
    using MaskIter = typename LeafT::MaskType::template Iterator<Filter>;

public:
    using NodeT = std::conditional_t<IsConst, const LeafT, LeafT>;

    LeafValueIter() = default;
    LeafValueIter(NodeT* leaf, Index pos) : mLeaf(leaf), mBit(&leaf->getValueMask(), pos) {}

    explicit operator bool() const { return bool(mBit); }
    bool operator==(std::default_sentinel_t) const { return mBit == std::default_sentinel; }
    LeafValueIter& operator++() {
        ++mBit;
        return *this;
    }

    Index pos() const { return mBit.pos(); }
    Coord getCoord() const { return mLeaf->offsetToGlobalCoord(pos()); }
    /// A reference into the leaf for array leaves, a bool for bit and mask leaves.
    decltype(auto) getValue() const { return mLeaf->getValue(pos()); }
    decltype(auto) operator*() const { return getValue(); }
    bool isValueOn() const { return mLeaf->isValueOn(pos()); }
    /// Sets the value of the current voxel, keeping its state (in a mask leaf the value is the
    /// state).
    template <typename V>
    void setValue(const V& v) const requires(!IsConst) {
        mLeaf->setValueOnly(pos(), v);
    }
    NodeT& leaf() const { return *mLeaf; }

private:
    NodeT* mLeaf = nullptr;
    MaskIter mBit;
};

/// The iterator types and begin functions of a leaf class `LeafT` (derived from this).
template <typename LeafT>
class LeafIterators {
public:
    template <ValueFilter Filter, bool IsConst>
    using ValueIter = LeafValueIter<LeafT, Filter, IsConst>;
    using ValueOnIter = ValueIter<ValueFilter::On, false>;
    using ValueOnCIter = ValueIter<ValueFilter::On, true>;
    using ValueOffIter = ValueIter<ValueFilter::Off, false>;
    using ValueOffCIter = ValueIter<ValueFilter::Off, true>;
    using ValueAllIter = ValueIter<ValueFilter::All, false>;
    using ValueAllCIter = ValueIter<ValueFilter::All, true>;

    ValueOnIter beginValueOn() { return {&self(), self().getValueMask().findFirstOn()}; }
    ValueOnCIter beginValueOn() const { return cbeginValueOn(); }
    ValueOnCIter cbeginValueOn() const { return {&self(), self().getValueMask().findFirstOn()}; }
    ValueOffIter beginValueOff() { return {&self(), self().getValueMask().findFirstOff()}; }
    ValueOffCIter beginValueOff() const { return cbeginValueOff(); }
    ValueOffCIter cbeginValueOff() const { return {&self(), self().getValueMask().findFirstOff()}; }
    ValueAllIter beginValueAll() { return {&self(), 0}; }
    ValueAllCIter beginValueAll() const { return cbeginValueAll(); }
    ValueAllCIter cbeginValueAll() const { return {&self(), 0}; }

private:
    LeafT& self() { return static_cast<LeafT&>(*this); }
    const LeafT& self() const { return static_cast<const LeafT&>(*this); }
};

/// What every leaf class provides, whatever it stores: checked for the three leaf classes
/// where they are defined.
template <typename LeafT>
concept LeafNodeConcept = requires(LeafT& leaf, const LeafT& cleaf, Index n, const Coord& ijk) {
    requires LeafT::LEVEL == 0;
    LeafT::NUM_VALUES;
    { cleaf.origin() } -> std::convertible_to<Coord>;
    {cleaf.getValueMask()};
    { cleaf.isValueOn(n) } -> std::same_as<bool>;
    { cleaf.isValueOn(ijk) } -> std::same_as<bool>;
    {cleaf.getValue(n)};
    {cleaf.getValue(ijk)};
    { cleaf.offsetToGlobalCoord(n) } -> std::same_as<Coord>;
    { LeafT::coordToOffset(ijk) } -> std::convertible_to<Index>;
    { leaf.beginValueOn() } -> std::same_as<typename LeafT::ValueOnIter>;
    { cleaf.beginValueOn() } -> std::same_as<typename LeafT::ValueOnCIter>;
    { cleaf.cbeginValueOn() } -> std::same_as<typename LeafT::ValueOnCIter>;
    { leaf.beginValueOff() } -> std::same_as<typename LeafT::ValueOffIter>;
    { cleaf.cbeginValueOff() } -> std::same_as<typename LeafT::ValueOffCIter>;
    { leaf.beginValueAll() } -> std::same_as<typename LeafT::ValueAllIter>;
    { cleaf.cbeginValueAll() } -> std::same_as<typename LeafT::ValueAllCIter>;
    { leaf.beginValueOn().leaf() } -> std::same_as<LeafT&>;
};

}  // namespace vdb::tree
