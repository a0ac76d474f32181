// SPDX-License-Identifier: Apache-2.0
/// @file
/// Scan conversion of triangle and quad meshes into narrow-band level sets (paper section 4.5),
/// with signs from a scanline flood fill and the hierarchical signed flood fill (section 4.6),
/// from generalized winding numbers for meshes with holes, or no signs at all.
///
/// Every voxel whose distance to the mesh is below the band width gets the exact Euclidean
/// distance to the closest point of the mesh (point-triangle distances in double precision, in
/// index space, times the voxel size). The work is organised leaf by leaf, as the paper
/// suggests: triangles are bucketed into blocks of 64^3 voxels, each block (one task) lists for
/// each of its leaves the triangles that can come within the band of it, and computes the
/// leaf's distances against those triangles only, touching for each triangle just the voxels
/// of its band. Leaves go into the tree in whatever order they are finished; blocks are
/// disjoint, so tasks never share a leaf (paper appendix B), and the grid is the same bit for
/// bit for every thread count.
///
/// Signs (MeshSign):
/// - FloodFill (default, closed meshes): along every z scanline of voxels the sign starts
///   outside below the mesh and flips at each crossing of the surface (a parity count that
///   counts a line through a shared edge or vertex exactly once, with no orientation needed);
///   inactive voxels and tiles beyond the band then take their signs from the hierarchical
///   signedFloodFill. Exact for closed meshes (watertight, any orientation); a hole makes the
///   scanlines through it wrong.
/// - WindingNumber (meshes with holes, consistently oriented): a voxel is inside when the
///   magnitude of the generalized winding number of the mesh at its centre exceeds 1/2
///   (Jacobson et al. 2013). The winding number is evaluated hierarchically (Barill et al.
///   2018): a bounding volume hierarchy over the triangles, whose far clusters count as dipoles
///   (area-weighted normal at the area-weighted centroid) and whose near triangles contribute
///   their exact solid angles. Points far from the holes are classified right; points near a
///   hole get a plausible side. Costs one hierarchy query per band voxel.
/// - Unsigned: non-negative distances, every inactive value the background.
///
/// Values are in world units (index-space distance times the voxel size). A voxel is active
/// when its distance is below the exterior band width (outside) or the interior band width
/// (inside); the background is exteriorBandWidth * voxelSize, and inactive values inside are
/// -interiorBandWidth * voxelSize. The grid class is level set (unknown for
/// unsigned distances).
///
/// Input: points in world space, mapped to index space by the transform (which must be linear
/// with a uniform scale; distances are measured in index space). Quads are split along their
/// (0, 2) diagonal; a quad whose fourth index is 0xFFFFFFFF is a triangle. Degenerate
/// triangles (repeated or collinear vertices) are allowed: they count by their edges.
///
/// Cost: about (triangle area + band volume of each triangle) voxel-triangle distance
/// evaluations, plus a sort of (block, triangle) pairs; memory: one leaf per band leaf plus
/// the bucket lists. Meshes up to 2^30 voxels from the origin work; coordinates are double.
///
/// @code
/// auto xform = vdb::math::Transform::createLinearTransform(0.01);
/// auto grid = vdb::tools::meshToLevelSet<vdb::FloatGrid>(*xform, points, triangles, quads);
///
/// vdb::tools::MeshToVolumeOptions options;
/// options.sign = vdb::tools::MeshSign::WindingNumber;  // the mesh has holes
/// options.interiorBandWidth = 6.0f;
/// auto open = vdb::tools::meshToVolume<vdb::FloatGrid>(*xform, points, triangles, {}, options);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>

#include <type_traits>
#include <vector>

namespace vdb::tools {

/// How meshToVolume() decides which voxels are inside (see the file comment).
enum class MeshSign {
    FloodFill,      ///< scanline parity + hierarchical flood fill: closed meshes
    WindingNumber,  ///< generalized winding number: meshes with holes
    Unsigned,       ///< no sign: unsigned distances
};

/// Settings of meshToVolume(). Band widths are in voxels and must be at least 1.
struct MeshToVolumeOptions {
    float exteriorBandWidth = 3.0f;
    float interiorBandWidth = 3.0f;  ///< ignored for MeshSign::Unsigned
    MeshSign sign = MeshSign::FloodFill;
    bool threaded = true;
};

/// Returns the narrow-band distance field of the mesh of `triangles` and `quads` over
/// `points` (world space), sampled with `xform`, as `options` say.
/// @throw ValueError when an index is out of range, a point is not finite or lies more than
///        2^30 voxels from the origin, a band width is below 1 or not finite, or the transform
///        is not linear with a uniform scale.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToVolume(const math::Transform& xform, const std::vector<Vec3s>& points,
                                 const std::vector<Vec3I>& triangles,
                                 const std::vector<Vec4I>& quads,
                                 const MeshToVolumeOptions& options = {});

/// Returns the narrow-band level set of a closed mesh: signed distances within `halfWidth`
/// voxels on both sides (MeshSign::FloodFill).
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToLevelSet(const math::Transform& xform, const std::vector<Vec3s>& points,
                                   const std::vector<Vec3I>& triangles,
                                   const std::vector<Vec4I>& quads, float halfWidth = 3.0f) {
    return meshToVolume<GridT>(xform, points, triangles, quads,
                               {halfWidth, halfWidth, MeshSign::FloodFill, true});
}

/// As above, for a mesh of triangles only.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToLevelSet(const math::Transform& xform, const std::vector<Vec3s>& points,
                                   const std::vector<Vec3I>& triangles, float halfWidth = 3.0f) {
    return meshToLevelSet<GridT>(xform, points, triangles, {}, halfWidth);
}

/// Signed distances of a closed mesh within `exBandWidth` voxels outside and `inBandWidth`
/// voxels inside.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToSignedDistanceField(const math::Transform& xform,
                                              const std::vector<Vec3s>& points,
                                              const std::vector<Vec3I>& triangles,
                                              const std::vector<Vec4I>& quads, float exBandWidth,
                                              float inBandWidth) {
    return meshToVolume<GridT>(xform, points, triangles, quads,
                               {exBandWidth, inBandWidth, MeshSign::FloodFill, true});
}

/// Unsigned distances within `bandWidth` voxels of the mesh (MeshSign::Unsigned).
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToUnsignedDistanceField(const math::Transform& xform,
                                                const std::vector<Vec3s>& points,
                                                const std::vector<Vec3I>& triangles,
                                                const std::vector<Vec4I>& quads, float bandWidth) {
    return meshToVolume<GridT>(xform, points, triangles, quads,
                               {bandWidth, bandWidth, MeshSign::Unsigned, true});
}

}  // namespace vdb::tools

#include <vdb/tools/detail/MeshToVolumeImpl.h>

// ---- Instantiated once in src/instantiate/MeshToVolume.cpp

namespace vdb::tools {

extern template FloatGrid::Ptr meshToVolume<FloatGrid>(const math::Transform&,
                                                       const std::vector<Vec3s>&,
                                                       const std::vector<Vec3I>&,
                                                       const std::vector<Vec4I>&,
                                                       const MeshToVolumeOptions&);
extern template DoubleGrid::Ptr meshToVolume<DoubleGrid>(const math::Transform&,
                                                         const std::vector<Vec3s>&,
                                                         const std::vector<Vec3I>&,
                                                         const std::vector<Vec4I>&,
                                                         const MeshToVolumeOptions&);

}  // namespace vdb::tools
