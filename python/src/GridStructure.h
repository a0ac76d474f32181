// SPDX-License-Identifier: Apache-2.0
/// @file
/// bindGridStructure<GridT>(): pyopenvdb's methods that describe a grid's tree structure
/// (nodeLog2Dims, getIndexRange, evalLeafBoundingBox, evalLeafDim). Included by
/// GridBinding.h.

#pragma once

#include <vdb/Grid.h>
#include <vdb/tree/NodeTraits.h>

#include "Common.h"

namespace vdb::python {

/// Appends the log2 edge of NodeT and of every node type below it (0 for a root, whose size
/// varies).
template <typename NodeT>
void appendLog2Dims(py::list& out) {
    if constexpr (tree::IS_ROOT_NODE<NodeT>)
        out.append(0);
    else
        out.append(NodeT::LOG2DIM);
    if constexpr (NodeT::LEVEL > 0)
        appendLog2Dims<typename NodeT::ChildNodeType>(out);
}

/// The box spanned by the top node's entries, as OpenVDB's Tree::getIndexRange: for a root,
/// from its smallest key to its largest key plus a child's edge minus one, the keys ordered
/// by (x, y, z) (so neither corner need be the componentwise extreme); (0, 0, 0) twice for a
/// root without entries.
template <typename TreeT>
std::pair<Coord, Coord> indexRange(const TreeT& tree) {
    using TopT = typename TreeT::TopNodeType;
    const TopT& top = tree.topNode();
    if constexpr (tree::IS_ROOT_NODE<TopT>) {
        Coord lo(0), hi(0);
        bool any = false;
        for (auto c = top.cbegin(); top.valid(c); top.next(c)) {
            const Coord& key = top.key(c);
            if (!any || key < lo)
                lo = key;
            if (!any || hi < key)
                hi = key;
            any = true;
        }
        if (any)
            hi = hi.offsetBy(Int32(TopT::ChildNodeType::DIM - 1));
        return {lo, hi};
    } else {
        const CoordBBox box = top.getNodeBoundingBox();
        return {box.min(), box.max()};
    }
}

/// The bounding box of the leaves that hold an active voxel and of the active tiles, as
/// OpenVDB's Tree::evalLeafBoundingBox. Each such leaf or tile spans whole leaf-aligned
/// blocks, and the extreme active voxel of each axis lies in the extreme block, so the box is
/// the active voxel box grown to leaf alignment; empty when there is no active value.
template <typename GridT>
CoordBBox leafBoundingBox(const GridT& grid) {
    constexpr Index LEAF_LOG2 = GridT::TreeType::LeafNodeType::LOG2DIM;
    const CoordBBox active = grid.evalActiveVoxelBoundingBox();
    if (active.empty())
        return active;
    return CoordBBox(active.min().alignedDown(LEAF_LOG2),
                     active.max().alignedDown(LEAF_LOG2).offsetBy(Int32((1u << LEAF_LOG2) - 1)));
}

template <typename GridT, typename ClassT>
void bindGridStructure(ClassT& cls) {
    cls.def(
        "nodeLog2Dims",
        [](const GridT&) {
            py::list dims;
            appendLog2Dims<typename GridT::TreeType::TopNodeType>(dims);
            return py::tuple(dims);
        },
        "nodeLog2Dims() -> tuple: the log2 edge (in children) of each node type from the root "
        "down to the leaf; 0 for the root, whose size varies: (0, 5, 4, 3).");
    cls.def(
        "getIndexRange", [](const GridT& g) { return indexRange(g.tree()); },
        "getIndexRange() -> (min, max): the coordinates the root's entries span (background "
        "included); the corners come from the first and last entry in (x, y, z) order, so "
        "the box may not hold every entry. ((0, 0, 0), (0, 0, 0)) for an empty root.");
    const auto leafBox = [](const GridT& g) {
        py::gil_scoped_release release;
        return leafBoundingBox(g);
    };
    cls.def(
        "evalLeafBoundingBox", [leafBox](const GridT& g) { return bboxCorners(leafBox(g)); },
        "evalLeafBoundingBox() -> (min, max): the corners of the bounding box of the leaves "
        "that hold an active voxel and of the active tiles ((2^31-1,)*3, (-2^31,)*3 when there "
        "are none).");
    cls.def(
        "evalLeafDim",
        [leafBox](const GridT& g) {
            const CoordBBox box = leafBox(g);
            return box.empty() ? Coord(0) : box.dim();
        },
        "evalLeafDim() -> (x, y, z): the dimensions of the evalLeafBoundingBox() box.");
}

}  // namespace vdb::python
