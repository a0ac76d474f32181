// SPDX-License-Identifier: Apache-2.0
/// @file
/// Pruning: nodes that hold nothing but one value become tiles (paper 2.1 and 4.2, "prune
/// empty nodes"), bottom-up, threaded over the nodes of each level.
///
/// The rules and the tile values are those of OpenVDB 10's tools/Prune.h:
/// - prune(): a node without children whose values all lie within `tolerance` of each other
///   (largest minus smallest at most `tolerance`) and share one active state becomes a tile of
///   that state. Its value is the node's lower median: element (N - 1) / 2 of the N values in
///   ascending order (vectors compare lexicographically). Bool and mask trees compare exactly;
///   integers compare their exact difference over the whole range of the type; a node that
///   holds a NaN is never constant.
/// - pruneInactive(): a node with no active value and no child becomes an inactive tile of the
///   background; pruneInactiveWithValue() uses a given value instead.
/// - pruneLevelSet(): a node with no active value and no child becomes an inactive tile of the
///   inside value (-background) when its first value is negative, else of the outside value
///   (+background).
/// With a root on top, every inactive root tile equal to the background is then removed, with
/// OpenVDB's default comparison (math::isApproxEqual(a, b)) (within 1e-8 for float, 1e-15 for
/// double; exact for integers and bools; per component within 1e-7, absolute or relative, for
/// vectors). A bounded tree's top node keeps its tiles.
///
/// Cost: one pass over the masks of every node below the top and over the values of each node
/// whose mask allows a tile; the nodes of one level are processed in parallel, children before
/// parents, so results do not depend on the thread count.
///
/// @code
/// vdb::tools::prune(tree);                // exact: only truly constant nodes
/// vdb::tools::prune(tree, 1e-3f);         // values within 0.001 of each other
/// vdb::tools::pruneLevelSet(sdf.tree());  // narrow-band level set: keep only the band's nodes
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/NodeUtil.h>
#include <vdb/tree/Tree.h>
#include <vdb/tree/TreeConfigs.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// Replaces with a tile every node whose values lie within `tolerance` of each other and share
/// one active state; the tile takes the node's lower median value. Children are pruned before
/// their parents, so whole constant branches collapse. Calls tree.clearAllAccessors() when it
/// frees nodes. Leaves whose values are not in memory are kept.
template <VdbTree TreeT>
void prune(TreeT& tree, typename TreeT::ValueType tolerance = typename TreeT::ValueType{},
           bool threaded = true);

/// As prune(), but only internal nodes become tiles (leaves stay): a node whose children are
/// all tiles within `tolerance` of each other, of one state, collapses. OpenVDB's pruneTiles.
template <VdbTree TreeT>
void pruneTiles(TreeT& tree, typename TreeT::ValueType tolerance = typename TreeT::ValueType{},
                bool threaded = true);

/// Replaces with an inactive tile of the background every node that has no active value and no
/// child, bottom-up; then drops root tiles equal to the background.
template <VdbTree TreeT>
void pruneInactive(TreeT& tree, bool threaded = true);

/// As pruneInactive(), with inactive tiles of `value` instead of the background. In a mask tree
/// a tile's value is its state, so the new tiles hold false whatever `value` is.
template <VdbTree TreeT>
void pruneInactiveWithValue(TreeT& tree, const typename TreeT::ValueType& value,
                            bool threaded = true);

/// Replaces every node that has no active value and no child with an inactive tile of
/// -background when the node's first value (at its smallest corner) is negative, else of
/// +background; then drops root tiles equal to the background. For narrow-band level sets,
/// whose inactive values are all +-background.
/// @throw ValueError when the background is negative.
template <SignedVdbTree TreeT>
void pruneLevelSet(TreeT& tree, bool threaded = true);

/// As pruneLevelSet(tree), with tiles of `insideValue` where the first value is negative and of
/// `outsideValue` elsewhere.
/// @throw ValueError when `outsideValue` is negative or `insideValue` is not.
template <SignedVdbTree TreeT>
void pruneLevelSet(TreeT& tree, const typename TreeT::ValueType& outsideValue,
                   const typename TreeT::ValueType& insideValue, bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// `a < b`; vectors compare lexicographically, component 0 first (OpenVDB's Tuple order).
template <typename ValueT>
bool pruneLess(const ValueT& a, const ValueT& b) {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return a < b;
    } else {
        for (int i = 0; i < 2; ++i) {
            if (a[i] != b[i])
                return a[i] < b[i];
        }
        return a[2] < b[2];
    }
}

/// True when `hi - lo` exceeds `tolerance`, for `lo` before `hi` in pruneLess order: for
/// scalars the negation of math::isApproxEqual() (exact integer distances), for vectors
/// OpenVDB's lexicographic comparison of the componentwise difference with the tolerance.
template <typename ValueT>
bool pruneSpreadExceeds(const ValueT& lo, const ValueT& hi, const ValueT& tolerance) {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return !math::isApproxEqual(lo, hi, tolerance);
    } else {
        for (int i = 0; i < 2; ++i) {
            if (const int c = math::compareDifference(lo[i], hi[i], tolerance[i]); c != 0)
                return c > 0;
        }
        return math::compareDifference(lo[2], hi[2], tolerance[2]) > 0;
    }
}

