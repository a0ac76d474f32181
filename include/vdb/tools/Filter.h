// SPDX-License-Identifier: Apache-2.0
/// @file
/// Filter: smoothing of the active values of scalar and vector grids, with OpenVDB 10's names
/// and meanings (tools::Filter): mean (a box filter), Gaussian (four box filters: a B-spline of
/// degree 3, within a few percent of a Gaussian), median, and offset, each optionally weighted
/// by an alpha mask.
///
/// - Only active voxels change; their neighbourhoods include inactive voxels and tiles (the
///   background beyond the data). Active tiles are left as they are.
/// - mean(width) averages the (2 width + 1)^3 box around each voxel as three one-dimensional
///   passes (along x, then z, then y, OpenVDB's order), each over the results of the last;
///   gaussian() applies that four times per iteration; median() takes the median of the box
///   (scalar grids only).
/// - With a mask (a scalar grid, read at the same index coordinates when its transform matches
///   the grid's, else sampled trilinearly in world space), each voxel becomes
///   (1 - alpha) old + alpha new, alpha being the mask value mapped from [minMask, maxMask] to
///   [0, 1] by a smooth step (setMaskRange(), invertMask()).
/// - Widths run from 1 to FILTER_MAX_WIDTH (MEDIAN_FILTER_MAX_WIDTH for the median); anything
///   else is a ValueError before any work (OpenVDB silently uses 1 for widths below 1).
///
/// Cost: per one-dimensional pass, one sweep over the active leaves, each gathering its
/// neighbourhood along the pass's axis into a dense block and summing 2 width + 1 array values
/// per voxel; the median reads (2 width + 1)^3 values per voxel. Threads: parallel over leaves
/// (grain size 0 runs serially); the result is the same for any thread count.
///
/// @code
/// vdb::tools::Filter<vdb::FloatGrid> filter(*density);
/// filter.gaussian(2);               // width 2: a 5^3 kernel, four times
/// filter.mean(1, 3);                // three iterations of a 3^3 box
/// filter.setMaskRange(0.0f, 1.0f);
/// filter.median(1, 1, mask.get());  // only where the mask is positive
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/tools/detail/FilterImpl.h>

#include <type_traits>

namespace vdb::tools {

/// Smooths the active values of one grid in place.
///
/// GridT holds float, double, Int32, Int64, Vec3s or Vec3d values (integers are averaged in
/// float and truncated, as OpenVDB does). The filter keeps a reference to the grid, which must
/// outlive it. Threads: one call at a time; each runs in parallel over leaves.
template <typename GridT, typename MaskT = typename GridT::template ValueConverter<float>::Type>
class Filter {
public:
    using GridType = GridT;
    using MaskType = MaskT;
    using TreeType = typename GridT::TreeType;
    using LeafType = typename TreeType::LeafNodeType;
    using ValueType = typename GridT::ValueType;
    using AlphaType = typename MaskT::ValueType;
    static_assert(std::is_floating_point_v<AlphaType>,
                  "Filter needs a mask grid with floating-point values");
    static_assert(!std::is_same_v<ValueType, bool>, "Filter does not filter bool grids");

    explicit Filter(GridT& grid) : mGrid(&grid) {}

    /// The number of leaves per task; 0 runs serially.
    int getGrainSize() const { return mGrainSize; }
    void setGrainSize(int grainSize) { mGrainSize = grainSize < 0 ? 0 : grainSize; }

    /// The mask values mapped to alpha 0 and 1 (default 0 and 1).
    AlphaType minMask() const { return mRange.min; }
    AlphaType maxMask() const { return mRange.max; }
    /// @throw ValueError unless min < max.
    void setMaskRange(AlphaType min, AlphaType max) { mRange.set(min, max); }
    bool isMaskInverted() const { return mRange.invert; }
    /// Maps the mask range to alpha 1 to 0 instead of 0 to 1.
    void invertMask(bool invert = true) { mRange.invert = invert; }

