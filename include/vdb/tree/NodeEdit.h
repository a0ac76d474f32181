// SPDX-License-Identifier: Apache-2.0
/// @file
/// Editing a tree's nodes without caring whether a node is a RootNode (a sparse table keyed by
/// child origin, regions without an entry holding the background) or an InternalNode (a dense
/// table of slots): the primitives the tree and the tools build and change branches with.
///
///   forEachTile(node, f)      every tile entry, in the node's order; f may change value and state
///   forEachChild(node, f)     every child
///   touchChild(node, ijk)     the child holding ijk, split from the tile there when there is none
///   setChild(node, child)     a child in its region's entry, replacing what was there
///   setTile(node, ijk, v, on) a tile in the region of ijk, freeing any child there
///   addLeaf(node, leaf)       a leaf linked below node, splitting the tiles on the way
///
/// These change nodes, never a tree's accessors: after freeing a node, call the tree's
/// clearAllAccessors().

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/util/Assert.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <type_traits>

namespace vdb::tree {

/// Which tiles forEachTile() visits.
enum class TileFilter { All, Active, Inactive };

/// A tile as forEachTile() hands it to its function: the origin of its region and its value
/// and state, which the function may change (not through a const node).
template <typename ValueT>
struct TileEntry {
    Coord origin;
    ValueT value;
    bool active;
};

/// Calls `f(TileEntry&)` for every tile of `node` that `Filter` selects, in table order (a
/// RootNode's entries, not the background around them; an InternalNode's slots). Changes that
/// `f` makes to the entry's value or state are stored back unless `node` is const. Children
/// are not visited and the node's structure does not change, so `f` may read the node.
template <TileFilter Filter = TileFilter::All, typename NodeT, typename FuncT>
void forEachTile(NodeT& node, const FuncT& f) {
    using Node = std::remove_const_t<NodeT>;
    using ValueT = typename Node::ValueType;
    constexpr bool WRITE = !std::is_const_v<NodeT>;
    const auto selected = [](bool active) {
        return Filter == TileFilter::All || active == (Filter == TileFilter::Active);
    };
    if constexpr (IS_ROOT_NODE<Node>) {
        for (auto c = node.cbegin(); node.valid(c); node.next(c)) {
            auto& e = node.entry(c);
            if (e.child || !selected(e.active))
                continue;
            TileEntry<ValueT> tile{node.key(c), e.tile, e.active};
            f(tile);
            if constexpr (WRITE) {
                e.tile = tile.value;
                e.active = tile.active;
            }
        }
    } else {
        const auto visit = [&](Index n) {
            TileEntry<ValueT> tile{node.offsetToGlobalCoord(n), node.getTileValue(n),
                                   node.isTileOn(n)};
            f(tile);
            if constexpr (WRITE)
                node.setTile(n, tile.value, tile.active);
        };
        // The masks are read in place, not copied (a bounded top's masks can be 128 MiB each):
        // `f` sees only its own tile, so the write-back changes only the bit being visited.
        if constexpr (Filter == TileFilter::Active) {
            for (Index n : node.getValueMask().onBits())
                visit(n);
        } else {
            // A mask word at a time, so that a node of children costs a word test each.
            const auto& children = node.getChildMask();
            const auto& on = node.getValueMask();
            for (Index w = 0; w < children.WORD_COUNT; ++w) {
                uint64_t bits = ~children.getWord(w);
                if constexpr (Filter == TileFilter::Inactive)
                    bits &= ~on.getWord(w);
                for (; bits; bits &= bits - 1) {
                    const Index n = (w << 6) + Index(std::countr_zero(bits));
                    if (n < Node::NUM_VALUES)
                        visit(n);
                }
            }
        }
    }
}

/// Calls `f(child)` for every child of `node`, in table order.
template <typename NodeT, typename FuncT>
void forEachChild(NodeT& node, const FuncT& f) {
    if constexpr (IS_ROOT_NODE<std::remove_const_t<NodeT>>) {
        for (auto c = node.cbegin(); node.valid(c); node.next(c)) {
            if (auto* child = node.entry(c).child)
                f(*child);
        }
    } else {
        for (Index n : node.getChildMask().onBits())
            f(*node.getChild(n));
    }
}

/// The number of children of `node`.
template <typename NodeT>
size_t childCount(const NodeT& node) {
    if constexpr (IS_ROOT_NODE<NodeT>) {
        size_t count = 0;
        forEachChild(node, [&count](const auto&) { ++count; });
        return count;
    } else {
        return node.getChildMask().countOn();
    }
}

/// The child of `node` whose region holds `ijk`, or null where a tile (or, under a RootNode,
/// the background) is.
template <typename NodeT>
auto probeChild(NodeT& node, const Coord& ijk) {
    using Node = std::remove_const_t<NodeT>;
    using ChildT = typename Node::ChildNodeType;
    using Ptr = std::conditional_t<std::is_const_v<NodeT>, const ChildT*, ChildT*>;
    if constexpr (IS_ROOT_NODE<Node>) {
        const auto* e = node.findEntry(Node::coordToKey(ijk));
        return Ptr(e ? e->child : nullptr);
    } else {
        return Ptr(node.getChild(Node::coordToOffset(ijk)));
    }
}

/// The child of `node` whose region holds `ijk`. Where there is none, the tile there (under a
/// RootNode, the background, inactive, where there is no entry) is split into a new child of
/// its value and state.
template <typename NodeT>
typename NodeT::ChildNodeType& touchChild(NodeT& node, const Coord& ijk) {
    using ChildT = typename NodeT::ChildNodeType;
    if constexpr (IS_ROOT_NODE<NodeT>) {
        const Coord key = NodeT::coordToKey(ijk);
        const auto* e = node.findEntry(key);
        if (e && e->child)
            return *e->child;
        auto* child = new ChildT(key, e ? e->tile : node.background(), e ? e->active : false);
        node.setChild(child);
        return *child;
    } else {
        const Index n = NodeT::coordToOffset(ijk);
        if (ChildT* child = node.getChild(n))
            return *child;
        auto* child = new ChildT(ijk, node.getTileValue(n), node.isTileOn(n));
        node.setChild(n, child);
        return *child;
    }
}

/// Makes `child` the entry of its region of `node`, deleting any child there. Returns the
/// child, now owned by `node`. @pre the child's region lies in `node`'s.
template <typename NodeT>
typename NodeT::ChildNodeType& setChild(NodeT& node,
                                        std::unique_ptr<typename NodeT::ChildNodeType> child) {
    VDB_ASSERT(child != nullptr);
    auto* raw = child.release();
    if constexpr (IS_ROOT_NODE<NodeT>) {
        node.setChild(raw);
    } else {
        VDB_ASSERT(node.contains(raw->origin()));
        node.setChild(NodeT::coordToOffset(raw->origin()), raw);
    }
    return *raw;
}

/// Makes the region of `node` holding `ijk` a tile of `value` and `active`, deleting any child
/// there. Returns true when a child was deleted.
template <typename NodeT>
bool setTile(NodeT& node, const Coord& ijk, const typename NodeT::ValueType& value, bool active) {
    const bool freed = probeChild(node, ijk) != nullptr;
    if constexpr (IS_ROOT_NODE<NodeT>) {
        node.setTile(ijk, value, active);
    } else {
        node.setTile(NodeT::coordToOffset(ijk), value, active);
    }
    return freed;
}

/// Makes the region of `node` holding `ijk` read as the background, inactive, deleting any
/// child there: a RootNode drops the region's entry, an InternalNode stores a tile of
/// `background`. Returns true when a child was deleted.
template <typename NodeT>
bool clearRegion(NodeT& node, const Coord& ijk, const typename NodeT::ValueType& background) {
    if constexpr (IS_ROOT_NODE<NodeT>) {
        const bool freed = probeChild(node, ijk) != nullptr;
        node.eraseEntry(ijk);
        return freed;
    } else {
        return setTile(node, ijk, background, false);
    }
}

/// Descends from `node` to the node at `Level` holding `ijk`, splitting tiles into children on
/// the way (touchChild), and returns it.
template <Index Level, typename NodeT>
NodeAtLevelT<NodeT, Level>& touchNode(NodeT& node, const Coord& ijk) {
    if constexpr (NodeT::LEVEL == Level) {
        return node;
    } else {
        return touchNode<Level>(touchChild(node, ijk), ijk);
    }
}

/// Links `leaf` below `node` at the leaf's origin, splitting the tiles on the way into
/// children of their values and states, and returns it, now owned by the tree. Returns through
/// `replaced` whether a leaf there was deleted. @pre `node` contains the leaf's origin
template <typename NodeT>
typename NodeT::LeafNodeType& addLeaf(NodeT& node,
                                      std::unique_ptr<typename NodeT::LeafNodeType> leaf,
                                      bool* replaced = nullptr) {
    VDB_ASSERT(leaf != nullptr);
    auto& parent = touchNode<1>(node, leaf->origin());
    if (replaced)
        *replaced = probeChild(parent, leaf->origin()) != nullptr;
    return setChild(parent, std::move(leaf));
}

}  // namespace vdb::tree
