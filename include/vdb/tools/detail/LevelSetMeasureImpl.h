// SPDX-License-Identifier: Apache-2.0
/// @file
/// The implementation of tools/LevelSetMeasure.h (not API).

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/tools/LevelSetTracker.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tree/LeafManager.h>
#include <vdb/tree/ValueAccessor.h>
#include <vdb/util/Parallel.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

namespace detail {

/// The smeared Dirac delta of LevelSetMeasure, (1 + cos(pi x / e)) / (2e) for |x| <= e, else 0.
class DiracDelta {
public:
    explicit DiracDelta(double e) : mC(0.5 / e), mD(std::numbers::pi / e), mE(e) {}
    double operator()(double x) const {
        return std::abs(x) > mE ? 0.0 : mC * (1.0 + std::cos(mD * x));
    }

private:
    double mC, mD, mE;
};

/// Half the width, in voxels, of the smeared delta of the level set measures.
inline constexpr double MEASURE_DELTA_HALF_WIDTH = 1.5;

/// Throws TypeError, naming the grid and its type, unless GridT holds floating-point scalars.
template <typename GridT>
void requireScalarLevelSet(const GridT& grid, const char* who) {
    if constexpr (!std::is_floating_point_v<typename GridT::ValueType>) {
        throw TypeError(std::string(who) + " needs a scalar floating-point level set; grid \"" +
                        grid.getName() + "\" has type " + grid.type());
    }
}

/// Adds up `values` in ascending order (OpenVDB's order: it keeps cancellation between large
/// partial sums of opposite sign small, and it is fixed by the data alone).
inline double sortedSum(std::vector<double>& values) {
    std::sort(values.begin(), values.end());
    double sum = 0.0;
    for (double v : values)
        sum += v;
    return sum;
}

/// True when a voxel of `leaf` is active and within `reach` (in the values' units) of zero.
template <typename LeafT>
bool nearZero(const LeafT& leaf, typename LeafT::ValueType reach) {
    const auto* values = leaf.buffer(0).data();
    for (auto it = leaf.cbeginValueOn(); it; ++it) {
        if (std::abs(values[it.pos()]) <= reach)
            return true;
    }
    return false;
}

/// The smeared inside fraction of a voxel with value `v`, for half width `e` (same units).
inline double insideFraction(double v, double e) {
    if (v <= -e)
        return 1.0;
    if (v >= e)
        return 0.0;
    const double x = -v;
    return 0.5 + x / (2.0 * e) + std::sin(std::numbers::pi * x / e) / (2.0 * std::numbers::pi);
}

/// Runs `op(leaf, block, index, sums)` over the leaves of `grid` near its surface, with the
/// leaf's neighbourhood (depth 1, of `shape`) in `block`; `sums` holds `K` per-leaf sums (zero
/// for the leaves far from the surface). Returns each sum over all leaves, added in ascending
/// order.
template <int K, typename GridT, typename OpT>
std::array<double, K> sumOverSurfaceLeaves(const GridT& grid, BlockShape shape, double reach,
                                           int grain, const OpT& op) {
    using TreeT = typename GridT::TreeType;
    using ValueT = typename GridT::ValueType;
    const tree::LeafManager<const TreeT> leaves(grid.tree());
    const size_t n = leaves.leafCount();
    std::array<std::vector<double>, K> parts;
    for (auto& p : parts)
        p.assign(n, 0.0);
    util::parallelForRange(
        n,
        [&](size_t begin, size_t end) {
            const tree::ValueAccessor<const TreeT> acc(grid.tree());
            NeighborhoodBlock<TreeT> block(Coord(1), shape);
            for (size_t i = begin; i < end; ++i) {
                const auto& leaf = leaves.leaf(i);
                if (!nearZero(leaf, ValueT(reach)))
                    continue;
                block.gather(leaf.origin(), &leaf, 0, acc);
                std::array<double, K> sums{};
                op(leaf, block, sums);
                for (int k = 0; k < K; ++k)
                    parts[size_t(k)][i] = sums[size_t(k)];
            }
        },
        grain > 0, size_t(std::max(grain, 1)));
    std::array<double, K> totals;
    for (int k = 0; k < K; ++k)
        totals[size_t(k)] = sortedSum(parts[size_t(k)]);
    return totals;
}

/// Calls `f(offset, centre)` for every active voxel of `leaf`, with `centre` its position in
/// `block`.
template <typename LeafT, typename BlockT, typename FuncT>
void forEachActiveInBlock(const LeafT& leaf, const BlockT& block, const FuncT& f) {
    const auto* words = leaf.getValueMask().words();
    for (Index w = 0; w < LeafT::MaskType::WORD_COUNT; ++w) {
        for (uint64_t bits = words[w]; bits; bits &= bits - 1) {
            const Index n = (w << 6) + Index(std::countr_zero(bits));
            f(n, block.atOffset(n));
        }
    }
}

}  // namespace detail

