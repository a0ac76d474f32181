// SPDX-License-Identifier: Apache-2.0
/// @file
/// Editing a tree's nodes without caring whether a node is a RootNode (a sparse table keyed by
/// child origin, regions without an entry holding the background) or an InternalNode (a dense
/// table of slots): the primitives the tree and the tools build and change branches with.
///
///   forEachTile(node, f)      every tile entry, in the node's order; f may change value and state
///   visitBlocks(node, t, l)   the block visit: every tile (by ValueFilter) and leaf of the
///                             subtree, depth first, root entries in key order
///   forEachTileIn(node, box)  every tile of the subtree that meets a box, clipped to it
///   tileCount(node)           the tiles of a node by ValueFilter; NodeCounters: the counters
///                             of RootNode and InternalNode
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
#include <vdb/tree/NodeUtil.h>
#include <vdb/util/Assert.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>

namespace vdb::tree {

/// A tile as the walks hand it: the origin of its region, its value and state, the level of
/// the node holding it and the edge of its region in voxels. forEachTile() lets the function
/// change the value and the state (not through a const node).
template <typename ValueT>
struct TileEntry {
    Coord origin;
    ValueT value;
    bool active;
    Index level;
    Index dim;
    /// The tile's region.
    CoordBBox bbox() const { return CoordBBox::createCube(origin, Int32(dim)); }
};

namespace detail {

/// True when a value of state `active` is one that `Filter` selects.
template <ValueFilter Filter>
constexpr bool selects(bool active) {
    return Filter == ValueFilter::All || active == (Filter == ValueFilter::On);
}

/// The tile of `node` at table offset `n` (an InternalNode) or of root entry `e` at `key`.
template <typename NodeT>
auto tileAt(const NodeT& node, Index n) {
    using ValueT = typename NodeT::ValueType;
    return TileEntry<ValueT>{node.offsetToGlobalCoord(n), node.getTileValue(n), node.isTileOn(n),
                             NodeT::LEVEL, NodeT::ChildNodeType::DIM};
}
template <typename NodeT, typename EntryT>
auto tileAt(const NodeT&, const Coord& key, const EntryT& e) {
    using ValueT = typename NodeT::ValueType;
    return TileEntry<ValueT>{key, e.tile, e.active, NodeT::LEVEL, NodeT::ChildNodeType::DIM};
}

/// Scans the table of InternalNode `node` in offset order, a mask word at a time (a word of
/// children costs one test when they are not wanted): `onTile(n)` at every tile that `Filter`
/// selects and, with `Children`, `onChild(n)` at every child. The masks are read in place, not
/// copied (a bounded top's masks can be 128 MiB each); a word is read before its entries are
/// visited, so the functions may change the entries they are given.
template <ValueFilter Filter, bool Children, typename NodeT, typename TileF, typename ChildF>
void scanTable(NodeT& node, const TileF& onTile, const ChildF& onChild) {
    using Node = std::remove_const_t<NodeT>;
    const auto& children = node.getChildMask();
    const auto& on = node.getValueMask();
    for (Index w = 0; w < children.WORD_COUNT; ++w) {
        const uint64_t childWord = children.getWord(w);
        uint64_t tiles = Filter == ValueFilter::On ? on.getWord(w) : ~childWord;
        if constexpr (Filter == ValueFilter::Off)
            tiles &= ~on.getWord(w);
        for (uint64_t bits = Children ? (tiles | childWord) : tiles; bits; bits &= bits - 1) {
            const Index n = (w << 6) + Index(std::countr_zero(bits));
            if constexpr (Node::NUM_VALUES % 64 != 0) {
                if (n >= Node::NUM_VALUES)
                    break;
            }
            if (Children && ((childWord >> (n & 63)) & 1))
                onChild(n);
            else
                onTile(n);
        }
    }
}

}  // namespace detail

/// Calls `f(TileEntry&)` for every tile of `node` that `Filter` selects, in table order (a
/// RootNode's entries, not the background around them; an InternalNode's slots). Changes that
/// `f` makes to the entry's value or state are stored back unless `node` is const. Children
/// are not visited and the node's structure does not change, so `f` may read the node.
template <ValueFilter Filter = ValueFilter::All, typename NodeT, typename FuncT>
void forEachTile(NodeT& node, const FuncT& f) {
    using Node = std::remove_const_t<NodeT>;
    constexpr bool WRITE = !std::is_const_v<NodeT>;
    if constexpr (IS_ROOT_NODE<Node>) {
        for (auto c = node.cbegin(); node.valid(c); node.next(c)) {
            auto& e = node.entry(c);
            if (e.child || !detail::selects<Filter>(e.active))
                continue;
            auto tile = detail::tileAt(node, node.key(c), e);
            f(tile);
            if constexpr (WRITE) {
                e.tile = tile.value;
                e.active = tile.active;
            }
        }
    } else {
        detail::scanTable<Filter, false>(
            node,
            [&](Index n) {
                auto tile = detail::tileAt(node, n);
                f(tile);
                if constexpr (WRITE)
                    node.setTile(n, tile.value, tile.active);
            },
            [](Index) {});
    }
}

/// The block visit: every block of the subtree of `node`, depth first, each once, in the
/// order of OpenVDB's tree iterators: a RootNode's entries in (x, y, z) order of their keys,
/// an InternalNode's table in offset order, a child's blocks where the child stands.
/// `onTile(const TileEntry&)` gets every tile that `Filter` selects, `onLeaf(leaf)` every leaf
/// (whatever its values; const when `node` is). With `onLeaf` = nullptr the nodes of level 1
/// are scanned for their tiles only. The tree's structure must not change during the visit.
template <ValueFilter Filter, typename NodeT, typename TileF, typename LeafF>
void visitBlocks(NodeT& node, const TileF& onTile, const LeafF& onLeaf) {
    using Node = std::remove_const_t<NodeT>;
    using ChildT = typename Node::ChildNodeType;
    constexpr bool LEAVES = !std::is_same_v<LeafF, std::nullptr_t>;
    constexpr bool DESCEND = ChildT::LEVEL > 0 || LEAVES;
    const auto visitChild = [&](auto& child) {
        if constexpr (ChildT::LEVEL > 0) {
            visitBlocks<Filter>(child, onTile, onLeaf);
        } else if constexpr (LEAVES) {
            onLeaf(child);
        }
    };
    if constexpr (IS_ROOT_NODE<Node>) {
        for (const Coord& key : node.sortedKeys()) {
            auto& e = *node.findEntry(key);
            if (e.child) {
                if constexpr (DESCEND)
                    visitChild(*e.child);
            } else if (detail::selects<Filter>(e.active)) {
                const auto tile = detail::tileAt(node, key, e);
                onTile(tile);
            }
        }
    } else {
        detail::scanTable<Filter, DESCEND>(
            node,
            [&](Index n) {
                const auto tile = detail::tileAt(node, n);
                onTile(tile);
            },
            [&](Index n) { visitChild(*node.getChild(n)); });
    }
}

/// The block visit without leaves: `f(const TileEntry&)` for every tile of the subtree of
/// `node` that `Filter` selects, in visitBlocks() order.
template <ValueFilter Filter, typename NodeT, typename FuncT>
void visitTiles(const NodeT& node, const FuncT& f) {
    visitBlocks<Filter>(node, f, nullptr);
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

/// Calls `f(origin, part)` for every aligned cube of 2^log2 voxels that meets `box`, with
/// `part` its intersection with the box, in (x, y, z) order.
template <typename FuncT>
void forEachAlignedCube(const CoordBBox& box, Index log2, const FuncT& f) {
    const Int64 step = Int64(1) << log2;
    const Coord lo = box.min().alignedDown(log2);
    for (Int64 x = lo[0]; x <= box.max()[0]; x += step) {
        for (Int64 y = lo[1]; y <= box.max()[1]; y += step) {
            for (Int64 z = lo[2]; z <= box.max()[2]; z += step) {
                const Coord origin{Int32(x), Int32(y), Int32(z)};
                CoordBBox part = CoordBBox::createCube(origin, Int32(step));
                part.intersect(box);
                f(origin, part);
            }
        }
    }
}

/// Calls `f(part, value)` for every tile of the subtree of `node` that meets `box`, with
/// `part` the tile's region clipped to the box; leaves are skipped. Under a RootNode a region
/// without an entry counts as a tile of the background. @pre `box` lies within the node
template <typename NodeT, typename FuncT>
void forEachTileIn(const NodeT& node, const CoordBBox& box, const FuncT& f) {
    using ChildT = typename NodeT::ChildNodeType;
    forEachAlignedCube(box, ChildT::TOTAL, [&](const Coord& origin, const CoordBBox& part) {
        const ChildT* child;
        if constexpr (IS_ROOT_NODE<NodeT>) {
            const auto* e = node.findEntry(origin);
            child = e ? e->child : nullptr;
            if (!child) {
                f(part, e ? e->tile : node.background());
                return;
            }
        } else {
            const Index n = NodeT::coordToOffset(origin);
            child = node.getChild(n);
            if (!child) {
                f(part, node.getTileValue(n));
                return;
            }
        }
        if constexpr (ChildT::LEVEL > 0)
            forEachTileIn(*child, part, f);
    });
}

/// The number of tiles of `node` that `Filter` selects (an InternalNode's from its masks).
template <ValueFilter Filter, typename NodeT>
Index64 tileCount(const NodeT& node) {
    if constexpr (IS_ROOT_NODE<NodeT>) {
        Index64 count = 0;
        forEachTile<Filter>(node, [&count](const auto&) { ++count; });
        return count;
    } else {
        const Index64 on = node.getValueMask().countOn();
        const Index64 tiles = NodeT::NUM_VALUES - node.getChildMask().countOn();
        return Filter == ValueFilter::On ? on : Filter == ValueFilter::Off ? tiles - on : tiles;
    }
}

/// The counters of RootNode and InternalNode, written once over the node primitives above:
/// each of the two derives from NodeCounters of itself. Voxel counts saturate at 2^64 - 1.
template <typename NodeT>
class NodeCounters {
public:
    /// Active voxels, tiles counted by their voxels.
    Index64 onVoxelCount() const {
        return sumOverChildren(countVoxels(tileCount<ValueFilter::On>(self())),
                               [](const auto& child) { return child.onVoxelCount(); });
    }
    /// Inactive voxels, tiles counted by their voxels; a RootNode's tiles of the background
    /// value count for nothing (as in OpenVDB).
    Index64 offVoxelCount() const {
        Index64 tiles = 0;
        if constexpr (IS_ROOT_NODE<NodeT>) {
            forEachTile<ValueFilter::Off>(self(), [&](const auto& tile) {
                tiles += tile.value == self().background() ? 0 : 1;
            });
        } else {
            tiles = tileCount<ValueFilter::Off>(self());
        }
        return sumOverChildren(countVoxels(tiles),
                               [](const auto& child) { return child.offVoxelCount(); });
    }
    /// Active voxels of the leaves.
    Index64 onLeafVoxelCount() const { return leafVoxels<true>(); }
    /// Inactive voxels of the leaves.
    Index64 offLeafVoxelCount() const { return leafVoxels<false>(); }
    /// Active tiles of this node and the nodes below it.
    Index64 onTileCount() const {
        if constexpr (aboveLeaves()) {
            return tileCount<ValueFilter::On>(self());
        } else {
            return sumOverChildren(tileCount<ValueFilter::On>(self()),
                                   [](const auto& child) { return child.onTileCount(); });
        }
    }
    Index32 leafCount() const {
        if constexpr (aboveLeaves()) {
            return Index32(childCount(self()));
        } else {
            return Index32(sumOverChildren(0, [](const auto& child) { return child.leafCount(); }));
        }
    }
    /// This node and the internal nodes below it.
    Index32 nonLeafCount() const {
        if constexpr (aboveLeaves()) {
            return 1;
        } else {
            return Index32(
                sumOverChildren(1, [](const auto& child) { return child.nonLeafCount(); }));
        }
    }
    /// Expands `bbox` by the active tiles and voxels of this node and the nodes below it.
    void evalActiveBoundingBox(CoordBBox& bbox) const {
        forEachTile<ValueFilter::On>(self(), [&](const auto& tile) { bbox.expand(tile.bbox()); });
        forEachChild(self(), [&](const auto& child) {
            if (!bbox.isInside(child.getNodeBoundingBox()))
                child.evalActiveBoundingBox(bbox);
        });
    }

private:
    const NodeT& self() const { return static_cast<const NodeT&>(*this); }
    template <typename T>
    static constexpr bool IS_LEAF = std::remove_cvref_t<T>::LEVEL == 0;
    static constexpr bool aboveLeaves() { return NodeT::ChildNodeType::LEVEL == 0; }
    static Index64 countVoxels(Index64 tiles) {
        return detail::saturatingMul(tiles, NodeT::ChildNodeType::NUM_VOXELS);
    }
    template <bool On>
    Index64 leafVoxels() const {
        return sumOverChildren(0, [](const auto& child) -> Index64 {
            if constexpr (IS_LEAF<decltype(child)>) {
                return On ? child.onVoxelCount() : child.offVoxelCount();
            } else {
                return On ? child.onLeafVoxelCount() : child.offLeafVoxelCount();
            }
        });
    }
    template <typename CountF>
    Index64 sumOverChildren(Index64 total, const CountF& count) const {
        forEachChild(self(), [&](const auto& child) {
            total = detail::saturatingAdd(total, Index64(count(child)));
        });
        return total;
    }
};

}  // namespace vdb::tree
