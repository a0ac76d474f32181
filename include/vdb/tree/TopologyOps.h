// SPDX-License-Identifier: Apache-2.0
/// @file
/// The node-level work of Tree::topologyUnion, topologyIntersection and topologyDifference
/// (paper section 4.4): boolean operations on the active states of two trees of the same node
/// layout, whose value types may differ. Included by Tree.h; not API.
///
/// Each internal node is handled with whole-mask operations on its child and value masks; the
/// walk descends only where both trees have a child, and leaves combine their value masks
/// word by word. Tiles on either side are handled without visiting voxels: a tile of the other
/// tree over a child of this one activates, keeps or frees the whole child; a child of the
/// other tree under a tile of this one is copied as topology only (never voxel by voxel).
///
/// The rules are those of OpenVDB 10:
/// - union: every value active in either tree is active; values that were inactive in this
///   tree keep their value, regions new to this tree get the background (or the value of the
///   tile they fall in). An active tile of this tree over a child of the other becomes a fully
///   active child of the same topology, unless `preserveTiles` keeps the tile.
/// - intersection: a value stays active only where the other tree is active too; a child of
///   this tree under an inactive tile of the other is freed (background tile); an active tile
///   over a child of the other takes the other child's topology.
/// - difference: a value stays active only where the other tree is inactive; a child of this
///   tree under an active tile of the other is freed (background tile).
///
/// In a mask tree (LeafNode<ValueMask>) tiles keep value == active state, as everywhere else.

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/tree/InternalNode.h>
#include <vdb/tree/LeafNode.h>
#include <vdb/tree/NodeTraits.h>
#include <vdb/tree/RootNode.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace vdb::tree::detail {

// ---- Node layout

/// True when `A` and `B` have the same levels and branching factors (value types and root
/// tables may differ), so that their nodes cover the same regions.
template <typename A, typename B>
constexpr bool sameNodeLayout() {
    if constexpr (A::LEVEL != B::LEVEL) {
        return false;
    } else if constexpr (IS_ROOT_NODE<A> != IS_ROOT_NODE<B>) {
        return false;
    } else if constexpr (IS_ROOT_NODE<A>) {
        return sameNodeLayout<typename A::ChildNodeType, typename B::ChildNodeType>();
    } else if constexpr (A::LEVEL == 0) {
        return A::LOG2DIM == B::LOG2DIM;
    } else {
        return A::LOG2DIM == B::LOG2DIM &&
               sameNodeLayout<typename A::ChildNodeType, typename B::ChildNodeType>();
    }
}

/// The value a tile of `NodeT` gets when its state becomes `active`: in mask trees the state
/// itself, elsewhere `value` (the tile keeps its value).
template <typename NodeT>
typename NodeT::ValueType tileValue(const typename NodeT::ValueType& value, bool active) {
    if constexpr (IS_MASK_NODE<NodeT>) {
        return active;
    } else {
        return value;
    }
}

// ---- Helpers on internal nodes
//
// The top node of a bounded tree can have masks of up to 2^30 bits (128 MiB), so no mask is
// copied: combinations of masks are formed a word at a time.

/// Calls fn(n) for every bit n set in the words word(0), ..., word(WORD_COUNT - 1) of a mask of
/// type MaskT. Each word is read once before its bits are visited, so fn may change the masks
/// the words come from.
template <typename MaskT, typename WordFn, typename BitFn>
void forEachOnBit(const WordFn& word, const BitFn& fn) {
    for (Index w = 0; w < MaskT::WORD_COUNT; ++w) {
        for (uint64_t bits = word(w); bits != 0; bits &= bits - 1)
            fn((w << 6) + Index(std::countr_zero(bits)));
    }
}

/// Sets the active states of the tiles of `node` a word at a time (see
/// InternalNode::updateTileStates) and, in a mask tree, the value of every changed tile to its
/// new state.
template <typename NodeT, typename WordOpT>
void updateTileStates(NodeT& node, const WordOpT& op) {
    if constexpr (IS_MASK_NODE<NodeT>) {
        node.updateTileStates([&](Index w, uint64_t word) {
            const uint64_t next = op(w, word);
            const uint64_t changed = (word ^ next) & ~node.getChildMask().getWord(w);
            for (uint64_t bits = changed; bits != 0; bits &= bits - 1) {
                const Index i = Index(std::countr_zero(bits));
                node.setTileValueOnly((w << 6) + i, ((next >> i) & 1u) != 0);
            }
            return next;
        });
    } else {
        node.updateTileStates(op);
    }
}

/// Activates every voxel and tile of the branch under `node`; values are kept.
template <typename NodeT>
void activateAll(NodeT& node) {
    if constexpr (NodeT::LEVEL == 0) {
        node.getValueMask().setOn();
    } else {
        for (Index n : node.getChildMask().onBits())
            activateAll(*node.getChild(n));
        updateTileStates(node, [](Index, uint64_t) { return ~uint64_t(0); });
    }
}

