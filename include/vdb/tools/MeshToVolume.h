// SPDX-License-Identifier: Apache-2.0
/// @file
/// Scan conversion of triangle and quad meshes into narrow-band level sets (paper section 4.5),
/// signed by counting surface crossings along scanlines and the hierarchical signed flood fill
/// (section 4.6), corrected near holes by generalized winding numbers, or left unsigned.
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
/// Signs. A voxel is inside when the generalized winding number of the mesh at its centre
/// (Jacobson et al. 2013) exceeds 1/2 in magnitude: 1 inside a closed mesh, 0 outside, 2 where
/// two closed parts overlap, and in between near the holes of an open one. It is computed
/// exactly, without evaluating the winding number at every voxel:
/// - The edges are analysed first. Points at the same position are welded (an STL file stores
///   each triangle's corners apart), each edge is matched with its faces, and, except in
///   WindingNumber mode, faces whose neighbours run the other way round their shared edge are
///   turned over, so that each connected piece keeps the orientation of most of its area.
/// - Along every z scanline of voxels, the crossings of the surface below a voxel are counted
///   with signs (+1 entering, -1 leaving, by the face's orientation; a line through a shared
///   edge or vertex counts once). For a closed mesh the count is the winding number itself.
/// - The edges left open (holes, leftover non-manifold or misoriented edges) form loops; each
///   loop is capped by a cone from its centre. Mesh minus cones is closed, so the winding
///   number of the mesh is the count along the scanlines (through mesh and cones) plus the
///   winding number of the cones, which is evaluated (hierarchically, Barill et al. 2018) only
///   in the leaves and tiles where a bound on it reaches 1/2: near the holes. Far from them,
///   and everywhere for flat holes, the count alone decides. Inactive tiles then take their
///   signs from the leaves (hierarchical flood fill) or, when the mesh has holes, each from the
///   count and winding number at its centre.
///
/// Modes (MeshSign):
/// - Auto (default): the analysis decides. A closed mesh (after orienting and welding) is
///   signed by FloodFill, any other by WindingNumber; MeshToVolumeReport says which and why.
///   Right for closed meshes, meshes with holes, non-manifold edges, duplicate points,
///   self-intersections and overlapping parts, and for faces turned the wrong way.
/// - FloodFill: the counts and the flood fill alone, with faces oriented as in Auto: inside
///   where the count is nonzero, or odd if the mesh is not closed (a hole then makes the
///   scanlines through it wrong). What Auto picks for closed meshes, bit for bit.
/// - WindingNumber: the generalized winding number of the mesh with its faces as given (no
///   turning): points far from holes are classified exactly, points near a hole get a
///   plausible side; faces turned the wrong way count against their neighbours.
/// - Unsigned: non-negative distances, every inactive value the background; no analysis.
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
/// evaluations, plus sorts of the points and of (block, triangle) pairs, two passes over the
/// edges, and one winding-number query per voxel of the leaves near large holes; memory: one
/// leaf per band leaf, the bucket lists, and 32 KB per block of 64^3 voxels the surface
/// passes through. Meshes up to 2^30 voxels from the origin work; coordinates are double.
///
/// @code
/// auto xform = vdb::math::Transform::createLinearTransform(0.01);
/// auto grid = vdb::tools::meshToLevelSet<vdb::FloatGrid>(*xform, points, triangles, quads);
///
/// vdb::tools::MeshToVolumeOptions options;
/// options.interiorBandWidth = 6.0f;
/// vdb::tools::MeshToVolumeReport report;
/// auto wide = vdb::tools::meshToVolume<vdb::FloatGrid>(*xform, points, triangles, {}, options,
///                                                      &report);
/// if (report.holes > 0) { /* signed by winding numbers: report.boundaryEdges open edges */ }
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>

#include <cstddef>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// How meshToVolume() decides which voxels are inside (see the file comment).
enum class MeshSign {
    Auto,           ///< FloodFill for closed meshes, WindingNumber for any other
    FloodFill,      ///< crossing counts and flood fill: closed meshes
    WindingNumber,  ///< generalized winding number of the faces as given: meshes with holes
    Unsigned,       ///< no sign: unsigned distances
};

