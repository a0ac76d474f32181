// SPDX-License-Identifier: Apache-2.0
/// @file
/// Signed distance fields and extension fields by the fast sweeping method, with OpenVDB 10's
/// names and meanings: re-distancing a fog volume or a distorted level set band, widening a
/// band by any number of voxels, filling a mask with distances, and extending a field given on
/// a surface (a velocity, a colour) along the surface normals.
///
/// The eikonal equation |grad phi| = 1 is solved on the active voxels with the first-order
/// Godunov upwind scheme (Zhao, "A fast sweeping method for eikonal equations", Math. Comp. 74,
/// 2005): each voxel takes the smallest root of sum_a max(phi - n_a, 0)^2 = h^2 over its
/// closest neighbours n_a along the three axes, and Gauss-Seidel sweeps visit the voxels in
/// the eight diagonal orders (+x+y+z, then -x-y-z, then +x+y-z, ...). The boundary condition is
/// set on the voxels next to the isosurface, from the linear interpolation of the crossing
/// along each axis. An extension field is carried along with the same upwind weights, so it
/// is constant along the characteristics (the normals of the distance field).
///
/// Accuracy: first order. On smooth surfaces the distances near the surface are within a few
/// hundredths of a voxel, and the error grows with the distance (to about one voxel at 20 to 50
/// voxels from a sphere of radius 30 to 100 voxels); one iteration (eight sweeps) suffices for
/// convex shapes, concave ones may need more.
///
/// Threads: one sweep processes the voxels of equal x +- y +- z (hyperplanes of the sweep
/// direction) in parallel: voxels of one hyperplane are never face neighbours, so the result
/// is the same, bit for bit, for every thread count. Cost per sweep: O(active voxels) plus a
/// few 64-bit mask operations per leaf and hyperplane.
///
/// Differences from OpenVDB 10, which does the same computation:
/// - Active tiles become active voxels for every input (OpenVDB throws for level sets).
/// - Neighbours are "unknown" only while they still hold the initial +-max; OpenVDB also
///   ignores neighbours at 1000 world units or more, so its sweeps stop there.
/// - The extension grid gets the input's transform, and the functor is called at world
///   positions (OpenVDB 10 gives the extension grid an identity transform and calls the
///   functor at index positions).
/// - fogToSdf() and fogToSdfAndExt() mark their result GRID_LEVEL_SET.
/// - A grid whose every active voxel is a boundary voxel is still finalized (its background
///   and inactive values set from the extrema); OpenVDB returns it with a background of max.
///
/// @code
/// auto sdf = vdb::tools::fogToSdf(*density, /*isoValue=*/0.5f);       // level set, same voxels
/// auto wide = vdb::tools::dilateSdf(*levelSet, /*dilation=*/20);      // a 26-voxel band
/// auto vel = vdb::tools::sdfToExt(*levelSet, [](const vdb::Vec3d& xyz) {
///     return vdb::Vec3s(float(-xyz[1]), float(xyz[0]), 0.0f);  // the surface velocity
/// }, vdb::Vec3s(0.0f), 0.0f);
/// @endcode

#pragma once

#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/Morphology.h>

#include <cstddef>
#include <type_traits>
#include <utility>
#include <vector>

