// SPDX-License-Identifier: Apache-2.0
/// @file
/// What a node type is, in one place: the concepts a tree's top node and a whole tree satisfy,
/// whether a node is a RootNode, whether it stores bools or only states (mask trees), and the
/// node type at a given level below a node. Every layer that branches on the kind of node
/// (the tree, its topology operations, the DDA, the tools, the file reader) asks here.

#pragma once

#include <vdb/Types.h>

#include <type_traits>

namespace vdb::tree {

/// True for node types that can be the top of a tree: a RootNode or an InternalNode.
template <typename NodeT>
concept TopNodeType = requires {
    typename NodeT::ChildNodeType;
    typename NodeT::ValueType;
    NodeT::LEVEL;
};

/// A tree of any configuration: a RootNode (unbounded) or an InternalNode (bounded) on top.
template <typename TreeT>
concept VdbTree = TopNodeType<typename TreeT::TopNodeType>;

/// A tree whose values carry a sign (float, double, Int32, Int64), as level sets need.
template <typename TreeT>
concept SignedVdbTree = VdbTree<TreeT> && std::is_signed_v<typename TreeT::ValueType>;

/// True when `NodeT` is a RootNode (the top of an unbounded tree).
template <typename NodeT>
inline constexpr bool IS_ROOT_NODE = requires {
    NodeT::IS_ROOT;
};

/// True for the nodes of mask trees (value type ValueMask: states only, no values).
template <typename NodeT>
inline constexpr bool IS_MASK_NODE = std::is_same_v<typename NodeT::BuildType, ValueMask>;

/// True for the nodes of bool trees (values stored as bits).
template <typename NodeT>
inline constexpr bool IS_BOOL_NODE = std::is_same_v<typename NodeT::BuildType, bool>;

/// The node type at `Level` of the tree whose top node type is `TopT` (level 0 is the leaf).
template <typename TopT, Index Level>
struct NodeAtLevel {
    static_assert(Level <= TopT::LEVEL, "the tree has no level this high");
    using Type = typename NodeAtLevel<typename TopT::ChildNodeType, Level>::Type;
};
template <typename TopT, Index Level>
requires(TopT::LEVEL == Level) struct NodeAtLevel<TopT, Level> {
    using Type = TopT;
};
template <typename TopT, Index Level>
using NodeAtLevelT = typename NodeAtLevel<TopT, Level>::Type;

}  // namespace vdb::tree
