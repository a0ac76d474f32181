// SPDX-License-Identifier: Apache-2.0
/// @file
/// LevelSetTracker: renormalisation of a narrow-band level set (the Eikonal equation) and the
/// rebuild of its band after the interface moved (paper 4.2).
///
/// normalize() runs getNormCount() pseudo-time steps of the reinitialisation equation
///   phi_t + S(phi) (|grad phi| - 1) = 0,   S(phi) = phi / sqrt(phi^2 + |grad phi|^2 dx^2)
/// (Peng et al. 1999) on the active voxels, with Godunov's upwind |grad phi| from first-order or
/// HJ-WENO5 one-sided differences and a TVD Runge-Kutta scheme in the leaves' temporal buffers,
/// pseudo-time step CFL * dx (CFL 0.3).
///
/// track() is the paper's rebuild: dilate the active voxels by one (face neighbours), normalize,
/// deactivate every voxel whose |value| reached the half width (it becomes -background inside
/// or +background outside), and prune nodes left without active values to inactive tiles of
/// the right sign. The band thus stays 2 x half width voxels wide, the half width being
/// background / voxel size (3 for OpenVDB's default level sets, 5 for the paper's Enright set-up).
///
/// Cost: per normalisation step, one pass over the active voxels per Runge-Kutta stage (19
/// reads from a per-leaf block for HJ-WENO5), plus six neighbour lookups per leaf. Threads:
/// parallel over leaves; results are bit-identical for any number of threads.
///
/// @code
/// vdb::tools::LevelSetTracker<vdb::FloatGrid> tracker(*grid);
/// tracker.setNormCount(3);
/// tracker.normalize();   // reinitialise the values
/// tracker.track();       // rebuild the band
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/FiniteDifference.h>
#include <vdb/tools/Morphology.h>
#include <vdb/tools/Prune.h>
#include <vdb/tools/detail/LevelSetKernels.h>
#include <vdb/tree/LeafManager.h>

#include <cmath>
#include <memory>
#include <type_traits>

namespace vdb::tools {

/// Half width, in voxels, of OpenVDB's default narrow band (openvdb::LEVEL_SET_HALF_WIDTH).
inline constexpr double LEVEL_SET_HALF_WIDTH = 3.0;

/// Renormalises and rebuilds the narrow band of one level set grid.
///
/// The grid must have a uniform voxel size and floating-point values in world units, with
/// inactive values of -background inside and +background outside (as createLevelSetSphere and
/// signedFloodFill leave them). The tracker keeps a reference to the grid, which must outlive
/// it; the grid's topology may change between calls.
/// Threads: one call at a time; each call runs parallel over leaves.
template <typename GridT>
class LevelSetTracker {
public:
    using GridType = GridT;
    using TreeType = typename GridT::TreeType;
    using ValueType = typename GridT::ValueType;
    using LeafManagerType = tree::LeafManager<TreeType>;
    static_assert(std::is_floating_point_v<ValueType>,
                  "LevelSetTracker needs a level set grid with floating-point values");

    /// @throw ValueError when the voxels are not cubes or the background is not positive.
    explicit LevelSetTracker(GridT& grid);

    GridT& grid() { return *mGrid; }
    const GridT& grid() const { return *mGrid; }
    /// The leaves of the grid as of the last call.
    LeafManagerType& leafs() { return *mLeaves; }

    math::BiasedGradientScheme getSpatialScheme() const { return mSpatialScheme; }
    /// @throw ValueError for a scheme this library does not implement.
    void setSpatialScheme(math::BiasedGradientScheme s);
    math::TemporalIntegrationScheme getTemporalScheme() const { return mTemporalScheme; }
    /// @throw ValueError for UNKNOWN_TIS.
    void setTemporalScheme(math::TemporalIntegrationScheme s);
    /// Pseudo-time steps per normalize() (default 3, OpenVDB's default).
    int getNormCount() const { return mNormCount; }
    void setNormCount(int n) { mNormCount = n < 0 ? 0 : n; }
    /// CFL number of the pseudo-time step (default 0.3): the step is cfl * voxel size.
    ValueType getCFL() const { return mCfl; }
    /// @throw ValueError unless 0 < cfl <= 1.
    void setCFL(ValueType cfl);
    /// Whether work runs in parallel over leaves (default true); results are the same either way.
    bool isThreaded() const { return mThreaded; }
    void setThreaded(bool threaded) { mThreaded = threaded; }