/// A new branch of type `NodeT` with the topology of `other` (same children, same active
/// states) and every value `value` (in a mask tree, every tile value its state).
template <typename NodeT, typename OtherT>
NodeT* topologyCopy(const OtherT& other, const typename NodeT::ValueType& value) {
    if constexpr (NodeT::LEVEL == 0) {
        auto leaf = std::make_unique<NodeT>(other.origin(), value, false);
        leaf->setValueMask(other.getValueMask());
        return leaf.release();
    } else {
        using ChildT = typename NodeT::ChildNodeType;
        auto node = std::make_unique<NodeT>(other.origin(), tileValue<NodeT>(value, false), false);
        for (Index n : other.getChildMask().onBits())
            node->setChild(n, topologyCopy<ChildT>(*other.getChild(n), value));
        const auto& states = other.getValueMask();
        updateTileStates(*node, [&](Index w, uint64_t) { return states.getWord(w); });
        return node.release();
    }
}

// ---- Internal nodes and leaves

template <typename NodeT, typename OtherT>
void topologyUnion(NodeT& node, const OtherT& other, bool preserveTiles) {
    if constexpr (NodeT::LEVEL == 0) {
        node.getValueMask() |= other.getValueMask();
    } else {
        using ChildT = typename NodeT::ChildNodeType;
        using MaskT = typename NodeT::MaskType;
        // Children of the other node: recurse into ours, or replace our tile by a copy of the
        // other branch's topology (fully active when our tile was active).
        for (Index n : other.getChildMask().onBits()) {
            if (node.isChild(n)) {
                topologyUnion(*node.getChild(n), *other.getChild(n), preserveTiles);
            } else if (!preserveTiles || !node.isTileOn(n)) {
                const bool on = node.isTileOn(n);
                auto child = std::unique_ptr<ChildT>(
                    topologyCopy<ChildT>(*other.getChild(n), node.getTileValue(n)));
                if (on)
                    activateAll(*child);
                node.setChild(n, child.release());
            }
        }
        // Active tiles of the other node over our children activate the whole child.
        const auto& otherStates = other.getValueMask();
        forEachOnBit<MaskT>(
            [&](Index w) { return otherStates.getWord(w) & node.getChildMask().getWord(w); },
            [&](Index n) { activateAll(*node.getChild(n)); });
        // Our remaining tiles: active where either is an active tile.
        updateTileStates(node,
                         [&](Index w, uint64_t word) { return word | otherStates.getWord(w); });
    }
}

template <typename NodeT, typename OtherT>
void topologyIntersection(NodeT& node, const OtherT& other,
                          const typename NodeT::ValueType& background) {
    if constexpr (NodeT::LEVEL == 0) {
        node.getValueMask() &= other.getValueMask();
    } else {
        using ChildT = typename NodeT::ChildNodeType;
        using MaskT = typename NodeT::MaskType;
        // Our children: recurse where the other has a child, free them under its inactive
        // tiles, keep them unchanged under its active tiles.
        forEachOnBit<MaskT>([&](Index w) { return node.getChildMask().getWord(w); },
                            [&](Index n) {
                                if (other.isChild(n)) {
                                    topologyIntersection(*node.getChild(n), *other.getChild(n),
                                                         background);
                                } else if (!other.isTileOn(n)) {
                                    node.setTile(n, background, false);
                                }
                            });
        // Our active tiles over the other's children take that child's topology.
        forEachOnBit<MaskT>(
            [&](Index w) {
                return node.getValueMask().getWord(w) & other.getChildMask().getWord(w);
            },
            [&](Index n) {
                node.setChild(n, topologyCopy<ChildT>(*other.getChild(n), node.getTileValue(n)));
            });
        const auto& otherStates = other.getValueMask();
        updateTileStates(node,
                         [&](Index w, uint64_t word) { return word & otherStates.getWord(w); });
    }
}

template <typename NodeT, typename OtherT>
void topologyDifference(NodeT& node, const OtherT& other,
                        const typename NodeT::ValueType& background) {
    if constexpr (NodeT::LEVEL == 0) {
        node.getValueMask() -= other.getValueMask();
    } else {
        using ChildT = typename NodeT::ChildNodeType;
        using MaskT = typename NodeT::MaskType;
        // Our children: recurse where the other has a child, free them under its active tiles.
        forEachOnBit<MaskT>([&](Index w) { return node.getChildMask().getWord(w); },
                            [&](Index n) {
                                if (other.isChild(n)) {
                                    topologyDifference(*node.getChild(n), *other.getChild(n),
                                                       background);
                                } else if (other.isTileOn(n)) {
                                    node.setTile(n, background, false);
                                }
                            });
        // Our active tiles over the other's children become active children, then lose what
        // the other child has active.
        forEachOnBit<MaskT>(
            [&](Index w) {
                return node.getValueMask().getWord(w) & other.getChildMask().getWord(w);
            },
            [&](Index n) {
                auto child = std::make_unique<ChildT>(node.offsetToGlobalCoord(n),
                                                      node.getTileValue(n), true);
                topologyDifference(*child, *other.getChild(n), background);
                node.setChild(n, child.release());
            });
        const auto& otherStates = other.getValueMask();
        updateTileStates(node,
                         [&](Index w, uint64_t word) { return word & ~otherStates.getWord(w); });
    }
}