template <typename GridT>
void LevelSetMeasure<GridT>::init(const GridT& grid) {
    mDx = double(detail::checkedLevelSetVoxelSize(grid));
    if (grid.getGridClass() != GRID_LEVEL_SET)
        throw ValueError("LevelSetMeasure: grid \"" + grid.getName() +
                         "\" is not a level set (set its class to GRID_LEVEL_SET)");
    if (grid.empty())
        throw ValueError("LevelSetMeasure: grid \"" + grid.getName() + "\" is empty");
    mGrid = &grid;
    mHasArea = mHasCurvature = false;
}

template <typename GridT>
void LevelSetMeasure<GridT>::measureAreaAndVolume() {
    using LeafT = typename TreeType::LeafNodeType;
    const double invDx = 1.0 / mDx;
    const detail::DiracDelta delta(detail::MEASURE_DELTA_HALF_WIDTH);
    const auto totals = detail::sumOverSurfaceLeaves<2>(
        *mGrid, detail::BlockShape::Cross, detail::MEASURE_DELTA_HALF_WIDTH * mDx, mGrainSize,
        [&](const LeafT& leaf, const auto& block, std::array<double, 2>& sums) {
            const int sx = block.sx(), sy = block.sy();
            const ValueType* values = leaf.buffer(0).data();
            detail::forEachActiveInBlock(leaf, block, [&](Index n, const ValueType* c) {
                const double dd = delta(double(values[n]) * invDx);
                if (!(dd > 0.0))
                    return;
                const detail::BlockPoint<ValueType> p{c, sx, sy};
                // The gradient in world units is the index-space gradient of phi / dx.
                const Vec3d g(double(math::centralDiff<0>(p)) * invDx,
                              double(math::centralDiff<1>(p)) * invDx,
                              double(math::centralDiff<2>(p)) * invDx);
                const Vec3d x(leaf.offsetToGlobalCoord(n));
                sums[0] += dd * g.length();
                sums[1] += dd * g.dot(x);
            });
        });
    mArea = totals[0];
    mVolume = totals[1] / 3.0;
    mHasArea = true;
}

template <typename GridT>
void LevelSetMeasure<GridT>::measureCurvatures() {
    using LeafT = typename TreeType::LeafNodeType;
    const double invDx = 1.0 / mDx;
    const detail::DiracDelta delta(detail::MEASURE_DELTA_HALF_WIDTH);
    const auto totals = detail::sumOverSurfaceLeaves<2>(
        *mGrid, detail::BlockShape::Full, detail::MEASURE_DELTA_HALF_WIDTH * mDx, mGrainSize,
        [&](const LeafT& leaf, const auto& block, std::array<double, 2>& sums) {
            const int sx = block.sx(), sy = block.sy();
            const ValueType* values = leaf.buffer(0).data();
            detail::forEachActiveInBlock(leaf, block, [&](Index n, const ValueType* c) {
                const double dd = delta(double(values[n]) * invDx);
                if (!(dd > 0.0))
                    return;
                // Index-space derivatives of phi in world units: |grad phi| is about 1, the
                // curvatures come out in voxel units.
                const auto d =
                    math::centralDerivatives<double>(detail::BlockPoint<ValueType>{c, sx, sy});
                double alphaM, alphaG, normGrad;
                if (!math::curvatureTerms(d, alphaM, alphaG, normGrad))
                    return;
                const double area = dd * normGrad * invDx;
                const double g2 = normGrad * normGrad;
                sums[0] += area * alphaM / (2.0 * g2 * normGrad);
                sums[1] += area * alphaG / (g2 * g2);
            });
        });
    mTotMeanCurvature = totals[0];
    mTotGaussCurvature = totals[1];
    mHasCurvature = true;
}

