// SPDX-License-Identifier: Apache-2.0
/// @file
/// Differential and pointwise operators on grids, with OpenVDB 10's names and meanings:
/// gradient, divergence, curl, Laplacian and mean curvature (second-order central differences,
/// paper 3.4), and the magnitude and normalisation of vectors. Each returns a new grid with the
/// input's active topology (intersected with an optional mask's) and transform.
///
/// - Derivatives are in world units: the index-space differences are mapped through the
///   transform's inverse Jacobian (a division by the voxel size for uniform scale, per axis
///   for non-uniform scale, the full inverse-transpose for affine maps). Translations do not
///   matter. Frustum transforms are not supported (ValueError).
/// - Active tiles are first expanded into leaves for the differential operators (a constant
///   tile has derivatives only along its border), and the result is pruned (tolerance 0);
///   magnitude() and normalize() keep tiles as tiles.
/// - The output's background is the operator applied to a grid holding only the input's
///   background (0 for the derivatives); every inactive value is that background.
/// - A vector grid of class GRID_STAGGERED (a MAC grid: component a of voxel i sits on the face
///   at i - 1/2 along a) has its divergence taken with forward differences.
/// - The mask is read by index coordinates, whatever its transform: only voxels active in both
///   the input and the mask are computed (and active) in the output.
/// - gradient() and curl() mark their output VEC_COVARIANT, as do laplacian() and
///   meanCurvature() (as OpenVDB does, though their values are scalars); normalize() turns
///   VEC_COVARIANT into VEC_COVARIANT_NORMALIZE and keeps any other vector type.
///
/// Cost: one pass over the active leaves, each gathering its neighbourhood into a dense block
/// (six face neighbours, or all 26 for the mixed derivatives of curvature and of Laplacians
/// under affine maps) and evaluating the operator at its active voxels by array reads.
/// Threads: parallel over leaves; the result is the same for any thread count.
///
/// @code
/// auto normals = vdb::tools::gradient(*sdf);        // Vec3SGrid, |n| = 1 on a level set
/// auto div = vdb::tools::divergence(*velocity);     // FloatGrid
/// auto curv = vdb::tools::meanCurvature(*sdf);      // 1/R near a sphere of radius R
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Vec3.h>

#include <type_traits>

