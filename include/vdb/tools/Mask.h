// SPDX-License-Identifier: Apache-2.0
/// @file
/// interiorMask(): a bool grid marking the "inside" of any grid, as OpenVDB 10's
/// tools::interiorMask builds it.
///
/// - A floating-point grid of class GRID_LEVEL_SET: its interior, sdfInteriorMask(grid, iso)
///   (tools/LevelSetUtil.h): active and true wherever the level set's value is below `iso`,
///   including the enclosed inside tiles.
/// - A bool grid: a deep copy of it.
/// - Any other grid (fog volumes included): its active topology, every active voxel and tile
///   active, with the value false (a topology union into an empty bool grid, as OpenVDB
///   builds it; the active states are the mask). The isovalue is not used (OpenVDB ignores it too);
///   call tools::extractIsosurfaceMask or threshold a fog volume with activate()/deactivate() for
///   an iso-dependent mask.
/// The mask gets a copy of the grid's transform.
///
/// Cost: that of sdfInteriorMask for level sets, otherwise one topology union (masks only).
///
/// @code
/// vdb::BoolGrid::Ptr inside = vdb::tools::interiorMask(*sdf);      // level set: its inside
/// vdb::BoolGrid::Ptr support = vdb::tools::interiorMask(*density); // fog: its active voxels
/// @endcode

#pragma once

#include <vdb/Grid.h>
#include <vdb/tools/LevelSetUtil.h>
#include <vdb/tools/detail/NodeLists.h>

#include <type_traits>

namespace vdb::tools {

/// Returns a new bool grid of the interior of `grid` (see the file comment).
template <VdbTree TreeT>
typename Grid<TreeT>::template ValueConverter<bool>::Type::Ptr interiorMask(const Grid<TreeT>& grid,
                                                                            double isovalue = 0.0);

// ---- Implementation ---------------------------------------------------------------------------

template <VdbTree TreeT>
typename Grid<TreeT>::template ValueConverter<bool>::Type::Ptr interiorMask(const Grid<TreeT>& grid,
                                                                            double isovalue) {
    using ValueT = typename TreeT::ValueType;
    using BoolGridT = typename Grid<TreeT>::template ValueConverter<bool>::Type;
    if constexpr (std::is_same_v<ValueT, bool> && std::is_same_v<BoolGridT, Grid<TreeT>>) {
        return grid.deepCopy();
    } else {
        if constexpr (std::is_floating_point_v<ValueT>) {
            if (grid.getGridClass() == GRID_LEVEL_SET)
                return sdfInteriorMask(grid, static_cast<ValueT>(isovalue));
        }
        auto mask = BoolGridT::create(false);
        mask->setTransform(grid.transform().copy());
        mask->tree().topologyUnion(grid.tree());
        return mask;
    }
}

}  // namespace vdb::tools