    /// `iterations` box filters of edge 2 width + 1. Does nothing for iterations <= 0.
    /// @throw ValueError unless 1 <= width <= FILTER_MAX_WIDTH.
    void mean(int width = 1, int iterations = 1, const MaskT* mask = nullptr);
    /// `iterations` approximate Gaussian filters, each four box filters of edge 2 width + 1.
    /// @throw ValueError unless 1 <= width <= FILTER_MAX_WIDTH.
    void gaussian(int width = 1, int iterations = 1, const MaskT* mask = nullptr);
    /// `iterations` median filters over boxes of edge 2 width + 1.
    /// @throw ValueError unless 1 <= width <= MEDIAN_FILTER_MAX_WIDTH; TypeError for a vector
    /// grid (vectors have no median), naming the grid's type.
    void median(int width = 1, int iterations = 1, const MaskT* mask = nullptr);
    /// Adds `offset` to every active voxel.
    /// @throw ValueError for a non-finite offset.
    void offset(ValueType offset, const MaskT* mask = nullptr);

private:
    void box(int width, const MaskT* mask);
    bool threaded() const { return mGrainSize > 0; }

    GridT* mGrid;
    int mGrainSize = 1;
    detail::MaskRange<AlphaType> mRange;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename GridT, typename MaskT>
void Filter<GridT, MaskT>::box(int width, const MaskT* mask) {
    const detail::MaskRange<float> range{float(mRange.min), float(mRange.max), mRange.invert};
    tree::LeafManager<TreeType> leaves(mGrid->tree());
    leaves.setAuxBufferCount(1, threaded());
    const float frac = 1.0f / float(2 * width + 1);
    // x, then z, then y, each pass over the results of the previous one.
    for (const int axis : {0, 2, 1}) {
        Coord radius(0);
        radius[size_t(axis)] = width;
        detail::filterPass(
            leaves, radius, detail::BlockShape::Cross, mGrid->transform(), mask, range,
            [&](const auto& block, Index n) {
                return detail::boxAverage(block, n, axis, width, frac);
            },
            threaded());
        leaves.swapLeafBuffers(0, 1, threaded());
    }
    leaves.setAuxBufferCount(0, threaded());
}

template <typename GridT, typename MaskT>
void Filter<GridT, MaskT>::mean(int width, int iterations, const MaskT* mask) {
    detail::checkFilterWidth(width, FILTER_MAX_WIDTH, "Filter::mean");
    for (int i = 0; i < iterations; ++i)
        box(width, mask);
}

template <typename GridT, typename MaskT>
void Filter<GridT, MaskT>::gaussian(int width, int iterations, const MaskT* mask) {
    detail::checkFilterWidth(width, FILTER_MAX_WIDTH, "Filter::gaussian");
    for (int i = 0; i < iterations; ++i) {
        for (int n = 0; n < 4; ++n)
            box(width, mask);
    }
}

template <typename GridT, typename MaskT>
void Filter<GridT, MaskT>::median(int width, int iterations, const MaskT* mask) {
    if constexpr (!std::is_arithmetic_v<ValueType>) {
        throw TypeError("Filter::median needs scalar values; grid \"" + mGrid->getName() +
                        "\" has type " + mGrid->type());
    } else {
        detail::checkFilterWidth(width, MEDIAN_FILTER_MAX_WIDTH, "Filter::median");
        if (iterations <= 0)
            return;
        const detail::MaskRange<float> range{float(mRange.min), float(mRange.max), mRange.invert};
        tree::LeafManager<TreeType> leaves(mGrid->tree());
        leaves.setAuxBufferCount(1, threaded());
        for (int i = 0; i < iterations; ++i) {
            detail::filterPass(
                leaves, Coord(width), detail::BlockShape::Full, mGrid->transform(), mask, range,
                [width](const auto& block, Index n) {
                    thread_local std::vector<ValueType> scratch;
                    return detail::boxMedian(block, n, width, scratch);
                },
                threaded());
            leaves.swapLeafBuffers(0, 1, threaded());
        }
        leaves.setAuxBufferCount(0, threaded());
    }
}

template <typename GridT, typename MaskT>
void Filter<GridT, MaskT>::offset(ValueType value, const MaskT* mask) {
    detail::checkFiniteOffset(value, "Filter::offset");
    const detail::MaskRange<float> range{float(mRange.min), float(mRange.max), mRange.invert};
    tree::LeafManager<TreeType> leaves(mGrid->tree());
    detail::offsetPass(leaves, value, mGrid->transform(), mask, range, threaded());
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/Filter.cpp

namespace vdb::tools {

extern template class Filter<FloatGrid, FloatGrid>;
extern template class Filter<DoubleGrid, FloatGrid>;
extern template class Filter<Vec3SGrid, FloatGrid>;

}  // namespace vdb::tools
