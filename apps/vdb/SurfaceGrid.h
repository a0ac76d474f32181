// SPDX-License-Identifier: Apache-2.0
/// @file
/// What the `tomesh` and `rebuild` subcommands share: choosing the grid whose isosurface they
/// take, and the isovalue it is taken at by default.

#pragma once

#include "Cli.h"

#include <optional>
#include <string>

namespace vdb::app {

/// The grid named `name` of `grids` read from `path`, or without a name the first float or
/// double level set, else the first float or double grid. Throws UsageError naming the file
/// when there is none, or when the named grid is not a float or double grid.
GridBase::Ptr pickSurfaceGrid(const GridPtrVec& grids, const std::string& name,
                              const std::string& path);

/// `isovalue` when given, else the surface's usual value for the grid's class: 0 for level
/// sets and grids of unknown class, 0.5 for fog volumes (densities from 0 to 1).
double isovalueFor(const GridBase& grid, const std::optional<double>& isovalue);

/// Throws UsageError when the isosurface of `grid`, taken as float mesh points in world space
/// (tools::volumeToMesh, and through it tools::levelSetRebuild), lies where floats are too
/// coarse for the grid's voxels or for `voxelSize` (checkFloatPrecision).
void checkSurfacePrecision(const GridBase& grid, double voxelSize);

}  // namespace vdb::app
