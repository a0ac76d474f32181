// SPDX-License-Identifier: Apache-2.0
/// @file
/// The read operations of the one descent that Tree, RootNode, InternalNode and ValueAccessor
/// share: `get<OpT>(ijk, args...)` walks from wherever it starts (the top node, or the lowest
/// cached node of an accessor) to the tile or the leaf that holds `ijk` and applies `OpT` there.
/// Every read of a voxel (getValue, isValueOn, probeValue, probeLeaf) is one of these ops, so
/// the walk is written once; writes go through the nodes' modifyValue().
///
/// An op is a type with two static functions:
///   OpT::leaf(leaf, offset, args...)   at the leaf holding `ijk`, `offset` its index there;
///   OpT::tile(value, active, args...)  at the tile holding `ijk`, or the background (inactive)
///                                       where no node stores it.
/// The result type is the leaf function's; the tile function's result converts to it.
///
/// @code
/// struct IsNegative {   // a user's op: one walk, no copy of the value
///     template <typename LeafT>
///     static bool leaf(const LeafT& leaf, vdb::Index n) { return leaf.getValue(n) < 0; }
///     static bool tile(float value, bool) { return value < 0; }
/// };
/// bool inside = accessor.get<IsNegative>(ijk);
/// @endcode

#pragma once

#include <vdb/Types.h>

#include <utility>

namespace vdb::tree {

/// The result of `OpT` at a leaf of type `LeafT` with extra arguments `ArgsT`.
template <typename OpT, typename LeafT, typename... ArgsT>
using AccessResult =
    decltype(OpT::leaf(std::declval<const LeafT&>(), Index(0), std::declval<ArgsT&>()...));

namespace ops {

/// The value at `ijk`.
struct GetValue {
    template <typename LeafT>
    static auto leaf(const LeafT& leaf, Index n) -> typename LeafT::ValueType {
        return leaf.getValue(n);
    }
    template <typename ValueT>
    static const ValueT& tile(const ValueT& value, bool) {
        return value;
    }
};

/// The active state at `ijk`.
struct IsValueOn {
    template <typename LeafT>
    static bool leaf(const LeafT& leaf, Index n) {
        return leaf.isValueOn(n);
    }
    template <typename ValueT>
    static bool tile(const ValueT&, bool active) {
        return active;
    }
};

/// Stores the value at `ijk` in the argument and returns its active state.
struct ProbeValue {
    template <typename LeafT>
    static bool leaf(const LeafT& leaf, Index n, typename LeafT::ValueType& value) {
        value = leaf.getValue(n);
        return leaf.isValueOn(n);
    }
    template <typename ValueT>
    static bool tile(const ValueT& tile, bool active, ValueT& value) {
        value = tile;
        return active;
    }
};

/// The leaf that holds `ijk`, or null where a tile or the background does.
struct ProbeLeaf {
    template <typename LeafT>
    static const LeafT* leaf(const LeafT& leaf, Index) {
        return &leaf;
    }
    template <typename ValueT>
    static std::nullptr_t tile(const ValueT&, bool) {
        return nullptr;
    }
};

}  // namespace ops
}  // namespace vdb::tree
