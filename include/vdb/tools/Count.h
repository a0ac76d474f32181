// SPDX-License-Identifier: Apache-2.0
/// @file
/// Reductions over the active values of a tree, where OpenVDB 10 keeps them: minMax(), the
/// smallest and largest active value (voxels and tiles) in one parallel pass.
///
/// For vector values the order is OpenVDB's componentwise one: a value replaces the minimum
/// only when each of its components is smaller (and the maximum when each is larger), so the
/// result is the first value met that no later value dominates in every component.
///
/// @code
/// auto mm = vdb::tools::minMax(grid->tree());
/// float lo = mm.min(), hi = mm.max();   // both 0 for a tree without active values
/// @endcode

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Stats.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Statistics.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <optional>
#include <type_traits>

namespace vdb::tools {

/// The smallest and largest active values of `tree` (voxels and tiles); both zero when the tree
/// has no active value.
template <typename TreeT>
math::MinMax<typename TreeT::ValueType> minMax(const TreeT& tree, bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// a < b: for vectors, in every component (OpenVDB's cwiseLessThan).
template <typename ValueT>
bool allLess(const ValueT& a, const ValueT& b) {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return a < b;
    } else {
        return a[0] < b[0] && a[1] < b[1] && a[2] < b[2];
    }
}

/// The running min and max of active values, empty until the first value.
template <typename ValueT>
struct ActiveRange {
    std::optional<ValueT> min, max;
    void add(const ValueT& v) {
        if (!min) {
            min = max = v;
            return;
        }
        if (allLess(v, *min))
            min = v;
        if (allLess(*max, v))
            max = v;
    }
    void add(const ActiveRange& o) {
        if (o.min) {
            add(*o.min);
            add(*o.max);
        }
    }
};

}  // namespace detail

template <typename TreeT>
math::MinMax<typename TreeT::ValueType> minMax(const TreeT& tree, bool threaded) {
    using ValueT = typename TreeT::ValueType;
    using RangeT = detail::ActiveRange<ValueT>;
    const tree::LeafManager<const TreeT> leaves(tree);
    RangeT range = util::parallelReduce(
        leaves.leafCount(), RangeT{},
        [&](size_t begin, size_t end) {
            RangeT part;
            for (size_t i = begin; i < end; ++i) {
                const auto& leaf = leaves.leaf(i);
                for (auto it = leaf.cbeginValueOn(); it; ++it)
                    part.add(*it);
            }
            return part;
        },
        [](RangeT a, const RangeT& b) {
            a.add(b);
            return a;
        },
        threaded, 16);
    tree::visitTiles<ValueFilter::On>(tree.topNode(),
                                      [&](const auto& tile) { range.add(tile.value); });
    if (!range.min)
        return math::MinMax<ValueT>(ValueT{}, ValueT{});
    return math::MinMax<ValueT>(*range.min, *range.max);
}

}  // namespace vdb::tools