template <typename GridT>
double LevelSetMeasure<GridT>::area(bool useWorldUnits) {
    if (!mHasArea)
        measureAreaAndVolume();
    return useWorldUnits ? mArea * mDx * mDx : mArea;
}

template <typename GridT>
double LevelSetMeasure<GridT>::volume(bool useWorldUnits) {
    if (!mHasArea)
        measureAreaAndVolume();
    return useWorldUnits ? mVolume * mDx * mDx * mDx : mVolume;
}

template <typename GridT>
double LevelSetMeasure<GridT>::totMeanCurvature(bool useWorldUnits) {
    if (!mHasCurvature)
        measureCurvatures();
    return useWorldUnits ? mTotMeanCurvature * mDx : mTotMeanCurvature;
}

template <typename GridT>
double LevelSetMeasure<GridT>::totGaussianCurvature(bool) {
    if (!mHasCurvature)
        measureCurvatures();
    return mTotGaussCurvature;
}

template <typename GridT>
int LevelSetMeasure<GridT>::eulerCharacteristic() {
    return int(std::lround(totGaussianCurvature() / (2.0 * std::numbers::pi)));
}

template <typename GridT>
double levelSetArea(const GridT& grid, bool useWorldSpace) {
    detail::requireScalarLevelSet(grid, "levelSetArea");
    if constexpr (std::is_floating_point_v<typename GridT::ValueType>)
        return LevelSetMeasure<GridT>(grid).area(useWorldSpace);
    return 0.0;
}

template <typename GridT>
double levelSetVolume(const GridT& grid, bool useWorldSpace) {
    detail::requireScalarLevelSet(grid, "levelSetVolume");
    if constexpr (std::is_floating_point_v<typename GridT::ValueType>)
        return LevelSetMeasure<GridT>(grid).volume(useWorldSpace);
    return 0.0;
}

template <typename GridT>
int levelSetEulerCharacteristic(const GridT& grid) {
    detail::requireScalarLevelSet(grid, "levelSetEulerCharacteristic");
    if constexpr (std::is_floating_point_v<typename GridT::ValueType>)
        return LevelSetMeasure<GridT>(grid).eulerCharacteristic();
    return 0;
}

template <typename GridT>
int levelSetGenus(const GridT& grid) {
    detail::requireScalarLevelSet(grid, "levelSetGenus");
    if constexpr (std::is_floating_point_v<typename GridT::ValueType>)
        return LevelSetMeasure<GridT>(grid).genus();
    return 0;
}

template <typename GridT>
double smearedHeavisideVolume(const GridT& grid, double smearing, bool threaded) {
    using TreeT = typename GridT::TreeType;
    const double dx = grid.voxelSize()[0];
    const double e = smearing * dx;
    const tree::LeafManager<const TreeT> leaves(grid.tree());
    double voxels = util::parallelReduce(
        leaves.leafCount(), 0.0,
        [&](size_t begin, size_t end) {
            double sum = 0.0;
            for (size_t i = begin; i < end; ++i) {
                const auto& leaf = leaves.leaf(i);
                for (Index n = 0; n < leaf.NUM_VALUES; ++n)
                    sum += detail::insideFraction(double(leaf.getValue(n)), e);
            }
            return sum;
        },
        [](double a, double b) { return a + b; }, threaded, 64);
    // Tiles: every value above the leaves stands for a cube of voxels.
    for (auto it = grid.tree().cbeginValueAll(); it; ++it) {
        if (it.getLevel() == 0)
            continue;
        CoordBBox box;
        it.getBoundingBox(box);
        const auto d = box.dim();
        voxels += double(d[0]) * double(d[1]) * double(d[2]) *
                  detail::insideFraction(double(it.getValue()), e);
    }
    return voxels * dx * dx * dx;
}

}  // namespace vdb::tools
