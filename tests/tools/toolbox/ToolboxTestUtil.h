// SPDX-License-Identifier: Apache-2.0
// Helpers of the toolbox tests: grids sampled from analytic fields voxel by voxel (not through
// the library's tools), narrow-band level sets of analytic signed distances, and brute-force
// walks over boxes of voxels.

#pragma once

#include <vdb/Grid.h>
#include <vdb/Types.h>
#include <vdb/math/Coord.h>
#include <vdb/math/Transform.h>
#include <vdb/math/Vec3.h>
#include <vdb/tools/SignedFloodFill.h>

#include "LevelSetTestUtil.h"

#include <cmath>
#include <functional>

namespace vdb::test {

/// Calls `f(ijk)` for every voxel of `box`.
template <typename FuncT>
void forEachVoxel(const CoordBBox& box, const FuncT& f) {
    for (Int32 i = box.min()[0]; i <= box.max()[0]; ++i)
        for (Int32 j = box.min()[1]; j <= box.max()[1]; ++j)
            for (Int32 k = box.min()[2]; k <= box.max()[2]; ++k)
                f(Coord(i, j, k));
}

/// A grid whose voxels in `box` are active and hold `field` at their world position (the
/// voxel centre under `xform`); background `background`.
template <typename GridT, typename FieldT>
typename GridT::Ptr sampleField(const CoordBBox& box, const math::Transform::Ptr& xform,
                                const FieldT& field, typename GridT::ValueType background = {}) {
    auto grid = GridT::create(background);
    grid->setTransform(xform);
    auto acc = grid->getAccessor();
    forEachVoxel(box, [&](const Coord& ijk) {
        acc.setValue(ijk, typename GridT::ValueType(field(xform->indexToWorld(ijk))));
    });
    return grid;
}

/// A narrow-band level set of the signed distance `sdf` (voxel units, negative inside) over
/// the index box `box`: every voxel closer than `halfWidth` voxels is active and holds the
/// distance in world units (voxel size `dx`); then flood filled.
inline FloatGrid::Ptr levelSetFromSdf(const Sdf& sdf, const CoordBBox& box, double dx,
                                      double halfWidth = 3.0) {
    auto grid = FloatGrid::create(float(halfWidth * dx));
    grid->setTransform(math::Transform::createLinearTransform(dx));
    grid->setGridClass(GRID_LEVEL_SET);
    auto acc = grid->getAccessor();
    forEachVoxel(box, [&](const Coord& ijk) {
        const double d = sdfAt(sdf, ijk);
        if (std::abs(d) < halfWidth)
            acc.setValue(ijk, float(d * dx));
    });
    tools::signedFloodFill(grid->tree());
    return grid;
}

}  // namespace vdb::test
