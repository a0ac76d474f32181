// SPDX-License-Identifier: Apache-2.0
/// @file
/// Statistics of the values of a grid in one parallel pass, with OpenVDB 10's names:
/// statistics() (count, min, max, mean, population variance), extrema() (count, min, max) and
/// histogram(). They take a tree value iterator (grid.cbeginValueOn(), cbeginValueOff(),
/// cbeginValueAll()) and visit what it visits; a tile counts as many samples as it has voxels.
/// Vector values contribute their length.
///
/// From an iterator at its start, the leaves are processed in parallel and the partial
/// results merged in an order fixed by the tree, so the results do not depend on the thread
/// count; an iterator that has already advanced is walked serially from where it is.
///
/// @code
/// vdb::math::Stats s = vdb::tools::statistics(grid->cbeginValueOn());
/// std::printf("%llu voxels, mean %g, std %g\n", s.size(), s.mean(), s.stdDev());
/// vdb::math::Histogram h = vdb::tools::histogram(grid->cbeginValueOn(), s.min(), s.max(), 20);
/// @endcode

#pragma once

#include <vdb/Types.h>
#include <vdb/math/Stats.h>
#include <vdb/math/Vec3.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/NodeEdit.h>
#include <vdb/tree/Tree.h>
#include <vdb/util/Parallel.h>

#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace vdb::tools {

/// Count, min, max, mean and variance of the values `iter` visits (vector lengths for vector
/// grids).
template <typename IterT>
math::Stats statistics(const IterT& iter, bool threaded = true);

/// Count, min and max of the values `iter` visits.
template <typename IterT>
math::Extrema extrema(const IterT& iter, bool threaded = true);

/// A histogram of `numBins` bins over [minVal, maxVal] of the values `iter` visits; values
/// outside the range are not counted.
/// @throw ValueError unless minVal < maxVal and numBins >= 1.
template <typename IterT>
math::Histogram histogram(const IterT& iter, double minVal, double maxVal, size_t numBins = 10,
                          bool threaded = true);

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// A value as a sample: itself for scalars, its length for vectors.
template <typename ValueT>
double sampleOf(const ValueT& v) {
    if constexpr (std::is_arithmetic_v<ValueT>) {
        return double(v);
    } else {
        return double(v.length());
    }
}

template <typename IterT>
struct IterTraits;
template <typename TreeT, ValueFilter F>
struct IterTraits<tree::TreeValueIterator<TreeT, F>> {
    using TreeType = std::remove_const_t<TreeT>;
    static constexpr ValueFilter FILTER = F;
};

/// Adds to a fresh `AccT` (Stats, Extrema or Histogram, made by `make()`) every value that the
/// iterator `iter` visits, with `add(acc, value, count)`.
template <typename IterT, typename MakeT, typename AddT>
auto accumulate(const IterT& iter, const MakeT& make, const AddT& add, bool threaded) {
    using Traits = IterTraits<IterT>;
    using TreeT = typename Traits::TreeType;
    constexpr ValueFilter F = Traits::FILTER;
    using AccT = decltype(make());
    AccT result = make();
    if (!iter)
        return result;
    const TreeT& tree = iter.getTree();
    const IterT start(iter.getTree());
    if (start.getLevel() != iter.getLevel() || start.getCoord() != iter.getCoord()) {
        // An iterator already under way: the rest of its walk, serially.
        for (IterT it = iter; it; ++it) {
            CoordBBox box;
            it.getBoundingBox(box);
            add(result, sampleOf(*it), Index64(box.volume()));
        }
        return result;
    }
    // Leaves, in parallel; merged in the order of the leaves.
    const tree::LeafManager<const TreeT> leaves(tree);
    result = util::parallelReduce(
        leaves.leafCount(), make(),
        [&](size_t begin, size_t end) {
            AccT part = make();
            for (size_t i = begin; i < end; ++i) {
                const auto& leaf = leaves.leaf(i);
                const auto* values = leaf.buffer(0).data();
                const auto* words = leaf.getValueMask().words();
                for (Index w = 0; w < leaf.getValueMask().WORD_COUNT; ++w) {
                    const uint64_t word = F == ValueFilter::On    ? words[w]
                                          : F == ValueFilter::Off ? ~words[w]
                                                                  : ~uint64_t(0);
                    for (uint64_t bits = word; bits; bits &= bits - 1)
                        add(part, sampleOf(values[(w << 6) + Index(std::countr_zero(bits))]), 1);
                }
            }
            return part;
        },
        [](AccT a, const AccT& b) {
            a.add(b);
            return a;
        },
        threaded, 16);
    // Tiles, node by node from the top, in table order.
    tree::visitTiles<F>(tree.topNode(), [&](const auto& tile) {
        add(result, sampleOf(tile.value), Index64(tile.bbox().volume()));
    });
    return result;
}

}  // namespace detail

template <typename IterT>
math::Stats statistics(const IterT& iter, bool threaded) {
    return detail::accumulate(
        iter, [] { return math::Stats(); },
        [](math::Stats& s, double v, Index64 n) { s.add(v, n); }, threaded);
}

template <typename IterT>
math::Extrema extrema(const IterT& iter, bool threaded) {
    return detail::accumulate(
        iter, [] { return math::Extrema(); },
        [](math::Extrema& s, double v, Index64 n) { s.add(v, n); }, threaded);
}

template <typename IterT>
math::Histogram histogram(const IterT& iter, double minVal, double maxVal, size_t numBins,
                          bool threaded) {
    const math::Histogram empty(minVal, maxVal, numBins);  // validates the range first
    return detail::accumulate(
        iter, [&] { return empty; }, [](math::Histogram& h, double v, Index64 n) { h.add(v, n); },
        threaded);
}

}  // namespace vdb::tools