/// True when `v` is or holds a NaN: such a node is never constant (no value is lost to a tile).
template <typename ValueT>
bool holdsNan(const ValueT& v) {
    if constexpr (std::is_floating_point_v<ValueT>) {
        return v != v;
    } else if constexpr (std::is_arithmetic_v<ValueT>) {
        return false;
    } else {
        return holdsNan(v[0]) || holdsNan(v[1]) || holdsNan(v[2]);
    }
}

/// True when the `n` values `get(0..n-1)` lie within `tolerance` (largest minus smallest).
template <typename ValueT, typename GetT>
bool valuesWithin(Index n, const GetT& get, const ValueT& tolerance) {
    ValueT lo = get(0), hi = lo;
    if (holdsNan(lo))
        return false;
    for (Index i = 1; i < n; ++i) {
        const ValueT& v = get(i);
        if (holdsNan(v))
            return false;
        if (pruneLess(v, lo)) {
            if (pruneSpreadExceeds(v, hi, tolerance))
                return false;
            lo = v;
        } else if (pruneLess(hi, v)) {
            if (pruneSpreadExceeds(lo, v, tolerance))
                return false;
            hi = v;
        }
    }
    return true;
}

/// The lower median of `get(0..n-1)`: the element at (n - 1) / 2 after std::nth_element over the
/// values in table order, so that equal-comparing values (0 and -0) resolve as OpenVDB's do.
template <typename ValueT, typename GetT>
ValueT lowerMedian(Index n, const GetT& get) {
    std::vector<ValueT> values(n);
    for (Index i = 0; i < n; ++i)
        values[i] = get(i);
    const size_t mid = (size_t(n) - 1) >> 1;
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(mid), values.end(),
                     [](const ValueT& a, const ValueT& b) { return pruneLess(a, b); });
    return values[mid];
}

/// True when `node` could be replaced by one tile under prune(tolerance); then `value` and
/// `state` describe the tile.
template <typename NodeT, typename ValueT>
bool isConstantForPrune(const NodeT& node, const ValueT& tolerance, ValueT& value, bool& state) {
    if constexpr (std::is_same_v<ValueT, bool>) {
        // Bool and mask nodes: exact; the node's own test reads both masks.
        if constexpr (NodeT::LEVEL == 0) {
            return node.isConstant(value, state, tolerance);
        } else {
            return node.getChildMask().isOff() && node.isConstant(value, state, tolerance);
        }
    } else if constexpr (NodeT::LEVEL == 0) {
        if (!node.isAllocated())
            return false;
        const auto& mask = node.getValueMask();
        state = mask.isOn(0);
        if (state ? !mask.isOn() : !mask.isOff())
            return false;
        const auto get = [&](Index n) -> const ValueT& { return node.getValue(n); };
        if (!valuesWithin<ValueT>(NodeT::NUM_VALUES, get, tolerance))
            return false;
        value = lowerMedian<ValueT>(NodeT::NUM_VALUES, get);
        return true;
    } else {
        if (!node.getChildMask().isOff())
            return false;
        const auto& mask = node.getValueMask();
        state = mask.isOn(0);
        if (state ? !mask.isOn() : !mask.isOff())
            return false;
        const auto get = [&](Index n) -> const ValueT& { return node.getTileValue(n); };
        if (!valuesWithin<ValueT>(NodeT::NUM_VALUES, get, tolerance))
            return false;
        value = lowerMedian<ValueT>(NodeT::NUM_VALUES, get);
        return true;
    }
}

/// True when `node` has no active value and no child.
template <typename NodeT>
bool isInactiveNode(const NodeT& node) {
    if constexpr (NodeT::LEVEL == 0) {
        return node.isEmpty();
    } else {
        return node.getChildMask().isOff() && node.getValueMask().isOff();
    }
}

/// The value at the smallest corner of `node` (table entry 0). @pre the node has no child there
template <typename NodeT>
typename NodeT::ValueType firstTileOrVoxel(const NodeT& node) {
    if constexpr (NodeT::LEVEL == 0) {
        return node.getValue(Index(0));
    } else {
        return node.getTileValue(0);
    }
}

template <Index L, Index Top, typename ListsT, typename OpT>
void foreachLevelBottomUp(const ListsT& lists, const OpT& op, bool threaded) {
    if constexpr (L < Top) {
        lists.template foreach<L>(op, threaded);
        foreachLevelBottomUp<L + 1, Top>(lists, op, threaded);
    }
}