    /// World units per voxel.
    ValueType voxelSize() const { return mDx; }
    /// Half the band width in voxels: background / voxel size.
    ValueType getHalfWidth() const { return mGrid->background() / mDx; }

    /// Runs getNormCount() steps of the reinitialisation equation on the active voxels.
    void normalize();
    /// Rebuilds the band: dilate by one, normalize, trim to the half width, prune.
    void track();
    /// Activates the face neighbours of the active voxels, `iterations` times (new voxels keep
    /// their +-background values).
    void dilate(int iterations = 1);
    /// Deactivates active voxels whose |value| is at least the background (they become
    /// -background or +background) and prunes nodes left without active values.
    void prune();

private:
    template <math::BiasedGradientScheme Scheme>
    void normalizeWith();
    void rebuildLeaves() { mLeaves->rebuild(); }

    GridT* mGrid;
    std::unique_ptr<LeafManagerType> mLeaves;
    ValueType mDx;
    math::BiasedGradientScheme mSpatialScheme = math::HJWENO5_BIAS;
    math::TemporalIntegrationScheme mTemporalScheme = math::TVD_RK1;
    int mNormCount = int(LEVEL_SET_HALF_WIDTH);
    ValueType mCfl = ValueType(0.3);
    bool mThreaded = true;
};

// ---- Implementation ---------------------------------------------------------------------------

namespace detail {

/// Throws ValueError for a grid a level set tool cannot work on.
template <typename GridT>
typename GridT::ValueType checkedLevelSetVoxelSize(const GridT& grid) {
    const Vec3d vs = grid.voxelSize();
    if (!(vs[0] > 0.0) || std::abs(vs[0] - vs[1]) > 1e-8 * vs[0] ||
        std::abs(vs[0] - vs[2]) > 1e-8 * vs[0] || !grid.transform().isLinear()) {
        throw ValueError("level set tools need a linear transform with cubic voxels");
    }
    if (!(grid.background() > typename GridT::ValueType(0)))
        throw ValueError("a level set's background (half the band width) must be positive");
    return typename GridT::ValueType(vs[0]);
}

inline void checkSupported(math::BiasedGradientScheme s) {
    if (!math::isSupported(s)) {
        throw ValueError(
            "spatial scheme not implemented: use FIRST_BIAS, SECOND_BIAS, THIRD_BIAS or "
            "HJWENO5_BIAS");
    }
}
inline void checkSupported(math::TemporalIntegrationScheme s) {
    if (!math::isSupported(s))
        throw ValueError("temporal scheme not implemented: use TVD_RK1, TVD_RK2 or TVD_RK3");
}

/// Calls `f.template operator()<Scheme>()` with the scheme `s` as a compile-time constant.
template <typename FuncT>
void dispatchSpatialScheme(math::BiasedGradientScheme s, const FuncT& f) {
    switch (s) {
        case math::FIRST_BIAS:
            f.template operator()<math::FIRST_BIAS>();
            break;
        case math::SECOND_BIAS:
            f.template operator()<math::SECOND_BIAS>();
            break;
        case math::THIRD_BIAS:
            f.template operator()<math::THIRD_BIAS>();
            break;
        case math::HJWENO5_BIAS:
            f.template operator()<math::HJWENO5_BIAS>();
            break;
        default:
            checkSupported(s);
    }
}

}  // namespace detail

template <typename GridT>
LevelSetTracker<GridT>::LevelSetTracker(GridT& grid)
    : mGrid(&grid),
      mLeaves(std::make_unique<LeafManagerType>(grid.tree())),
      mDx(detail::checkedLevelSetVoxelSize(grid)) {}

template <typename GridT>
void LevelSetTracker<GridT>::setSpatialScheme(math::BiasedGradientScheme s) {
    detail::checkSupported(s);
    mSpatialScheme = s;
}

template <typename GridT>
void LevelSetTracker<GridT>::setTemporalScheme(math::TemporalIntegrationScheme s) {
    detail::checkSupported(s);
    mTemporalScheme = s;
}

template <typename GridT>
void LevelSetTracker<GridT>::setCFL(ValueType cfl) {
    if (!(cfl > ValueType(0) && cfl <= ValueType(1)))
        throw ValueError("LevelSetTracker: the CFL number must lie in (0, 1]");
    mCfl = cfl;
}

template <typename GridT>
void LevelSetTracker<GridT>::normalize() {
    detail::dispatchSpatialScheme(mSpatialScheme, [this]<math::BiasedGradientScheme S>() {
        this->template normalizeWith<S>();
    });
}

template <typename GridT>
template <math::BiasedGradientScheme Scheme>
void LevelSetTracker<GridT>::normalizeWith() {
    rebuildLeaves();
    if (mNormCount == 0 || mLeaves->leafCount() == 0)
        return;
    constexpr int R = math::stencilRadius(Scheme);
    using Block = detail::LeafNeighborhood<TreeType, R>;
    const ValueType dt = mCfl * mDx, invDx = ValueType(1) / mDx;
    // phi_t = -sign(phi) (|grad phi| - 1), a row of voxels at a time. The square roots have a
    // loop of their own: built where math functions may set errno (the default outside this
    // library's sources, see CMakeLists.txt), that loop stays scalar and the others do not.
    constexpr int DIM = Block::DIM;
    const auto eikonal = [dt, invDx](size_t, Index, uint64_t, const ValueType* c, ValueType* res) {
        ValueType dm[3][DIM], dp[3][DIM], g2[DIM], norm[DIM], grad[DIM];
        detail::rowDifferences<Scheme>(c, Block::SX, Block::SY, dm, dp);
        for (int k = 0; k < DIM; ++k) {
            const ValueType phi = c[k];
            g2[k] = math::godunovNormSqrd(phi > ValueType(0), dm[0][k], dp[0][k], dm[1][k],
                                          dp[1][k], dm[2][k], dp[2][k]);
            norm[k] = phi * phi + g2[k];
        }
        for (int k = 0; k < DIM; ++k) {
            norm[k] = std::sqrt(norm[k]);
            grad[k] = std::sqrt(g2[k]);
        }
        for (int k = 0; k < DIM; ++k) {
            const ValueType phi = c[k];
            const ValueType sign = phi / (norm[k] + math::Tolerance<ValueType>::value());
            res[k] = phi - dt * sign * (grad[k] * invDx - ValueType(1));
        }
    };
    const auto stage = [&](Index src, Index dst, ValueType alpha) {
        detail::eulerStage<R>(*mLeaves, src, dst, alpha, eikonal, mThreaded);
    };
    mLeaves->setAuxBufferCount(Index(math::auxBufferCount(mTemporalScheme)), mThreaded);
    for (int n = 0; n < mNormCount; ++n)
        detail::rungeKuttaStep(*mLeaves, mTemporalScheme, stage, mThreaded);
    mLeaves->setAuxBufferCount(0, mThreaded);
}

template <typename GridT>
void LevelSetTracker<GridT>::dilate(int iterations) {
    if (iterations > 0)
        dilateActiveValues(mGrid->tree(), iterations, NN_FACE, IGNORE_TILES, mThreaded);
    rebuildLeaves();
}

template <typename GridT>
void LevelSetTracker<GridT>::prune() {
    rebuildLeaves();
    const ValueType gamma = mGrid->background();
    mLeaves->foreach (
        [gamma](auto& leaf, size_t) {
            for (auto it = leaf.beginValueOn(); it; ++it) {
                const ValueType v = *it;
                if (v <= -gamma) {
                    leaf.setValueOff(it.pos(), -gamma);
                } else if (v >= gamma) {
                    leaf.setValueOff(it.pos(), gamma);
                }
            }
        },
        mThreaded);
    pruneLevelSet(mGrid->tree(), mThreaded);
    rebuildLeaves();
}

template <typename GridT>
void LevelSetTracker<GridT>::track() {
    dilate(1);
    normalize();
    prune();
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetAdvect.cpp

namespace vdb::tools {

extern template class LevelSetTracker<FloatGrid>;
extern template class LevelSetTracker<DoubleGrid>;

}  // namespace vdb::tools