namespace vdb::tools {

/// Which voxels fast sweeping updates (the side of the isosurface, for dilateSdf() and the
/// extension functions).
enum class FastSweepingDomain {
    SWEEP_ALL,                    ///< every voxel the sweeps reach
    SWEEP_GREATER_THAN_ISOVALUE,  ///< only voxels on the side of values above the isovalue
    SWEEP_LESS_THAN_ISOVALUE      ///< only voxels on the side of values below the isovalue
};

/// Returns a signed distance field of the isosurface at `isoValue` of the fog volume (any
/// scalar grid whose values rise towards the inside) `fogGrid`, on its active voxels: values
/// above the isovalue are inside (negative). Active tiles become active voxels; the result is
/// a GRID_LEVEL_SET with the inactive values and background set to the extrema of the
/// distances. `nIter` iterations of eight sweeps.
/// When no active voxel is next to the isosurface, the active values are +-max (OpenVDB's
/// behaviour); FastSweeping::initSdf() reports that case.
template <typename GridT>
typename GridT::Ptr fogToSdf(const GridT& fogGrid, typename GridT::ValueType isoValue,
                             int nIter = 1);

/// As fogToSdf() for an approximate signed distance field (values above the isovalue are
/// outside, positive): restores |grad| = 1 over the whole active band, which may be far wider
/// than a narrow band.
template <typename GridT>
typename GridT::Ptr sdfToSdf(const GridT& sdfGrid, typename GridT::ValueType isoValue = 0,
                             int nIter = 1);

/// The extension off the isosurface of `fogGrid` at `isoValue` of the field `op(const Vec3d&
/// xyz) -> ExtValueT` (world positions on the surface), on the active voxels of `fogGrid`.
/// With a `mode` other than SWEEP_ALL, `extGrid` (same transform) gives the values on the
/// other side. Floating-point and vector fields are interpolated; integer fields take the
/// nearest value.
/// @throw ValueError when `mode` is not SWEEP_ALL and `extGrid` is null or in another index
///        space.
template <typename FogGridT, typename ExtOpT, typename ExtValueT>
typename FogGridT::template ValueConverter<ExtValueT>::Type::Ptr fogToExt(
    const FogGridT& fogGrid, const ExtOpT& op, const ExtValueT& background,
    typename FogGridT::ValueType isoValue, int nIter = 1,
    FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL,
    const typename FogGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid = nullptr);

/// As fogToExt() for a signed distance field.
template <typename SdfGridT, typename ExtOpT, typename ExtValueT>
typename SdfGridT::template ValueConverter<ExtValueT>::Type::Ptr sdfToExt(
    const SdfGridT& sdfGrid, const ExtOpT& op, const ExtValueT& background,
    typename SdfGridT::ValueType isoValue = 0, int nIter = 1,
    FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL,
    const typename SdfGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid = nullptr);

/// fogToSdf() and fogToExt() in one pass: (distance field, extension field).
template <typename FogGridT, typename ExtOpT, typename ExtValueT>
std::pair<typename FogGridT::Ptr, typename FogGridT::template ValueConverter<ExtValueT>::Type::Ptr>
fogToSdfAndExt(
    const FogGridT& fogGrid, const ExtOpT& op, const ExtValueT& background,
    typename FogGridT::ValueType isoValue, int nIter = 1,
    FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL,
    const typename FogGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid = nullptr);

/// sdfToSdf() and sdfToExt() in one pass: (distance field, extension field).
template <typename SdfGridT, typename ExtOpT, typename ExtValueT>
std::pair<typename SdfGridT::Ptr, typename SdfGridT::template ValueConverter<ExtValueT>::Type::Ptr>
sdfToSdfAndExt(
    const SdfGridT& sdfGrid, const ExtOpT& op, const ExtValueT& background,
    typename SdfGridT::ValueType isoValue = 0, int nIter = 1,
    FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL,
    const typename SdfGridT::template ValueConverter<ExtValueT>::Type::ConstPtr extGrid = nullptr);

/// Widens the band of the signed distance field `sdfGrid` by `dilation` voxels (morphological
/// dilation of the active voxels with `nn`, then distances in the new voxels by sweeping from
/// the old band, whose voxels keep their values). With SWEEP_GREATER_THAN_ISOVALUE or
/// SWEEP_LESS_THAN_ISOVALUE only the outside or the inside grows. Not to be confused with
/// LevelSetFilter::offset(), which moves the surface.
template <typename GridT>
typename GridT::Ptr dilateSdf(const GridT& sdfGrid, int dilation, NearestNeighbors nn = NN_FACE,
                              int nIter = 1,
                              FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL);

/// Extends the signed distance field `sdfGrid` into the active voxels of `mask` (same index
/// space): the result's active voxels are the union of both. A level set mask stands for its
/// interior; otherwise active tiles of the mask count as active voxels unless
/// `ignoreActiveTiles`. @throw ValueError when the transforms differ.
template <typename GridT, typename MaskTreeT>
typename GridT::Ptr maskSdf(const GridT& sdfGrid, const Grid<MaskTreeT>& mask,
                            bool ignoreActiveTiles = false, int nIter = 1);

/// The solver behind the functions above: one init*() call sets up the boundary condition and
/// the voxels to solve for on a copy of the input, then sweep() solves.
///
/// Invariants after a successful init: every active value of sdfGrid() lies in a leaf; the
/// boundary voxels hold their distance, the voxels to solve for hold +-max (the sign of their
/// side), and every value outside the leaves is +-max.
/// Threads: one object per computation; the methods are internally parallel.
template <typename SdfGridT, typename ExtValueT = typename SdfGridT::ValueType>
class FastSweeping {
    static_assert(std::is_floating_point_v<typename SdfGridT::ValueType>,
                  "FastSweeping needs a grid of floating-point values");

public:
    using SdfValueT = typename SdfGridT::ValueType;
    using SdfTreeT = typename SdfGridT::TreeType;
    using ExtGridT = typename SdfGridT::template ValueConverter<ExtValueT>::Type;
    using ExtTreeT = typename ExtGridT::TreeType;
    using LeafT = typename SdfTreeT::LeafNodeType;
    using ExtLeafT = typename ExtTreeT::LeafNodeType;
    using MaskT = typename LeafT::MaskType;

    FastSweeping() = default;
    FastSweeping(const FastSweeping&) = delete;
    FastSweeping& operator=(const FastSweeping&) = delete;

    /// The distance field (null before an init).
    typename SdfGridT::Ptr sdfGrid() { return mSdfGrid; }
    /// The extension field (null unless initExt() was called).
    typename ExtGridT::Ptr extGrid() { return mExtGrid; }
    /// The extension values kept on the side that is not swept (null with SWEEP_ALL).
    typename ExtGridT::ConstPtr extGridInput() { return mExtGridInput; }

