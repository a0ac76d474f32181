// SPDX-License-Identifier: Apache-2.0
/// @file
/// A clean narrow-band level set of the isosurface of any scalar grid: a fog volume at a
/// density, a signed distance field whose band was distorted by filtering or advection, or a
/// level set wanted at another voxel size or band width.
///
/// The surface at the isovalue is meshed (tools/VolumeToMesh.h, adaptivity 0: one vertex per
/// surface cell, closed and two-manifold) and the mesh is scan-converted again
/// (tools/MeshToVolume.h, signs by scanline parity and flood fill), so every band voxel of the
/// result holds the exact Euclidean distance to that mesh, which lies within a few hundredths
/// of a voxel of the input's surface on smooth shapes. Inside is below the isovalue for level
/// sets and above it for every other grid class (a fog volume's dense side), as volumeToMesh()
/// orients it; the result is a level set either way: negative inside, -inBandWidth to
/// +exBandWidth voxels times the voxel size over its band, the flood-filled band values beyond.
///
/// The result may be sampled with another linear transform. With a uniform scale its values are
/// Euclidean distances in world units. With unequal scales (or a shear) the mesh is mapped into
/// the transform's index space and the distances are measured there, times the transform's first
/// voxel size (voxelSize()[0]), as OpenVDB does: the zero crossing is the surface, the band is
/// -inBandWidth to +exBandWidth index units wide on either side, and values are world distances
/// only along directions in which one index unit is voxelSize()[0] long.
///
/// Cost: volumeToMesh() plus meshToVolume() on its quads; both threaded with oneTBB, and the
/// result is the same for every thread count. Overlapping closed surfaces of the input merge,
/// as the mesh's parity says.
///
/// @code
/// // A fog volume to a level set of the surface where its density is 0.5.
/// auto sdf = vdb::tools::levelSetRebuild(*fog, /*isovalue=*/0.5f);
/// // A level set resampled at a coarser voxel size.
/// auto coarse = vdb::math::Transform::createLinearTransform(2.0 * grid->voxelSize()[0]);
/// auto resampled = vdb::tools::levelSetRebuild(*grid, 0.0f, 3.0f, coarse.get());
/// @endcode

#pragma once

#include <vdb/Exceptions.h>
#include <vdb/Grid.h>
#include <vdb/math/Transform.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/VolumeToMesh.h>
#include <vdb/util/Parallel.h>

#include <cmath>
#include <type_traits>
#include <vector>

namespace vdb::tools {

/// Returns a new narrow-band level set of the surface of `grid` at `isovalue`, with
/// `exBandWidth` voxels of band outside and `inBandWidth` inside, sampled with `xform` (the
/// grid's own transform when null; it must be linear, and with unequal scales distances are
/// measured in its index space: see the file comment).
/// @throw ValueError when `isovalue` is not finite, a band width is below 1 voxel or not
///        finite, or the transform is not linear.
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr levelSetRebuild(const GridT& grid, float isovalue, float exBandWidth,
                                    float inBandWidth, const math::Transform* xform = nullptr);

/// As above, with a band of `halfWidth` voxels on both sides (OpenVDB's signature).
template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr levelSetRebuild(const GridT& grid, float isovalue = 0.0f,
                                    float halfWidth = 3.0f,
                                    const math::Transform* xform = nullptr) {
    return levelSetRebuild(grid, isovalue, halfWidth, halfWidth, xform);
}

// ---- Implementation ---------------------------------------------------------------------------

template <typename GridT>
requires std::is_floating_point_v<typename GridT::ValueType>
typename GridT::Ptr levelSetRebuild(const GridT& grid, float isovalue, float exBandWidth,
                                    float inBandWidth, const math::Transform* xform) {
    for (const float w : {exBandWidth, inBandWidth}) {
        if (!(w >= 1.0f) || !std::isfinite(w))
            throw ValueError("levelSetRebuild: band widths must be finite and at least 1 voxel");
    }
    const math::Transform& target = xform ? *xform : grid.transform();
    if (!target.isLinear())
        throw ValueError("levelSetRebuild: the transform must be linear (not a frustum)");
    std::vector<Vec3s> points;
    std::vector<Vec4I> quads;
    volumeToMesh(grid, points, quads, double(isovalue));
    MeshToVolumeOptions options;
    options.exteriorBandWidth = exBandWidth;
    options.interiorBandWidth = inBandWidth;
    options.sign = MeshSign::FloodFill;
    if (target.hasUniformScale())
        return meshToVolume<GridT>(target, points, {}, quads, options);
    // Unequal scales: the points go to the target's index space, scaled by its first voxel size,
    // and are scan-converted with that uniform voxel size, so the distances are those of index
    // space times voxelSize()[0]; the result then takes the target transform.
    const double voxelSize = target.voxelSize()[0];
    util::parallelFor(
        points.size(),
        [&](size_t i) { points[i] = Vec3s(target.worldToIndex(Vec3d(points[i])) * voxelSize); },
        true, 4096);
    auto result = meshToVolume<GridT>(*math::Transform::createLinearTransform(voxelSize), points,
                                      {}, quads, options);
    result->setTransform(target.copy());
    return result;
}

}  // namespace vdb::tools

// ---- Instantiated once in src/instantiate/LevelSetRebuild.cpp

namespace vdb::tools {

extern template FloatGrid::Ptr levelSetRebuild(const FloatGrid&, float, float, float,
                                               const math::Transform*);
extern template DoubleGrid::Ptr levelSetRebuild(const DoubleGrid&, float, float, float,
                                                const math::Transform*);

}  // namespace vdb::tools
