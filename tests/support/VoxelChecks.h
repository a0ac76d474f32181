// SPDX-License-Identifier: Apache-2.0
/// @file
/// Test support: writing the same voxels and boxes into a tree and its oracle, and checking every
/// voxel of a box of a tree against an oracle, tiles included (a tile is checked through each
/// voxel it covers).

#pragma once

#include <vdb/math/Coord.h>
#include <vdb/tree/ValueAccessor.h>

#include <gtest/gtest.h>

namespace vdb::test {

/// Writes `value` at `ijk` into both `tree` and `model` (an oracle of tests/support/Oracles.h),
/// active or inactive.
template <typename TreeT, typename ModelT, typename ValueT>
void setBoth(TreeT& tree, ModelT& model, const Coord& ijk, const ValueT& value, bool active) {
    if (active) {
        tree.setValueOn(ijk, value);
        model.setValueOn(ijk, value);
    } else {
        tree.setValueOff(ijk, value);
        model.setValueOff(ijk, value);
    }
}

/// Fills `box` of both `tree` and `model` with `value`, active or inactive.
template <typename TreeT, typename ModelT, typename ValueT>
void fillBoth(TreeT& tree, ModelT& model, const CoordBBox& box, const ValueT& value, bool active) {
    tree.fill(box, value, active);
    model.fill(box, value, active);
}

/// Expects every voxel ijk of `region` of `tree` to read as expect(ijk) = {value, active}
/// (values compared with ==); reports the first few that do not.
template <typename TreeT, typename ExpectT>
void expectVoxels(const TreeT& tree, const CoordBBox& region, const ExpectT& expect) {
    tree::ValueAccessor<const TreeT> acc(tree);
    int failures = 0;
    for (Int32 x = region.min()[0]; x <= region.max()[0]; ++x) {
        for (Int32 y = region.min()[1]; y <= region.max()[1]; ++y) {
            for (Int32 z = region.min()[2]; z <= region.max()[2]; ++z) {
                const Coord ijk(x, y, z);
                const auto [value, active] = expect(ijk);
                if (!(acc.getValue(ijk) == value) || acc.isValueOn(ijk) != active) {
                    ADD_FAILURE() << "at " << ijk << ": got " << acc.getValue(ijk) << "/"
                                  << acc.isValueOn(ijk) << ", expected " << value << "/" << active;
                    if (++failures > 5)
                        return;
                }
            }
        }
    }
}

}  // namespace vdb::test