    /// Sets up the distance computation of the isosurface at `isoValue` of `sdfGrid`, a signed
    /// distance field when `isInputSdf` (above the isovalue is outside) or a fog volume (above
    /// is inside). Returns isValid().
    bool initSdf(const SdfGridT& sdfGrid, SdfValueT isoValue, bool isInputSdf);

    /// As initSdf(), and the extension of `op` (see fogToExt()) with background `background`.
    /// @throw ValueError when `mode` is not SWEEP_ALL and `extGrid` is null or in another index
    ///        space.
    template <typename ExtOpT>
    bool initExt(const SdfGridT& sdfGrid, const ExtOpT& op, const ExtValueT& background,
                 SdfValueT isoValue, bool isInputSdf,
                 FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL,
                 const typename ExtGridT::ConstPtr extGrid = nullptr);

    /// Sets up the widening of the band of `sdfGrid` by `dilation` voxels (see dilateSdf()).
    /// @throw ValueError when `dilation` is negative.
    bool initDilate(const SdfGridT& sdfGrid, int dilation, NearestNeighbors nn = NN_FACE,
                    FastSweepingDomain mode = FastSweepingDomain::SWEEP_ALL);

    /// Sets up the extension of `sdfGrid` into `mask` (see maskSdf()).
    /// @throw ValueError when the transforms differ.
    template <typename MaskTreeT>
    bool initMask(const SdfGridT& sdfGrid, const Grid<MaskTreeT>& mask,
                  bool ignoreActiveTiles = false);

    /// Runs `nIter` iterations of eight sweeps, then, when `finalize`, replaces the values
    /// still at +-max and every inactive value by the extrema of the distances (which become
    /// the background, asymmetric: outside the largest, inside the smallest).
    /// @throw RuntimeError before a successful init (no boundary voxels).
    void sweep(int nIter = 1, bool finalize = true);

    /// Drops the grids and counters.
    void clear();

    /// The number of active voxels solved for.
    size_t sweepingVoxelCount() const { return mSweepingVoxelCount; }
    /// The number of active voxels that hold the boundary condition.
    size_t boundaryVoxelCount() const { return mBoundaryVoxelCount; }
    /// True when there are voxels to solve for and a boundary to solve from.
    bool isValid() const { return mSweepingVoxelCount > 0 && mBoundaryVoxelCount > 0; }
    FastSweepingDomain sweepDirection() const { return mSweepDirection; }
    bool isInputSdf() const { return mIsInputSdf; }

private:
    template <typename ExtOpT>
    void initBoundary(const SdfGridT& input, SdfValueT isoValue, const ExtOpT* op);
    void initFromBand(const SdfGridT& input, SdfValueT boundaryBelow);
    void collectLeaves();
    void finalizeValues();

    typename SdfGridT::Ptr mSdfGrid;
    typename ExtGridT::Ptr mExtGrid;
    typename ExtGridT::ConstPtr mExtGridInput;
    std::vector<LeafT*> mLeaves;     // the leaves of mSdfGrid's tree
    std::vector<MaskT> mSweepMasks;  // per leaf: the active voxels to solve for
    size_t mSweepingVoxelCount = 0, mBoundaryVoxelCount = 0;
    FastSweepingDomain mSweepDirection = FastSweepingDomain::SWEEP_ALL;
    bool mIsInputSdf = true;
};

}  // namespace vdb::tools

// ---- Implementation ---------------------------------------------------------------------------

#include <vdb/tools/detail/FastSweepingImpl.h>

// ---- Instantiated once in src/instantiate/FastSweeping.cpp

namespace vdb::tools {

extern template class FastSweeping<FloatGrid>;
extern template class FastSweeping<FloatGrid, Vec3s>;
extern template class FastSweeping<DoubleGrid>;
extern template class FastSweeping<DoubleGrid, Vec3d>;
extern template FloatGrid::Ptr fogToSdf(const FloatGrid&, float, int);
extern template DoubleGrid::Ptr fogToSdf(const DoubleGrid&, double, int);
extern template FloatGrid::Ptr sdfToSdf(const FloatGrid&, float, int);
extern template DoubleGrid::Ptr sdfToSdf(const DoubleGrid&, double, int);
extern template FloatGrid::Ptr dilateSdf(const FloatGrid&, int, NearestNeighbors, int,
                                         FastSweepingDomain);
extern template DoubleGrid::Ptr dilateSdf(const DoubleGrid&, int, NearestNeighbors, int,
                                          FastSweepingDomain);
extern template FloatGrid::Ptr maskSdf(const FloatGrid&, const MaskGrid&, bool, int);
extern template FloatGrid::Ptr maskSdf(const FloatGrid&, const BoolGrid&, bool, int);
extern template FloatGrid::Ptr maskSdf(const FloatGrid&, const FloatGrid&, bool, int);

}  // namespace vdb::tools
