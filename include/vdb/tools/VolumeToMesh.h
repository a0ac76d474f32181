// SPDX-License-Identifier: Apache-2.0
/// @file
/// Polygon meshes of the isosurfaces of scalar grids: level sets, signed distance fields and
/// fog volumes at any isovalue, back to quads and triangles (the inverse of MeshToVolume.h).
///
/// The surface is contoured on the dual grid, as in dual contouring and surface nets: a cell
/// is the cube between eight neighbouring voxel centres, every cell whose corners lie on both
/// sides of the isovalue gets one vertex per sheet of surface that passes through it, and every
/// edge between two voxels of opposite sides becomes one quad joining the vertices of its four
/// cells. A vertex is the mean of the points where its sheet crosses the cell's edges (values
/// interpolated linearly along each edge, kept a thousandth of a voxel from the edge's ends so
/// that no two vertices coincide where values equal the isovalue), so it lies within the cell
/// and, on smooth surfaces, a few hundredths of a voxel from the surface. docs/VolumeToMesh.md
/// explains the algorithm.
///
/// Guarantees at adaptivity 0: the mesh of a closed surface is closed, two-manifold (every edge
/// in exactly two polygons, once in each direction) and consistently oriented, with no seam or
/// crack between leaves or between threads. Sheets that touch inside a cell are kept apart:
/// where a cell face is ambiguous (its diagonal corners agree), the bilinear interpolant on the
/// face decides whether the sheets join there; where a face would then make two cells share
/// one polygon edge four times, the face is resolved the other way.
///
/// Orientation: polygons wind clockwise seen from outside, so their right-hand normals point
/// inward and the signed volume they enclose is negative. This is OpenVDB's convention, kept so
/// that meshes drop in where OpenVDB's did; for level sets "inside" is below the isovalue, for
/// every other grid class (fog volumes, unknown) it is above. Mesh files wind the other way;
/// meshio::writeMesh() reverses the winding as it writes.
///
/// Adaptivity in (0, 1] merges flat regions into larger polygons: within each leaf, aligned
/// blocks of 2^3, 4^3, ... cells collapse to one vertex when every cell in them holds a single
/// sheet, the coarse cell's signs show the same single sheet as the fine cells (the
/// topological safety test of Ju et al., "Dual Contouring of Hermite Data", 2002, so that the
/// mesh stays closed and manifold) and the surface normals of the cells differ pairwise by at
/// most 1 - n_i.n_j <= adaptivity. The merged vertex is the mean of the cells' vertices moved
/// onto the interpolated surface. Quads between blocks of different sizes become triangles
/// where two of their corners merge. With `relaxDisorientedTriangles`, the vertices of triangles
/// that face against the surface normal move to the mean of their polygons' corners.
///
/// Values are read everywhere: voxels of leaves, tiles at every level and the background, active
/// or not, so a tile next to voxels is meshed as if it were voxels. Works on any tree
/// configuration. Cost: one pass over the leaves (each gathered once into a small dense array
/// with a layer of its neighbours), one over the tiles, and one over the surface cells; memory
/// about 30 bytes per surface cell. Threaded over leaves with oneTBB; the mesh is the same, bit
/// for bit, for every thread count.
///
/// @code
/// std::vector<vdb::Vec3s> points;
/// std::vector<vdb::Vec4I> quads;
/// vdb::tools::volumeToMesh(*grid, points, quads);  // world-space points, quads
///
/// std::vector<vdb::Vec3I> triangles;
/// vdb::tools::volumeToMesh(*grid, points, triangles, quads, /*isovalue=*/0.0,
///                          /*adaptivity=*/0.5);
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Vec3.h>

#include <string>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// A grid whose values volumeToMesh() can contour: a scalar number type other than bool.
template <typename GridT>
concept ScalarGrid = std::is_arithmetic_v<typename GridT::ValueType> &&
    !std::is_same_v<typename GridT::ValueType, bool>;

/// Meshes the isosurface of `grid` at `isovalue` with quads only (adaptivity 0). `points` are in
/// world space (the grid's transform); every quad indexes four distinct points. Both vectors are
/// replaced. See the file comment for placement, orientation and guarantees.
/// @throw ValueError when `isovalue` is not finite, a value next to the surface is NaN, or the
///        mesh would have 2^32 points or more.
template <ScalarGrid GridT>
void volumeToMesh(const GridT& grid, std::vector<Vec3s>& points, std::vector<Vec4I>& quads,
                  double isovalue = 0.0);

/// Meshes the isosurface of `grid` at `isovalue`, merging flat regions by `adaptivity` (0: one
/// vertex per surface cell, quads only; 1: the coarsest mesh the topology allows). Triangles
/// appear only where polygons of merged regions of different sizes meet.
/// @throw ValueError when `isovalue` is not finite, `adaptivity` is negative or not finite, a
///        value next to the surface is NaN, or the mesh would have 2^32 points or more.
template <ScalarGrid GridT>
void volumeToMesh(const GridT& grid, std::vector<Vec3s>& points, std::vector<Vec3I>& triangles,
                  std::vector<Vec4I>& quads, double isovalue = 0.0, double adaptivity = 0.0,
                  bool relaxDisorientedTriangles = true);

/// As above, for a grid whose type is known only at run time (a float or double grid).
/// @throw TypeError when `grid` is of another type (a vector, integer, bool or mask grid).
void volumeToMesh(const GridBase& grid, std::vector<Vec3s>& points, std::vector<Vec3I>& triangles,
                  std::vector<Vec4I>& quads, double isovalue = 0.0, double adaptivity = 0.0,
                  bool relaxDisorientedTriangles = true);

}  // namespace vdb::tools

#include <vdb/tools/detail/VolumeToMeshImpl.h>

// ---- Instantiated once in src/instantiate/VolumeToMesh.cpp

namespace vdb::tools {

extern template void volumeToMesh(const FloatGrid&, std::vector<Vec3s>&, std::vector<Vec3I>&,
                                  std::vector<Vec4I>&, double, double, bool);
extern template void volumeToMesh(const DoubleGrid&, std::vector<Vec3s>&, std::vector<Vec3I>&,
                                  std::vector<Vec4I>&, double, double, bool);
extern template void volumeToMesh(const FloatGrid&, std::vector<Vec3s>&, std::vector<Vec4I>&,
                                  double);
extern template void volumeToMesh(const DoubleGrid&, std::vector<Vec3s>&, std::vector<Vec4I>&,
                                  double);

}  // namespace vdb::tools
