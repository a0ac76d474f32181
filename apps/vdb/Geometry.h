// SPDX-License-Identifier: Apache-2.0
/// @file
/// Geometry to level sets for the `mesh`, `spheres` and `demo` subcommands: each conversion
/// runs as a timed report step after a memory check.

#pragma once

#include <vdb/meshio/MeshReader.h>
#include <vdb/tools/MeshToVolume.h>
#include <vdb/tools/ParticlesToLevelSet.h>

#include "Cli.h"

#include <string>

namespace vdb::app {

/// The smallest radius, in voxels, of a sphere the level set rasterizers draw
/// (tools::createLevelSetSphere, tools::ParticlesToLevelSet's default getRmin()).
inline constexpr double kMinSphereVoxels = 1.5;

/// The summary of a mesh, the one every command reports: the line "  N points, T triangles,
/// Q quads" and the keys points, triangles and quads in the JSON object open in `report.json()`.
void reportMesh(Report& report, const meshio::Mesh& mesh);

/// The world-space bounding box of the mesh's points.
BBoxd meshBounds(const meshio::Mesh& mesh);

/// A level set of `mesh` (signed as `sign` says) with voxels of `voxelSize` and a band of
/// 2 * halfWidth voxels, converted as the report step "scan-convert N faces"; `found`, if
/// given, receives what the converter found in the mesh's edges and the sign mode it used.
FloatGrid::Ptr meshToGrid(Report& report, const meshio::Mesh& mesh, double voxelSize,
                          float halfWidth, tools::MeshSign sign,
                          tools::MeshToVolumeReport* found = nullptr);

/// A level set of the union of `spheres` with voxels of `voxelSize` and a band of
/// 2 * halfWidth voxels, as the report step "rasterize N spheres"; notes how many spheres
/// were too small for the voxels.
FloatGrid::Ptr spheresToGrid(Report& report, const tools::SphereList& spheres, double voxelSize,
                             float halfWidth);

}  // namespace vdb::app
