// SPDX-License-Identifier: Apache-2.0
/// @file
/// Utilities on level sets and signed distance fields, with OpenVDB 10's names: conversion to
/// a fog volume, interior masks, enclosed regions, and the splitting of a grid into its
/// connected parts.
///
/// - sdfToFogVolume(grid, cutoff): the interior becomes density: values d <= 0 map to
///   d / -cutoff (a ramp from 0 at the surface to 1 at depth `cutoff`, and 1 deeper), the
///   interior tiles to active tiles of 1, everything outside to inactive 0 (the background).
///   The cutoff is clamped to the deepest value the grid holds, so a narrow band's ramp spans
///   its inside half. The grid becomes GRID_FOG_VOLUME.
/// - sdfInteriorMask(grid, iso): a bool grid, active and true where the value is below `iso`
///   (voxels, active or not, and tiles).
/// - extractEnclosedRegion(grid, iso, fillMask): the interior and the cavities it encloses:
///   everything except the exterior, the region of values >= iso connected (through face
///   neighbours within the leaves) to the tiles or background outside the leaves that hold
///   values >= iso. With `fillMask`, cavities not wholly inside the mask count as exterior.
/// - extractIsosurfaceMask(grid, iso): the active voxels with a face neighbour on the other
///   side of `iso`.
/// - extractActiveVoxelSegmentMasks(grid, masks): one bool grid per face-connected component
///   of the active voxels (active tiles included), largest first.
/// - segmentActiveVoxels(grid, segments): one grid per such component, holding its values.
/// - segmentSDF(grid, segments): one level set per connected surface: each component of the
///   isosurface voxels, grown through the band to every active voxel reached by moving away
///   from the surface (|phi| increasing), then flood filled.
///
/// Ties between components of equal size are broken by their first voxel's position, so the
/// order, like the results, does not depend on the thread count.
///
/// Cost: one or two passes over the leaves (in parallel), plus, for the enclosed region and the
/// segmentations, a flood over leaf-sized bit masks (serial, a few word operations per leaf
/// visit). The SDF segmentation's growth walks the band voxel by voxel.
///
/// @code
/// vdb::tools::sdfToFogVolume(*sdf);                      // sdf is now a density grid
/// auto inside = vdb::tools::sdfInteriorMask(*sdf);       // BoolGrid::Ptr
/// std::vector<vdb::FloatGrid::Ptr> parts;
/// vdb::tools::segmentSDF(*spheres, parts);               // one level set per sphere
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/Types.h>

#include <limits>
#include <vector>

namespace vdb::tools {

/// Turns a level set or signed distance field into a fog volume, in place.
template <typename GridT>
void sdfToFogVolume(GridT& grid, typename GridT::ValueType cutoffDistance =
                                     std::numeric_limits<typename GridT::ValueType>::max());

/// The region of `grid` below `isovalue`, as a bool grid with `grid`'s transform.
template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr sdfInteriorMask(
    const GridT& grid, typename GridT::ValueType isovalue = typename GridT::ValueType(0));

/// The interior of `grid` and the cavities it encloses, as a bool grid with `grid`'s
/// transform. `fillMask` (a bool tree in the grid's index space), when given, limits the
/// cavities to the ones it covers completely.
template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr extractEnclosedRegion(
    const GridT& grid, typename GridT::ValueType isovalue = typename GridT::ValueType(0),
    const typename GridT::TreeType::template ValueConverter<bool>::Type* fillMask = nullptr);

/// The active voxels of `grid` with a face neighbour on the other side of `isovalue`.
template <typename GridT>
typename GridT::template ValueConverter<bool>::Type::Ptr extractIsosurfaceMask(
    const GridT& grid, typename GridT::ValueType isovalue);

/// Appends to `masks` one bool grid per face-connected component of the active voxels and tiles
/// of `grid`, largest (most active voxels) first.
template <typename GridT>
void extractActiveVoxelSegmentMasks(
    const GridT& grid,
    std::vector<typename GridT::template ValueConverter<bool>::Type::Ptr>& masks);

/// Appends to `segments` one grid per face-connected component of the active voxels and tiles
/// of `grid`, holding that component's values (and `grid`'s transform and metadata), largest
/// first. A grid without active values gives one empty grid.
template <typename GridT>
void segmentActiveVoxels(const GridT& grid, std::vector<typename GridT::Ptr>& segments);

/// Appends to `segments` one narrow-band level set per connected surface of the level set
/// `grid`, largest (most surface voxels) first, each flood filled. A grid without a surface
/// gives one empty grid.
template <typename GridT>
void segmentSDF(const GridT& grid, std::vector<typename GridT::Ptr>& segments);

}  // namespace vdb::tools

// ---- Implementation ---------------------------------------------------------------------------

#include <vdb/tools/detail/LevelSetUtilImpl.h>

// ---- Instantiated once in src/instantiate/LevelSetUtil.cpp

namespace vdb::tools {

extern template void sdfToFogVolume(FloatGrid&, float);
extern template void sdfToFogVolume(DoubleGrid&, double);
extern template BoolGrid::Ptr sdfInteriorMask(const FloatGrid&, float);
extern template BoolGrid::Ptr extractEnclosedRegion(const FloatGrid&, float, const BoolTree*);
extern template BoolGrid::Ptr extractIsosurfaceMask(const FloatGrid&, float);
extern template void extractActiveVoxelSegmentMasks(const FloatGrid&, std::vector<BoolGrid::Ptr>&);
extern template void segmentActiveVoxels(const FloatGrid&, std::vector<FloatGrid::Ptr>&);
extern template void segmentSDF(const FloatGrid&, std::vector<FloatGrid::Ptr>&);

}  // namespace vdb::tools