namespace vdb::tools {

/// The grid type of the same tree configuration whose values are the components of
/// VectorGridT's vectors (Vec3SGrid to FloatGrid).
template <typename VectorGridT>
struct VectorToScalarConverter {
    using Type = typename VectorGridT::template ValueConverter<
        typename VectorGridT::ValueType::value_type>::Type;
};
/// The grid type of the same tree configuration whose values are vectors of ScalarGridT's
/// values (FloatGrid to Vec3SGrid).
template <typename ScalarGridT>
struct ScalarToVectorConverter {
    using Type = typename ScalarGridT::template ValueConverter<
        math::Vec3<typename ScalarGridT::ValueType>>::Type;
};

/// A grid of floating-point scalars (the input of gradient, laplacian, meanCurvature).
template <typename GridT>
concept ScalarGridType = std::is_floating_point_v<typename GridT::ValueType>;
/// A grid of floating-point 3-vectors (the input of divergence, curl, magnitude, normalize).
template <typename GridT>
concept VectorGridType = requires {
    typename GridT::ValueType::value_type;
}
&&std::is_floating_point_v<typename GridT::ValueType::value_type>;

/// A grid whose active topology serves as a mask (any value type).
template <typename GridT>
concept MaskGridLike = requires(const GridT& grid) {
    grid.tree().cbeginLeaf();
    grid.transform();
};

/// The gradient of a scalar grid, in world units.
/// @throw ValueError for a frustum transform.
template <ScalarGridType GridT>
typename ScalarToVectorConverter<GridT>::Type::Ptr gradient(const GridT& grid,
                                                            bool threaded = true);
/// The gradient where both `grid` and `mask` are active.
template <ScalarGridType GridT, MaskGridLike MaskT>
typename ScalarToVectorConverter<GridT>::Type::Ptr gradient(const GridT& grid, const MaskT& mask,
                                                            bool threaded = true);

/// The divergence of a vector grid, in world units (forward differences for GRID_STAGGERED).
template <VectorGridType GridT>
typename VectorToScalarConverter<GridT>::Type::Ptr divergence(const GridT& grid,
                                                              bool threaded = true);
template <VectorGridType GridT, MaskGridLike MaskT>
typename VectorToScalarConverter<GridT>::Type::Ptr divergence(const GridT& grid, const MaskT& mask,
                                                              bool threaded = true);

/// The curl of a vector grid, in world units.
template <VectorGridType GridT>
typename GridT::Ptr curl(const GridT& grid, bool threaded = true);
template <VectorGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr curl(const GridT& grid, const MaskT& mask, bool threaded = true);

/// The Laplacian of a scalar grid, in world units.
template <ScalarGridType GridT>
typename GridT::Ptr laplacian(const GridT& grid, bool threaded = true);
template <ScalarGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr laplacian(const GridT& grid, const MaskT& mask, bool threaded = true);

/// The mean curvature H = div(grad phi / |grad phi|) / 2 of the level sets of a scalar grid,
/// in world units (1/R near a sphere of radius R); 0 where the gradient vanishes.
template <ScalarGridType GridT>
typename GridT::Ptr meanCurvature(const GridT& grid, bool threaded = true);
template <ScalarGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr meanCurvature(const GridT& grid, const MaskT& mask, bool threaded = true);

/// The length of every vector of a vector grid.
template <VectorGridType GridT>
typename VectorToScalarConverter<GridT>::Type::Ptr magnitude(const GridT& grid,
                                                             bool threaded = true);
template <VectorGridType GridT, MaskGridLike MaskT>
typename VectorToScalarConverter<GridT>::Type::Ptr magnitude(const GridT& grid, const MaskT& mask,
                                                             bool threaded = true);

/// Every vector of a vector grid scaled to unit length (zero vectors stay zero).
template <VectorGridType GridT>
typename GridT::Ptr normalize(const GridT& grid, bool threaded = true);
template <VectorGridType GridT, MaskGridLike MaskT>
typename GridT::Ptr normalize(const GridT& grid, const MaskT& mask, bool threaded = true);

}  // namespace vdb::tools

// ---- Implementation ---------------------------------------------------------------------------

#include <vdb/tools/detail/GridOperatorsImpl.h>

// ---- Instantiated once in src/instantiate/GridOperators.cpp

namespace vdb::tools {

extern template Vec3SGrid::Ptr gradient(const FloatGrid&, bool);
extern template Vec3DGrid::Ptr gradient(const DoubleGrid&, bool);
extern template Vec3SGrid::Ptr gradient(const FloatGrid&, const MaskGrid&, bool);
extern template FloatGrid::Ptr divergence(const Vec3SGrid&, bool);
extern template DoubleGrid::Ptr divergence(const Vec3DGrid&, bool);
extern template FloatGrid::Ptr divergence(const Vec3SGrid&, const MaskGrid&, bool);
extern template Vec3SGrid::Ptr curl(const Vec3SGrid&, bool);
extern template Vec3DGrid::Ptr curl(const Vec3DGrid&, bool);
extern template Vec3SGrid::Ptr curl(const Vec3SGrid&, const MaskGrid&, bool);
extern template FloatGrid::Ptr laplacian(const FloatGrid&, bool);
extern template DoubleGrid::Ptr laplacian(const DoubleGrid&, bool);
extern template FloatGrid::Ptr laplacian(const FloatGrid&, const MaskGrid&, bool);
extern template FloatGrid::Ptr meanCurvature(const FloatGrid&, bool);
extern template DoubleGrid::Ptr meanCurvature(const DoubleGrid&, bool);
extern template FloatGrid::Ptr meanCurvature(const FloatGrid&, const MaskGrid&, bool);
extern template FloatGrid::Ptr magnitude(const Vec3SGrid&, bool);
extern template DoubleGrid::Ptr magnitude(const Vec3DGrid&, bool);
extern template FloatGrid::Ptr magnitude(const Vec3SGrid&, const MaskGrid&, bool);
extern template Vec3SGrid::Ptr normalize(const Vec3SGrid&, bool);
extern template Vec3DGrid::Ptr normalize(const Vec3DGrid&, bool);
extern template Vec3SGrid::Ptr normalize(const Vec3SGrid&, const MaskGrid&, bool);

}  // namespace vdb::tools
