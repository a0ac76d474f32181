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
/// An op may stop the descent at a node level instead: one with a `NodeType` (a node type of
/// the tree) has, in place of the leaf function,
///   OpT::node(node, args...)            at the node of type NodeType holding `ijk`;
/// its tile function is then called at a tile above that level (or the background). Its result
/// type is the node function's. ops::ProbeNode is one.
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
#include <vdb/math/Coord.h>

#include <utility>

namespace vdb::tree {

/// The level at which the descent of `OpT` stops: its NodeType's, else 0 (the leaves).
template <typename OpT>
consteval Index stopLevel() {
    if constexpr (requires { typename OpT::NodeType; }) {
        return OpT::NodeType::LEVEL;
    } else {
        return 0;
    }
}
template <typename OpT>
inline constexpr Index STOP_LEVEL = stopLevel<OpT>();

namespace detail {
template <typename OpT, typename LeafT, typename... ArgsT>
struct AccessResultOf {
    using Type =
        decltype(OpT::leaf(std::declval<const LeafT&>(), Index(0), std::declval<ArgsT&>()...));
};
template <typename OpT, typename LeafT, typename... ArgsT>
requires(STOP_LEVEL<OpT> > 0) struct AccessResultOf<OpT, LeafT, ArgsT...> {
    using Type = decltype(OpT::node(std::declval<const typename OpT::NodeType&>(),
                                    std::declval<ArgsT&>()...));
};
}  // namespace detail

/// The result of `OpT` in a tree of leaf type `LeafT` with extra arguments `ArgsT`.
template <typename OpT, typename LeafT, typename... ArgsT>
using AccessResult = typename detail::AccessResultOf<OpT, LeafT, ArgsT...>::Type;

/// Applies `OpT` at `node`, the node of its stop level that holds `ijk`: its leaf function at a
/// leaf, its node function above.
template <typename OpT, typename NodeT, typename... ArgsT>
decltype(auto) applyAt(const NodeT& node, const Coord& ijk, ArgsT&... args) {
    if constexpr (NodeT::LEVEL == 0) {
        return OpT::leaf(node, NodeT::coordToOffset(ijk), args...);
    } else {
        return OpT::node(node, args...);
    }
}

/// One step of the descent, from a node to its `child` that holds `ijk`: records the child in
/// `acc`, then applies `OpT` there when the child is at the op's stop level, else walks on below.
template <typename OpT, typename ChildT, typename AccT, typename... ArgsT>
decltype(auto) descend(const ChildT& child, const Coord& ijk, AccT& acc, ArgsT&... args) {
    acc.insert(ijk, &child);
    if constexpr (ChildT::LEVEL == STOP_LEVEL<OpT>) {
        return applyAt<OpT>(child, ijk, args...);
    } else {
        return child.template getAndCache<OpT>(ijk, acc, args...);
    }
}

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

/// The descent that stops at a node level: the node of type `NodeT` that holds `ijk`, or null
/// where a tile (or the background) above that level holds it. With a value argument, that
/// tile's value is stored there.
template <typename NodeT>
struct ProbeNode {
    using NodeType = NodeT;
    template <typename... ArgsT>
    static const NodeT* node(const NodeT& node, ArgsT&...) {
        return &node;
    }
    template <typename... ArgsT>
    static const NodeT* leaf(const NodeT& leaf, Index, ArgsT&...) {
        return &leaf;
    }
    template <typename ValueT>
    static const NodeT* tile(const ValueT&, bool) {
        return nullptr;
    }
    template <typename ValueT>
    static const NodeT* tile(const ValueT& tile, bool, ValueT& value) {
        value = tile;
        return nullptr;
    }
};

}  // namespace ops
}  // namespace vdb::tree
