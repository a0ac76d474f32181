// SPDX-License-Identifier: Apache-2.0
/// @file
/// LevelSetFilter: smoothing and offsetting of narrow-band level sets with interface tracking,
/// with OpenVDB 10's names and meanings. Every operation changes the active values, then
/// rebuilds the band with the LevelSetTracker it derives from (dilate, renormalise with the
/// tracker's schemes and norm count, trim, prune), so the result is again a valid narrow band
/// of the same width, and the surface may move any distance over repeated calls.
///
/// - mean(width): a box filter of edge 2 width + 1 (three one-dimensional passes, along x, z,
///   then y), then a rebuild; gaussian(width): four of those; median(width): the median of the
///   (2 width + 1)^3 box, then a rebuild.
/// - meanCurvature(): one explicit step of mean-curvature flow, phi += dt H |grad phi| with
///   dt = dx^2 / 3 (spheres shrink as r^2 = r0^2 - 2t); laplacian(): one step of the heat
///   equation, phi += dt lap(phi) with dt = dx^2 / 6 (the same flow on a true distance field,
///   and cheaper).
/// - offset(d): adds d (world units) to every active value, in steps of at most half a voxel,
///   each followed by a rebuild: the surface moves d along its normal, inwards for d > 0
///   (OpenVDB's sign: a positive offset erodes, a negative one dilates).
/// - An optional alpha mask (a scalar grid, see Filter.h) blends old and new values as
///   (1 - alpha) old + alpha new.
/// - Widths run from 1 to FILTER_MAX_WIDTH (MEDIAN_FILTER_MAX_WIDTH for the median); anything
///   else, or a non-finite offset, is a ValueError before any work.
///
/// Cost: per pass, one sweep over the active leaves, each gathering its neighbourhood into a
/// dense block; then the tracker's rebuild. Threads: parallel over leaves; results are the same
/// for any thread count.
///
/// @code
/// vdb::tools::LevelSetFilter<vdb::FloatGrid> filter(*sdf);
/// filter.meanCurvature();       // one step of curvature flow
/// filter.offset(-0.1f);         // dilate the surface by 0.1 world units
/// filter.gaussian(1);           // smooth
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/tools/LevelSetTracker.h>
#include <vdb/tools/detail/FilterImpl.h>

#include <cmath>
#include <type_traits>

namespace vdb::tools {

/// Filters a narrow-band level set in place and rebuilds its band after each operation.
///
/// The grid must meet LevelSetTracker's requirements (cubic voxels, floating-point values in
/// world units, a positive background). The filter keeps a reference to the grid, which must
/// outlive it. Threads: one call at a time; each runs in parallel over leaves.
template <typename GridT, typename MaskT = typename GridT::template ValueConverter<float>::Type>
class LevelSetFilter : public LevelSetTracker<GridT> {
public:
    using BaseType = LevelSetTracker<GridT>;
    using GridType = GridT;
    using MaskType = MaskT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename TreeType::ValueType;
    using AlphaType = typename MaskT::ValueType;
    static_assert(std::is_floating_point_v<AlphaType>,
                  "LevelSetFilter needs a mask grid with floating-point values");

    /// @throw ValueError when the voxels are not cubes or the background is not positive.
    explicit LevelSetFilter(GridT& grid) : BaseType(grid) {}

    /// The mask values mapped to alpha 0 and 1 (default 0 and 1).
    AlphaType minMask() const { return mRange.min; }
    AlphaType maxMask() const { return mRange.max; }
    /// @throw ValueError unless min < max.
    void setMaskRange(AlphaType min, AlphaType max) { mRange.set(min, max); }
    bool isMaskInverted() const { return mRange.invert; }
    /// Maps the mask range to alpha 1 to 0 instead of 0 to 1.
    void invertMask(bool invert = true) { mRange.invert = invert; }

    /// One step of mean-curvature flow, then a rebuild.
    void meanCurvature(const MaskT* mask = nullptr);
    /// One step of Laplacian flow, then a rebuild.
    void laplacian(const MaskT* mask = nullptr);
    /// Four box filters of edge 2 width + 1, each followed by a rebuild.
    /// @throw ValueError unless 1 <= width <= FILTER_MAX_WIDTH.
    void gaussian(int width = 1, const MaskT* mask = nullptr);
    /// Adds `offset` (world units) to the values: the surface moves inwards by `offset` (outwards
    /// when negative).
    /// @throw ValueError for a non-finite offset.
    void offset(ValueType offset, const MaskT* mask = nullptr);
    /// A median filter over boxes of edge 2 width + 1, then a rebuild.
    /// @throw ValueError unless 1 <= width <= MEDIAN_FILTER_MAX_WIDTH.
    void median(int width = 1, const MaskT* mask = nullptr);
    /// A box filter of edge 2 width + 1, then a rebuild.
    /// @throw ValueError unless 1 <= width <= FILTER_MAX_WIDTH.
    void mean(int width = 1, const MaskT* mask = nullptr);

private:
    void box(int width, const MaskT* mask);
    /// Runs one filter pass writing buffer 1 with `op`, makes it buffer 0, and rebuilds the band.
    template <typename OpT>
    void passAndTrack(const Coord& radius, detail::BlockShape shape, const MaskT* mask,
                      const OpT& op);
    detail::MaskRange<float> floatRange() const {
        return {float(mRange.min), float(mRange.max), mRange.invert};
    }