/// Settings of meshToVolume(). Band widths are in voxels and must be at least 1.
struct MeshToVolumeOptions {
    float exteriorBandWidth = 3.0f;
    float interiorBandWidth = 3.0f;  ///< ignored for MeshSign::Unsigned
    MeshSign sign = MeshSign::Auto;
    bool threaded = true;
};

/// What meshToVolume() found in the mesh's edges and how it signed the result. Counts are of
/// the mesh as given (after welding), before any face was turned over; all are 0 for
/// MeshSign::Unsigned, which analyses nothing.
struct MeshToVolumeReport {
    MeshSign sign = MeshSign::Auto;  ///< the mode used: Auto resolves to FloodFill or WindingNumber
    size_t mergedPoints = 0;         ///< points at the position of an earlier point, welded
    size_t boundaryEdges = 0;        ///< edges of exactly one face
    size_t nonManifoldEdges = 0;     ///< edges of three or more faces
    size_t misorientedEdges = 0;     ///< edges of two faces that run the same way along them
    size_t flippedFaces = 0;         ///< faces turned over to agree with their neighbours
    size_t holes = 0;  ///< loops of edges left open that enclose an area; 0: the mesh is closed
};

/// Returns the narrow-band distance field of the mesh of `triangles` and `quads` over
/// `points` (world space), sampled with `xform`, as `options` say; fills `report` if given.
/// @throw ValueError when an index is out of range, a point is not finite or lies more than
///        2^30 voxels from the origin, a band width is below 1 or not finite, there are 2^31
///        triangles or more, or the transform is not linear with a uniform scale.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToVolume(const math::Transform& xform, const std::vector<Vec3s>& points,
                                 const std::vector<Vec3I>& triangles,
                                 const std::vector<Vec4I>& quads,
                                 const MeshToVolumeOptions& options = {},
                                 MeshToVolumeReport* report = nullptr);

/// Returns the narrow-band level set of a mesh: signed distances within `halfWidth` voxels on
/// both sides (MeshSign::Auto).
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToLevelSet(const math::Transform& xform, const std::vector<Vec3s>& points,
                                   const std::vector<Vec3I>& triangles,
                                   const std::vector<Vec4I>& quads, float halfWidth = 3.0f) {
    return meshToVolume<GridT>(xform, points, triangles, quads,
                               {halfWidth, halfWidth, MeshSign::Auto, true});
}

/// As above, for a mesh of triangles only.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToLevelSet(const math::Transform& xform, const std::vector<Vec3s>& points,
                                   const std::vector<Vec3I>& triangles, float halfWidth = 3.0f) {
    return meshToLevelSet<GridT>(xform, points, triangles, {}, halfWidth);
}

/// Signed distances of a mesh within `exBandWidth` voxels outside and `inBandWidth` voxels
/// inside (MeshSign::Auto).
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr meshToSignedDistanceField(const math::Transform& xform,
                                              const std::vector<Vec3s>& points,
                                              const std::vector<Vec3I>& triangles,
                                              const std::vector<Vec4I>& quads, float exBandWidth,
                                              float inBandWidth) {
    return meshToVolume<GridT>(xform, points, triangles, quads,
                               {exBandWidth, inBandWidth, MeshSign::Auto, true});
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

extern template FloatGrid::Ptr meshToVolume<FloatGrid>(
    const math::Transform&, const std::vector<Vec3s>&, const std::vector<Vec3I>&,
    const std::vector<Vec4I>&, const MeshToVolumeOptions&, MeshToVolumeReport*);
extern template DoubleGrid::Ptr meshToVolume<DoubleGrid>(
    const math::Transform&, const std::vector<Vec3s>&, const std::vector<Vec3I>&,
    const std::vector<Vec4I>&, const MeshToVolumeOptions&, MeshToVolumeReport*);

}  // namespace vdb::tools
