// SPDX-License-Identifier: Apache-2.0
/// @file
/// Changing the background of a tree the way OpenVDB 10 does: not only the background field
/// (Tree::setBackground()) but every inactive value that stands for it, in leaves, in internal
/// nodes' tiles and in the root's tiles.
///
/// - changeBackground(tree, b): every inactive value equal to the old background (within
///   math::isApproxEqual()'s default tolerance) becomes b, and every one equal to minus the old
///   background becomes -b (the inside of a level set). Active values never change.
/// - changeLevelSetBackground(tree, w) = changeAsymmetricLevelSetBackground(tree, w, -w): every
///   inactive value becomes the outside value w when it is zero or positive, the inside value
///   -w when it is negative; w becomes the background. This widens or narrows the nominal band
///   of a level set (a tracker's rebuild then fills it in).
///
/// Cost: one pass over the values of every leaf and the tiles of every node; leaves and the
/// nodes of each level in parallel. Accessors stay valid (no node is freed).
///
/// @code
/// vdb::tools::changeBackground(density.tree(), 0.0f);
/// vdb::tools::changeLevelSetBackground(sdf.tree(), 5.0f * voxelSize);   // half width 5 voxels
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace vdb::tools {

/// Replaces the background of `tree` by `background` in every inactive value that holds the old
/// one (and its negative by the negative of the new one).
template <VdbTree TreeT>
void changeBackground(TreeT& tree, const typename TreeT::ValueType& background,
                      bool threaded = true, size_t grainSize = 32);
/// As above for the tree of `leaves` (whose leaf array stays valid).
template <VdbTree TreeT>
void changeBackground(tree::LeafManager<TreeT>& leaves, const typename TreeT::ValueType& background,
                      bool threaded = true, size_t grainSize = 32);

/// Makes every inactive value of the level set `tree` `outsideWidth` where it is not negative
/// and `insideWidth` where it is, and `outsideWidth` the background.
/// @throw ValueError unless outsideWidth >= 0 and insideWidth < 0.
template <SignedVdbTree TreeT>
void changeAsymmetricLevelSetBackground(TreeT& tree, const typename TreeT::ValueType& outsideWidth,
                                        const typename TreeT::ValueType& insideWidth,
                                        bool threaded = true, size_t grainSize = 32);
template <SignedVdbTree TreeT>
void changeAsymmetricLevelSetBackground(tree::LeafManager<TreeT>& leaves,
                                        const typename TreeT::ValueType& outsideWidth,
                                        const typename TreeT::ValueType& insideWidth,
                                        bool threaded = true, size_t grainSize = 32);

/// changeAsymmetricLevelSetBackground(tree, halfWidth, -halfWidth).
/// @throw ValueError unless halfWidth > 0.
template <SignedVdbTree TreeT>
void changeLevelSetBackground(TreeT& tree, const typename TreeT::ValueType& halfWidth,
                              bool threaded = true, size_t grainSize = 32);
template <SignedVdbTree TreeT>
void changeLevelSetBackground(tree::LeafManager<TreeT>& leaves,
                              const typename TreeT::ValueType& halfWidth, bool threaded = true,
                              size_t grainSize = 32);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Calls `f(value, active)` on every tile of `tree`, active or not (the tiles of every internal
/// node, the top node's included); `f` may change both. The nodes of one level run in
/// parallel.
template <typename TreeT, typename FuncT>
void forEachTile(TreeT& tree, const FuncT& f, bool threaded) {
    using TopT = typename TreeT::TopNodeType;
    const auto changeTiles = [&f](auto& node) {
        tree::forEachTile(node, [&f](auto& tile) { f(tile.value, tile.active); });
    };
    const NodeLists<TreeT> nodes(tree, 1);
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        (nodes.template foreach<L + 1>(changeTiles, threaded), ...);
    }
    (std::make_integer_sequence<Index, TopT::LEVEL - 1>{});
    changeTiles(tree.topNode());
}

/// Calls `f(value)` on every inactive value of `tree`: the inactive voxels of every leaf and
/// the inactive tiles of every node, the top node's included. `f` returns the new value.
template <typename TreeT, typename FuncT>
void forEachInactiveValue(TreeT& tree, const FuncT& f, bool threaded, size_t grainSize) {
    using ValueT = typename TreeT::ValueType;
    tree::LeafManager<TreeT> leaves(tree);
    leaves.foreach (
        [&](auto& leaf, size_t) {
            auto* values = leaf.buffer(0).data();
            for (auto it = leaf.cbeginValueOff(); it; ++it)
                values[it.pos()] = f(values[it.pos()]);
        },
        threaded, grainSize);
    forEachTile(
        tree,
        [&f](ValueT& value, bool active) {
            if (!active)
                value = f(value);
        },
        threaded);
}

}  // namespace detail

