// SPDX-License-Identifier: Apache-2.0
/// @file
/// Activation by value: activate() turns on every inactive voxel and tile whose value matches
/// a given value, deactivate() turns off every active one that matches, as OpenVDB 10's
/// tools::activate / tools::deactivate do.
///
/// A value matches when it equals `value` exactly (tolerance zero, the default) or, with a
/// non-zero tolerance, when math::isApproxEqual(v, value, tolerance) holds (|v - value| <=
/// tolerance, per component for vectors). Voxels, tiles of the internal nodes and tiles of the
/// root are all visited; regions without a root entry are not (they hold the background but
/// have no state to change). Values are never changed, except in mask trees, where a tile's
/// value is its state.
///
/// Cost: one pass over the masks of every node and over the values of the inactive (activate)
/// or active (deactivate) entries; the nodes of each level are processed in parallel, so the
/// result does not depend on the thread count.
///
/// @code
/// vdb::tools::activate(*grid, 0.0f, 1e-3f);   // every value within 0.001 of 0 becomes active
/// vdb::tools::deactivate(grid->tree(), 1.0f); // every value exactly 1 becomes inactive
/// @endcode

#pragma once

#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Math.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/detail/NodeLists.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>

#include <bit>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace vdb::tools {

/// Activates every inactive voxel and tile of `tree` whose value matches `value` within
/// `tolerance`.
template <VdbTree TreeT>
void activate(TreeT& tree, const typename TreeT::ValueType& value,
              const typename TreeT::ValueType& tolerance = typename TreeT::ValueType{},
              bool threaded = true);
/// Deactivates every active voxel and tile of `tree` whose value matches `value` within
/// `tolerance`.
template <VdbTree TreeT>
void deactivate(TreeT& tree, const typename TreeT::ValueType& value,
                const typename TreeT::ValueType& tolerance = typename TreeT::ValueType{},
                bool threaded = true);

/// The grid forms work on the grid's tree.
template <VdbTree TreeT>
void activate(Grid<TreeT>& grid, const typename TreeT::ValueType& value,
              const typename TreeT::ValueType& tolerance = typename TreeT::ValueType{},
              bool threaded = true) {
    activate(grid.tree(), value, tolerance, threaded);
}
template <VdbTree TreeT>
void deactivate(Grid<TreeT>& grid, const typename TreeT::ValueType& value,
                const typename TreeT::ValueType& tolerance = typename TreeT::ValueType{},
                bool threaded = true) {
    deactivate(grid.tree(), value, tolerance, threaded);
}

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Sets to `On` the state of every voxel and tile of `tree` whose state is !On and whose value
/// satisfies `matches`, one level at a time, the nodes of a level in parallel.
template <bool On, typename TreeT, typename MatchT>
void setStatesWhere(TreeT& tree, const MatchT& matches, bool threaded) {
    using TopT = typename TreeT::TopNodeType;
    constexpr Index TOP = TopT::LEVEL;

    // The tiles of one node (internal or root) not yet in state On.
    constexpr auto FILTER = On ? ValueFilter::Off : ValueFilter::On;
    const auto visitTiles = [&](auto& node) {
        using NodeT = std::remove_reference_t<decltype(node)>;
        tree::forEachTile<FILTER>(node, [&](auto& tile) {
            if (matches(tile.value)) {
                tile.value = tree::detail::tileValue<NodeT>(tile.value, On);
                tile.active = On;
            }
        });
    };

    NodeLists<TreeT> lists(tree);
    lists.template foreach<0>(
        [&](auto& leaf) {
            auto& mask = leaf.getValueMask();
            for (Index w = 0; w < std::remove_reference_t<decltype(mask)>::WORD_COUNT; ++w) {
                const uint64_t state = mask.getWord(w);
                uint64_t flip = 0;
                for (uint64_t bits = On ? ~state : state; bits != 0; bits &= bits - 1) {
                    const Index i = Index(std::countr_zero(bits));
                    if (matches(leaf.getValue((w << 6) + i)))
                        flip |= uint64_t(1) << i;
                }
                mask.getWord(w) = state ^ flip;
            }
        },
        threaded, 16);
    [&]<Index... L>(std::integer_sequence<Index, L...>) {
        (lists.template foreach<L + 1>(visitTiles, threaded), ...);
    }
    (std::make_integer_sequence<Index, TOP - 1>{});

    visitTiles(tree.topNode());
}

/// The match of activate() and deactivate(): exact for a zero tolerance, else within it.
template <typename ValueT>
auto valueMatcher(const ValueT& value, const ValueT& tolerance) {
    const bool exact = tolerance == ValueT{};
    return [value, tolerance, exact](const ValueT& v) {
        return exact ? v == value : math::isApproxEqual(v, value, tolerance);
    };
}

}  // namespace detail

template <VdbTree TreeT>
void activate(TreeT& tree, const typename TreeT::ValueType& value,
              const typename TreeT::ValueType& tolerance, bool threaded) {
    detail::setStatesWhere<true>(tree, detail::valueMatcher(value, tolerance), threaded);
}

template <VdbTree TreeT>
void deactivate(TreeT& tree, const typename TreeT::ValueType& value,
                const typename TreeT::ValueType& tolerance, bool threaded) {
    detail::setStatesWhere<false>(tree, detail::valueMatcher(value, tolerance), threaded);
}

}  // namespace vdb::tools