    detail::MaskRange<AlphaType> mRange;
};

// ---- Implementation ---------------------------------------------------------------------------

template <typename GridT, typename MaskT>
template <typename OpT>
void LevelSetFilter<GridT, MaskT>::passAndTrack(const Coord& radius, detail::BlockShape shape,
                                                const MaskT* mask, const OpT& op) {
    auto& leaves = this->leafs();
    const bool threaded = this->isThreaded();
    leaves.rebuild();
    leaves.setAuxBufferCount(1, threaded);
    detail::filterPass(leaves, radius, shape, this->grid().transform(), mask, floatRange(), op,
                       threaded);
    leaves.swapLeafBuffers(0, 1, threaded);
    leaves.setAuxBufferCount(0, threaded);
    this->track();
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::box(int width, const MaskT* mask) {
    auto& leaves = this->leafs();
    const bool threaded = this->isThreaded();
    const ValueType frac = ValueType(1) / ValueType(2 * width + 1);
    leaves.rebuild();
    leaves.setAuxBufferCount(1, threaded);
    // x, then z, then y, each pass over the results of the previous one.
    for (const int axis : {0, 2, 1}) {
        Coord radius(0);
        radius[size_t(axis)] = width;
        detail::filterPass(
            leaves, radius, detail::BlockShape::Cross, this->grid().transform(), mask, floatRange(),
            [&](const auto& block, Index n) {
                return detail::boxAverage(block, n, axis, width, frac);
            },
            threaded);
        leaves.swapLeafBuffers(0, 1, threaded);
    }
    leaves.setAuxBufferCount(0, threaded);
    this->track();
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::mean(int width, const MaskT* mask) {
    detail::checkFilterWidth(width, FILTER_MAX_WIDTH, "LevelSetFilter::mean");
    box(width, mask);
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::gaussian(int width, const MaskT* mask) {
    detail::checkFilterWidth(width, FILTER_MAX_WIDTH, "LevelSetFilter::gaussian");
    for (int n = 0; n < 4; ++n)
        box(width, mask);
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::median(int width, const MaskT* mask) {
    detail::checkFilterWidth(width, MEDIAN_FILTER_MAX_WIDTH, "LevelSetFilter::median");
    passAndTrack(Coord(width), detail::BlockShape::Full, mask, [width](const auto& block, Index n) {
        thread_local std::vector<ValueType> scratch;
        return detail::boxMedian(block, n, width, scratch);
    });
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::meanCurvature(const MaskT* mask) {
    const double dx = double(this->voxelSize());
    // phi += dt H |grad phi| with dt = dx^2 / 3; H |grad phi| = alpha / (2 |grad phi|^2 dx^2)
    // from the index-space differences.
    const ValueType dt = ValueType(dx * dx / 3.0);
    const double invDx2 = 1.0 / (dx * dx);
    passAndTrack(Coord(1), detail::BlockShape::Full, mask, [&](const auto& block, Index n) {
        const ValueType* c = block.atOffset(n);
        const auto d = math::centralDerivatives<double>(
            detail::BlockPoint<ValueType>{c, block.sx(), block.sy()});
        double alphaM, alphaG, normGrad;
        if (!math::curvatureTerms(d, alphaM, alphaG, normGrad))
            return *c;
        const ValueType speed = ValueType(alphaM * invDx2 / (2.0 * normGrad * normGrad));
        return *c + dt * speed;
    });
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::laplacian(const MaskT* mask) {
    const ValueType dx = this->voxelSize();
    const ValueType dt = dx * dx / ValueType(6), invDx2 = ValueType(1) / (dx * dx);
    passAndTrack(Coord(1), detail::BlockShape::Cross, mask, [&](const auto& block, Index n) {
        const ValueType* c = block.atOffset(n);
        return *c + dt * (invDx2 * math::centralLaplacian(
                                       detail::BlockPoint<ValueType>{c, block.sx(), block.sy()}));
    });
}

template <typename GridT, typename MaskT>
void LevelSetFilter<GridT, MaskT>::offset(ValueType value, const MaskT* mask) {
    detail::checkFiniteOffset(value, "LevelSetFilter::offset");
    // Steps of at most half a voxel, each followed by a rebuild, until within a thousandth of
    // the step of the requested distance.
    const ValueType cfl = ValueType(0.5) * this->voxelSize(), total = std::abs(value);
    ValueType dist = 0;
    while (total - dist > ValueType(0.001) * cfl) {
        const ValueType delta = std::min(total - dist, cfl);
        dist += delta;
        auto& leaves = this->leafs();
        leaves.rebuild();
        detail::offsetPass(leaves, ValueType(std::copysign(delta, value)), this->grid().transform(),
                           mask, floatRange(), this->isThreaded());
        this->track();
    }
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/Filter.cpp

namespace vdb::tools {

extern template class LevelSetFilter<FloatGrid, FloatGrid>;
extern template class LevelSetFilter<DoubleGrid, FloatGrid>;

}  // namespace vdb::tools