/// The driver shared by every prune: `decide(child, value, state)` says whether a child becomes
/// a tile (of `value`, `state`). The internal nodes of each level, lowest first, decide for
/// their children in parallel; then the top node, and a root drops its background tiles.
template <typename TreeT, typename DecideT>
void pruneBottomUp(TreeT& tree, const DecideT& decide, bool threaded) {
    using TopT = typename TreeT::TopNodeType;
    using ValueT = typename TreeT::ValueType;
    std::atomic<bool> freed{false};

    // Replace each child of `node` that `decide` accepts with a tile.
    const auto pruneChildren = [&](auto& node) {
        bool any = false;
        ValueT value{};
        bool state = false;
        tree::forEachChild(node, [&](auto& child) {
            if (decide(child, value, state)) {
                tree::setTile(node, child.origin(), value, state);  // deletes `child`
                any = true;
            }
        });
        if (any)
            freed.store(true, std::memory_order_relaxed);
    };

    // Levels 1 .. TOP-1, each in parallel, children before parents; then the top.
    if constexpr (TopT::LEVEL > 1) {
        const NodeLists<TreeT> lists(tree, 1);
        foreachLevelBottomUp<1, TopT::LEVEL>(lists, pruneChildren, threaded);
    }
    TopT& top = tree.topNode();
    pruneChildren(top);
    // A root keeps no entry that reads as its background (as OpenVDB's prune does).
    if constexpr (tree::IS_ROOT_NODE<TopT>) {
        std::vector<Coord> background;
        tree::forEachTile<ValueFilter::Off>(top, [&](const auto& tile) {
            if (math::isApproxEqual(tile.value, top.background()))
                background.push_back(tile.origin);
        });
        for (const Coord& key : background)
            top.eraseEntry(key);
    }
    if (freed.load(std::memory_order_relaxed))
        tree.clearAllAccessors();
}

}  // namespace detail

template <VdbTree TreeT>
void prune(TreeT& tree, typename TreeT::ValueType tolerance, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    detail::pruneBottomUp(
        tree,
        [&tolerance](const auto& child, ValueT& value, bool& state) {
            return detail::isConstantForPrune(child, tolerance, value, state);
        },
        threaded);
}

template <VdbTree TreeT>
void pruneTiles(TreeT& tree, typename TreeT::ValueType tolerance, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    detail::pruneBottomUp(
        tree,
        [&tolerance](const auto& child, ValueT& value, bool& state) {
            if constexpr (std::remove_cvref_t<decltype(child)>::LEVEL == 0) {
                return false;
            } else {
                return detail::isConstantForPrune(child, tolerance, value, state);
            }
        },
        threaded);
}

template <VdbTree TreeT>
void pruneInactiveWithValue(TreeT& tree, const typename TreeT::ValueType& value, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    const ValueT tileValue = tree::IS_MASK_NODE<typename TreeT::LeafNodeType> ? ValueT{} : value;
    detail::pruneBottomUp(
        tree,
        [&tileValue](const auto& child, ValueT& v, bool& state) {
            if (!detail::isInactiveNode(child))
                return false;
            v = tileValue;
            state = false;
            return true;
        },
        threaded);
}

template <VdbTree TreeT>
void pruneInactive(TreeT& tree, bool threaded) {
    const typename TreeT::ValueType background = tree.background();
    pruneInactiveWithValue(tree, background, threaded);
}

namespace detail {

template <typename TreeT>
void pruneLevelSetWith(TreeT& tree, const typename TreeT::ValueType& outside,
                       const typename TreeT::ValueType& inside, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    pruneBottomUp(
        tree,
        [&outside, &inside](const auto& child, ValueT& v, bool& state) {
            using ChildT = std::remove_cvref_t<decltype(child)>;
            if (!isInactiveNode(child))
                return false;
            if constexpr (ChildT::LEVEL == 0) {
                if (!child.isAllocated())
                    return false;
            }
            v = firstTileOrVoxel(child) < ValueT(0) ? inside : outside;
            state = false;
            return true;
        },
        threaded);
}

}  // namespace detail

template <SignedVdbTree TreeT>
void pruneLevelSet(TreeT& tree, const typename TreeT::ValueType& outsideValue,
                   const typename TreeT::ValueType& insideValue, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    if (outsideValue < ValueT(0))
        throw ValueError("pruneLevelSet: the outside value cannot be negative");
    if (!(insideValue < ValueT(0)))
        throw ValueError("pruneLevelSet: the inside value must be negative");
    const ValueT outside = outsideValue, inside = insideValue;
    detail::pruneLevelSetWith(tree, outside, inside, threaded);
}

template <SignedVdbTree TreeT>
void pruneLevelSet(TreeT& tree, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    const ValueT outside = tree.background();
    if (outside < ValueT(0))
        throw ValueError("pruneLevelSet: the background value cannot be negative");
    detail::pruneLevelSetWith(tree, outside, ValueT(-outside), threaded);
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/Prune.cpp

namespace vdb::tools {

extern template void prune(FloatTree&, float, bool);
extern template void prune(DoubleTree&, double, bool);
extern template void pruneInactive(FloatTree&, bool);
extern template void pruneInactive(DoubleTree&, bool);
extern template void pruneLevelSet(FloatTree&, bool);
extern template void pruneLevelSet(DoubleTree&, bool);

}  // namespace vdb::tools