// ---- Root nodes

template <typename RootT, typename OtherT>
void rootTopologyUnion(RootT& root, const OtherT& other,
                       const typename RootT::ValueType& background, bool preserveTiles) {
    using ChildT = typename RootT::ChildNodeType;
    for (auto c = other.cbegin(); other.valid(c); other.next(c)) {
        const Coord& key = other.key(c);
        const auto& src = other.entry(c);
        if (src.child) {
            auto* dst = root.findEntry(key);
            if (!dst) {
                root.setChild(topologyCopy<ChildT>(*src.child, background));
            } else if (dst->child) {
                topologyUnion(*dst->child, *src.child, preserveTiles);
            } else if (!preserveTiles || !dst->active) {
                const bool on = dst->active;
                auto child = std::unique_ptr<ChildT>(topologyCopy<ChildT>(*src.child, dst->tile));
                if (on)
                    activateAll(*child);
                root.setChild(child.release());
            }
        } else if (src.active) {
            auto* dst = root.findEntry(key);
            if (!dst) {
                root.setTile(key, tileValue<RootT>(background, true), true);
            } else if (dst->child) {
                activateAll(*dst->child);
            } else if (!dst->active) {
                dst->active = true;
                dst->tile = tileValue<RootT>(dst->tile, true);
            }
        }
    }
}

template <typename RootT, typename OtherT>
void rootTopologyIntersection(RootT& root, const OtherT& other,
                              const typename RootT::ValueType& background) {
    using ChildT = typename RootT::ChildNodeType;
    std::vector<Coord> freed;
    for (auto c = root.cbegin(); root.valid(c); root.next(c)) {
        const Coord& key = root.key(c);
        auto& dst = root.entry(c);
        const auto* src = other.findEntry(key);
        const bool otherOff = !src || (!src->child && !src->active);
        if (dst.child) {
            if (otherOff) {
                freed.push_back(key);
            } else if (src->child) {
                topologyIntersection(*dst.child, *src->child, background);
            }
        } else if (dst.active) {
            if (otherOff) {
                dst.active = false;
                dst.tile = tileValue<RootT>(dst.tile, false);
            } else if (src->child) {
                // The entry already exists, so it changes in place (no table insertion while
                // the cursor walks the table).
                dst.child = topologyCopy<ChildT>(*src->child, dst.tile);
                dst.active = false;
            }
        }
    }
    for (const Coord& key : freed)
        delete root.stealChild(key);
}

template <typename RootT, typename OtherT>
void rootTopologyDifference(RootT& root, const OtherT& other,
                            const typename RootT::ValueType& background) {
    using ChildT = typename RootT::ChildNodeType;
    for (auto c = other.cbegin(); other.valid(c); other.next(c)) {
        const Coord& key = other.key(c);
        const auto& src = other.entry(c);
        if (!src.child && !src.active)
            continue;
        auto* dst = root.findEntry(key);
        if (!dst || (!dst->child && !dst->active))
            continue;
        if (src.child) {
            if (dst->child) {
                topologyDifference(*dst->child, *src.child, background);
            } else {
                auto child = std::make_unique<ChildT>(key, dst->tile, true);
                topologyDifference(*child, *src.child, background);
                root.setChild(child.release());
            }
        } else if (dst->child) {
            delete root.stealChild(key);
        } else {
            dst->active = false;
            dst->tile = tileValue<RootT>(dst->tile, false);
        }
    }
}

// ---- Entry points for either kind of top node

template <typename TopT, typename OtherTopT>
void topTopologyUnion(TopT& top, const OtherTopT& other, const typename TopT::ValueType& background,
                      bool preserveTiles) {
    if constexpr (IS_ROOT_NODE<TopT>) {
        rootTopologyUnion(top, other, background, preserveTiles);
    } else {
        topologyUnion(top, other, preserveTiles);
    }
}

template <typename TopT, typename OtherTopT>
void topTopologyIntersection(TopT& top, const OtherTopT& other,
                             const typename TopT::ValueType& background) {
    if constexpr (IS_ROOT_NODE<TopT>) {
        rootTopologyIntersection(top, other, background);
    } else {
        topologyIntersection(top, other, background);
    }
}

template <typename TopT, typename OtherTopT>
void topTopologyDifference(TopT& top, const OtherTopT& other,
                           const typename TopT::ValueType& background) {
    if constexpr (IS_ROOT_NODE<TopT>) {
        rootTopologyDifference(top, other, background);
    } else {
        topologyDifference(top, other, background);
    }
}

}  // namespace vdb::tree::detail