template <VdbTree TreeT>
void changeBackground(TreeT& tree, const typename TreeT::ValueType& background, bool threaded,
                      size_t grainSize) {
    using ValueT = typename TreeT::ValueType;
    const ValueT oldValue = tree.background();
    constexpr bool SIGNED = !std::is_same_v<ValueT, bool> &&
                            (!std::is_arithmetic_v<ValueT> || std::is_signed_v<ValueT>);
    detail::forEachInactiveValue(
        tree,
        [&](const ValueT& v) -> ValueT {
            if (math::isApproxEqual(v, oldValue))
                return background;
            if constexpr (SIGNED) {
                if (math::isApproxEqual(v, ValueT(-oldValue)))
                    return ValueT(-background);
            }
            return v;
        },
        threaded, grainSize);
    tree.setBackground(background);
}

template <VdbTree TreeT>
void changeBackground(tree::LeafManager<TreeT>& leaves, const typename TreeT::ValueType& background,
                      bool threaded, size_t grainSize) {
    changeBackground(leaves.tree(), background, threaded, grainSize);
}

template <SignedVdbTree TreeT>
void changeAsymmetricLevelSetBackground(TreeT& tree, const typename TreeT::ValueType& outsideWidth,
                                        const typename TreeT::ValueType& insideWidth, bool threaded,
                                        size_t grainSize) {
    using ValueT = typename TreeT::ValueType;
    if (!(outsideWidth >= ValueT(0)))
        throw ValueError(
            "changeAsymmetricLevelSetBackground: the outside value cannot be negative");
    if (!(insideWidth < ValueT(0)))
        throw ValueError("changeAsymmetricLevelSetBackground: the inside value must be negative");
    detail::forEachInactiveValue(
        tree, [&](const ValueT& v) { return v < ValueT(0) ? insideWidth : outsideWidth; }, threaded,
        grainSize);
    tree.setBackground(outsideWidth);
}

template <SignedVdbTree TreeT>
void changeAsymmetricLevelSetBackground(tree::LeafManager<TreeT>& leaves,
                                        const typename TreeT::ValueType& outsideWidth,
                                        const typename TreeT::ValueType& insideWidth, bool threaded,
                                        size_t grainSize) {
    changeAsymmetricLevelSetBackground(leaves.tree(), outsideWidth, insideWidth, threaded,
                                       grainSize);
}

template <SignedVdbTree TreeT>
void changeLevelSetBackground(TreeT& tree, const typename TreeT::ValueType& halfWidth,
                              bool threaded, size_t grainSize) {
    if (!(halfWidth > typename TreeT::ValueType(0)))
        throw ValueError("changeLevelSetBackground: the half width must be positive");
    changeAsymmetricLevelSetBackground(tree, halfWidth, typename TreeT::ValueType(-halfWidth),
                                       threaded, grainSize);
}

template <SignedVdbTree TreeT>
void changeLevelSetBackground(tree::LeafManager<TreeT>& leaves,
                              const typename TreeT::ValueType& halfWidth, bool threaded,
                              size_t grainSize) {
    changeLevelSetBackground(leaves.tree(), halfWidth, threaded, grainSize);
}

}  // namespace vdb::tools
